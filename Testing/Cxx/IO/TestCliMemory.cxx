// SPDX-License-Identifier: BSD-3-Clause
// The tool's allocation policy (KeepFreedMemoryForReuse): a large array freed and allocated again
// is served from memory that is already faulted in. Measured by the process's minor page faults
// (kernel work, not time): by default glibc maps every block above 32 MB afresh, so every pass of
// a filter that rebuilds a 48 MB array (a 4M-triangle surface's triangles) faults it in again.
#include "CliSupport.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <memory>

#include <sys/resource.h>

namespace
{
long MinorPageFaults()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Allocates `bytes`, writes every byte and frees them; returns the minor page faults this took.
long FaultsOfArray(std::size_t bytes)
{
  const long before = MinorPageFaults();
  {
    std::unique_ptr<char[]> block(new char[bytes]);
    std::memset(block.get(), 1, bytes);
    asm volatile("" : : "r"(block.get()) : "memory"); // the writes happen
  }
  return MinorPageFaults() - before;
}
} // namespace

TEST(CliMemory, LargeArraysFreedAreReusedWithoutFaultingAgain)
{
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the policy applies to glibc's allocator only";
#endif
  if (std::getenv("GLIBC_TUNABLES") != nullptr)
  {
    GTEST_SKIP() << "GLIBC_TUNABLES is set: the user's allocator settings apply, not the tool's";
  }
  slodcli::KeepFreedMemoryForReuse();
  constexpr std::size_t bytes = std::size_t(64) << 20; // above glibc's largest mmap threshold
  const long pages = static_cast<long>(bytes / 4096);
  FaultsOfArray(bytes); // the first use faults the pages in
  const long again = FaultsOfArray(bytes) + FaultsOfArray(bytes);
  EXPECT_LT(again, pages / 16) << "two more 64 MB arrays faulted " << again << " pages in (" << pages
                               << " pages each)";
}
