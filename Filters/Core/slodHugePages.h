// SPDX-License-Identifier: BSD-3-Clause
#ifndef slodHugePages_h
#define slodHugePages_h

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace slod
{
// Transparent huge pages for the large working arrays (session 29). The collapse loop reads its
// arrays (quadrics, per-triangle states, the mesh, the queue) at random places: with 4 KiB pages
// nearly every read misses the TLB, and every page of a set-up array costs a page fault at its
// first touch (72,000 on mc1m). Backed by 2 MiB pages the same process took 10-15 % less CPU
// (glibc.malloc.hugetlb=1, sessions 28-29). Only the kernel's placement changes: contents, and so
// the outputs, are the same.
constexpr std::size_t HugePageBytes = std::size_t(2) << 20;

// Advises the kernel to back [data, data + bytes) by huge pages (MADV_HUGEPAGE on the 4 KiB pages
// that hold the range). The kernel then backs each 2 MiB-aligned part of the advised mapping by a
// huge page at its first touch, where transparent huge pages are enabled ("madvise" or "always");
// elsewhere, and off Linux, it does nothing. Returns whether advice was given.
inline bool AdviseHugePages(const void* data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t page = 4096;
  const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = begin & ~(page - 1);
  const std::uintptr_t last = (begin + bytes + page - 1) & ~(page - 1);
  if (data == nullptr || bytes < HugePageBytes)
  {
    return false;
  }
  return madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE) == 0;
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

// A capacity of at least n elements whose block fills whole huge pages: a block that large is
// mapped on its own (glibc's malloc: the request, its 16-byte header, rounded up to 4 KiB), and
// Linux (6.7 and later) places a mapping whose length is a multiple of 2 MiB on a 2 MiB boundary,
// so that every page of the array can be a huge page instead of its aligned interior only.
template <typename T>
std::size_t HugePageCapacity(std::size_t n)
{
  constexpr std::size_t slack = 64; // more than any allocator header, less than a 4 KiB page
  const std::size_t pages = (n * sizeof(T) + slack + HugePageBytes - 1) / HugePageBytes;
  return std::max(n, (pages * HugePageBytes - slack) / sizeof(T));
}

// As v.reserve(n) (the contents kept), with new storage advised for huge pages before anything
// is written to it. Arrays of less than two huge pages are reserved as usual.
template <typename T, typename A>
void ReserveOnHugePages(std::vector<T, A>& v, std::size_t n)
{
  if (v.capacity() >= n)
  {
    return;
  }
  if (n * sizeof(T) < 2 * HugePageBytes)
  {
    v.reserve(n);
    return;
  }
  std::vector<T, A> fresh(v.get_allocator());
  fresh.reserve(HugePageCapacity<T>(n));
  AdviseHugePages(fresh.data(), fresh.capacity() * sizeof(T));
  fresh.insert(fresh.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  v.swap(fresh);
}

// v.assign(n, value) into storage advised for huge pages (the old contents are dropped first,
// not copied).
template <typename T, typename A>
void AssignOnHugePages(std::vector<T, A>& v, std::size_t n, const T& value)
{
  if (v.capacity() < n)
  {
    std::vector<T, A>(v.get_allocator()).swap(v);
  }
  ReserveOnHugePages(v, n);
  v.assign(n, value);
}

// A vector of n copies of value, in storage advised for huge pages (see AssignOnHugePages).
template <typename T>
std::vector<T> MakeOnHugePages(std::size_t n, const T& value = T())
{
  std::vector<T> v;
  AssignOnHugePages(v, n, value);
  return v;
}

// v = source, into storage advised for huge pages.
template <typename T, typename A>
void CopyOnHugePages(std::vector<T, A>& v, const std::vector<T, A>& source)
{
  if (v.capacity() < source.size())
  {
    std::vector<T, A>(v.get_allocator()).swap(v);
  }
  ReserveOnHugePages(v, source.size());
  v.assign(source.begin(), source.end());
}
}

#endif
