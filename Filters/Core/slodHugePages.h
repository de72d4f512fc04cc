// SPDX-License-Identifier: BSD-3-Clause
#ifndef slodHugePages_h
#define slodHugePages_h

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace slod
{
// Transparent huge pages for the large working arrays (session 29). Each 4 KiB page of an array
// costs a page fault at its first touch (72,000 on mc1m for the whole triangle collapse); backed
// by 2 MiB pages the set-up stages around the collapse loop took about a quarter less CPU on mc1m
// and the MRI. Only the kernel's placement changes: contents, and so the outputs, are the same,
// and the resident memory too (only the whole huge pages inside an array are advised).
constexpr std::size_t HugePageBytes = std::size_t(2) << 20;

// Advises the kernel to back the whole 2 MiB pages inside [data, data + bytes) by huge pages
// (MADV_HUGEPAGE; the unaligned head and tail stay in 4 KiB pages, so that no page beyond the
// array's own is made resident). It takes effect for the pages touched after the call, where
// transparent huge pages are enabled ("madvise" or "always"); elsewhere, and off Linux, it does
// nothing. Returns whether advice was given (false also when the range holds no whole huge page).
inline bool AdviseHugePages(const void* data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + HugePageBytes - 1) & ~std::uintptr_t(HugePageBytes - 1);
  const std::uintptr_t last = (begin + bytes) & ~std::uintptr_t(HugePageBytes - 1);
  if (data == nullptr || last <= first)
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
  fresh.reserve(n);
  AdviseHugePages(fresh.data(), n * sizeof(T));
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
