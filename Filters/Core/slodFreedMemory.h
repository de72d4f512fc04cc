// SPDX-License-Identifier: BSD-3-Clause
#ifndef slodFreedMemory_h
#define slodFreedMemory_h

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace slod
{
// Gives the pages of freed blocks back to the system. glibc serves blocks below its adaptive mmap
// threshold (up to 32 MB, raised by every larger block freed) from the heap, where a freed block
// stays resident until it is reused: arrays released by a set-up or a compaction would otherwise
// still count in a peak reached later (the triangle collapse's start on mc1m: 11 MB, 22 bytes per
// vertex).
inline void ReturnFreedMemory()
{
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}
} // namespace slod

#endif
