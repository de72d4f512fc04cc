// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: an addressable min-priority queue of non-negative float costs with
// O(1) insert, remove and update, for collapse algorithms on large meshes.
//
// Why not a binary heap: after every collapse a dozen costs change, and each sift in a heap of a
// million entries is ~20 levels of cache misses; that dominated the run time. Here the float's
// bit pattern (monotone for non-negative floats) picks one of 2^15 buckets (128 per octave, so a
// bucket spans < 0.6 % of relative cost); a bucket is a contiguous array of {key, id}. Pop scans
// the lowest non-empty bucket for its exact minimum (ties: smallest id), so the order is the same
// as a heap's; only buckets larger than ScanLimit (typically exact ties such as the zero costs of
// planar regions) are served from the back without a scan. Deterministic.
#ifndef slodBucketQueue_h
#define slodBucketQueue_h

#include "slodHugePages.h"
#include "slodTriangleMesh.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace slod
{
class BucketQueue
{
public:
  static constexpr int BucketBits = 15;
  static constexpr Index ScanLimit = 512;

  void Reset(Index n)
  {
    AssignOnHugePages(this->Slot, size_t(n), InvalidIndex);
    AssignOnHugePages(this->BucketId, size_t(n), std::uint16_t(0));
    this->Buckets.assign(size_t(1) << BucketBits, {});
    this->Lowest = static_cast<Index>(this->Buckets.size());
    this->Count = 0;
  }

  // Reset(n) then Set(id, keys[id]) for every id in order, with each bucket allocated once at its
  // size (no growth by doubling: faster and no slack memory).
  void Build(const float* keys, Index n)
  {
    this->Reset(n);
    std::vector<Index> sizes(this->Buckets.size(), 0);
    for (Index id = 0; id < n; ++id)
    {
      ++sizes[BucketOf(keys[id])];
    }
    for (size_t b = 0; b < sizes.size(); ++b)
    {
      this->Buckets[b].reserve(size_t(sizes[b]));
    }
    for (Index id = 0; id < n; ++id)
    {
      this->Set(id, keys[id]);
    }
  }

  bool Empty() const { return this->Count == 0; }
  Index Size() const { return this->Count; }
  // Hint: id's entry is about to be changed.
  void Prefetch(Index id) const
  {
    __builtin_prefetch(&this->Slot[id]);
    __builtin_prefetch(&this->BucketId[id]);
  }
  // Second hint, once Prefetch(id) has landed: the bucket header of id's entry.
  void PrefetchBucket(Index id) const
  {
    if (this->Slot[id] != InvalidIndex)
    {
      __builtin_prefetch(&this->Buckets[this->BucketId[id]]);
    }
  }
  // Third hint, once PrefetchBucket(id) has landed: the entries a Set or Remove of id moves (its
  // own and the last of its bucket, which takes its place).
  void PrefetchEntries(Index id) const
  {
    const Index s = this->Slot[id];
    if (s != InvalidIndex)
    {
      const auto& bucket = this->Buckets[this->BucketId[id]];
      __builtin_prefetch(bucket.data() + s, 1);
      __builtin_prefetch(bucket.data() + bucket.size() - 1);
    }
  }
  // Fourth hint, once PrefetchEntries(id) has landed: the slot of the last entry of id's bucket,
  // which a Remove of id rewrites (the entry that fills the gap).
  void PrefetchMoved(Index id) const
  {
    if (this->Slot[id] != InvalidIndex)
    {
      __builtin_prefetch(&this->Slot[this->Buckets[this->BucketId[id]].back().Id], 1);
    }
  }
  // Hints for the insertion of a key: the header of its bucket, then (once landed) its end.
  void PrefetchBucketOf(float key) const { __builtin_prefetch(&this->Buckets[BucketOf(key)]); }
  void PrefetchEnd(float key) const
  {
    const auto& bucket = this->Buckets[BucketOf(key)];
    __builtin_prefetch(bucket.data() + bucket.size(), 1);
  }
  bool Contains(Index id) const { return this->Slot[id] != InvalidIndex; }

  // Ids of up to `count` entries of the lowest non-empty bucket (into ids; returns how many): pops
  // of the near future, for prefetch hints. In a bucket Pop scans they are taken cyclically from
  // position `from` (the scan's order is not theirs); in a larger one, from the back, Pop's order.
  // Reads only: the queue is unchanged. keys (optional) receives their keys.
  int Upcoming(size_t from, int count, Index* ids, float* keys = nullptr) const
  {
    Index b = this->Lowest;
    const Index end = static_cast<Index>(this->Buckets.size());
    while (b < end && this->Buckets[b].empty())
    {
      ++b;
    }
    if (b >= end || count <= 0)
    {
      return 0;
    }
    const auto& bucket = this->Buckets[b];
    const size_t size = bucket.size();
    const int n = size < size_t(count) ? static_cast<int>(size) : count;
    for (int i = 0; i < n; ++i)
    {
      const Entry& e = size > size_t(ScanLimit) ? bucket[size - 1 - size_t(i)] : bucket[(from + size_t(i)) % size];
      ids[i] = e.Id;
      if (keys)
      {
        keys[i] = e.K;
      }
    }
    return n;
  }

  // Inserts id or changes its key (key >= 0; NaN is treated as +infinity).
  void Set(Index id, float key)
  {
    if (this->Slot[id] != InvalidIndex)
    {
      this->Remove(id);
    }
    const Index b = BucketOf(key);
    auto& bucket = this->Buckets[b];
    if (bucket.size() == bucket.capacity())
    {
      // Grow by a quarter, not by doubling: Build allocates every bucket at its size, so the
      // first insertions of a collapse loop would otherwise double the busiest buckets at once
      // (the loop's memory peak on large meshes).
      bucket.reserve(bucket.size() + bucket.size() / 4 + 8);
    }
    this->Slot[id] = static_cast<Index>(bucket.size());
    this->BucketId[id] = static_cast<std::uint16_t>(b);
    bucket.push_back({ key, id });
    this->Lowest = b < this->Lowest ? b : this->Lowest;
    ++this->Count;
  }

  void Remove(Index id)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      return;
    }
    // The entry's bucket follows from its key.
    auto& bucket = this->Buckets[this->BucketId[id]];
    const Entry last = bucket.back();
    bucket[s] = last;
    this->Slot[last.Id] = s;
    bucket.pop_back();
    this->Slot[id] = InvalidIndex;
    --this->Count;
  }

  // The smallest key (call only when not Empty).
  float TopKey()
  {
    this->SkipEmptyBuckets();
    const auto& bucket = this->Buckets[this->Lowest];
    float best = bucket.back().K;
    if (bucket.size() <= size_t(ScanLimit))
    {
      for (const Entry& e : bucket)
      {
        best = e.K < best ? e.K : best;
      }
    }
    return best;
  }

  // True when an element with this key would be popped before every present one (in a bucket
  // too large to scan, any key of the lowest bucket counts as first: Pop serves it last-in).
  bool WouldBeFirst(float key)
  {
    if (this->Count == 0)
    {
      return true;
    }
    const float top = this->TopKey();
    const Index b = BucketOf(key);
    // Judged by the bucket's size once the key is in it, as Pop will judge it: a key inserted into
    // a bucket that then exceeds ScanLimit is served first (last in), so it is first.
    return b < this->Lowest || (b == this->Lowest && (this->Buckets[b].size() + 1 > size_t(ScanLimit) || key <= top));
  }

  // Removes and returns the element of smallest key (call only when not Empty).
  Index Pop(float* key = nullptr)
  {
    this->SkipEmptyBuckets();
    auto& bucket = this->Buckets[this->Lowest];
    size_t best = bucket.size() - 1;
    if (bucket.size() <= size_t(ScanLimit))
    {
      // NaN keys share the bucket of 3e38 (BucketOf) and compare neither smaller nor larger:
      // that bucket and those above it are scanned in order.
      best = this->Lowest < BucketOf(3.0e38f) ? SmallestOf(bucket) : SmallestInOrder(bucket);
    }
    const Entry e = bucket[best];
    if (key)
    {
      *key = e.K;
    }
    this->Remove(e.Id);
    return e.Id;
  }

  size_t MemoryBytes() const
  {
    size_t bytes = this->Slot.capacity() * sizeof(Index) + this->BucketId.capacity() * sizeof(std::uint16_t) + this->Buckets.capacity() * sizeof(this->Buckets[0]);
    for (const auto& b : this->Buckets)
    {
      bytes += b.capacity() * sizeof(Entry);
    }
    return bytes;
  }

private:
  struct Entry
  {
    float K;
    Index Id;
  };
  // SmallestOf reads the entries as pairs of floats, four keys per two 16-byte loads.
  static_assert(sizeof(Entry) == 2 * sizeof(float) && sizeof(Index) == sizeof(float), "Entry must be {float, 32-bit id}");
  // Advances Lowest to the first non-empty bucket (call only when not Empty). The buckets passed
  // give their storage back: costs rise as a collapse loop runs, so the entries move to higher
  // buckets, which grow, while the drained low ones would otherwise keep their largest size (on a
  // 1M-triangle mesh the buckets' capacity grew from 8 to 23 MB by the end of the loop: its peak).
  // The entries and their order are untouched.
  void SkipEmptyBuckets()
  {
    while (this->Buckets[this->Lowest].empty())
    {
      if (this->Buckets[this->Lowest].capacity() > 0)
      {
        std::vector<Entry>().swap(this->Buckets[this->Lowest]);
      }
      ++this->Lowest;
    }
  }
  // Position of the smallest entry (smallest key, then smallest id; the last entry wins nothing
  // over an equal earlier one with a smaller id), one entry after the other: the definition.
  static size_t SmallestInOrder(const std::vector<Entry>& bucket)
  {
    size_t best = bucket.size() - 1;
    for (size_t i = 0; i + 1 < bucket.size(); ++i)
    {
      const Entry& e = bucket[i];
      if (e.K < bucket[best].K || (!(bucket[best].K < e.K) && e.Id < bucket[best].Id))
      {
        best = i;
      }
    }
    return best;
  }

  // The same position for keys that are not NaN, in two passes that need no branch per entry:
  // the smallest key (four at a time), then the smallest id among the entries of that key (equal
  // keys, -0 and +0 included, are the ties of SmallestInOrder). The pop scan was the largest
  // part of the collapse loop's own instructions.
  static size_t SmallestOf(const std::vector<Entry>& bucket)
  {
    const size_t n = bucket.size();
    const Entry* e = bucket.data();
    float smallest = e[n - 1].K;
    size_t i = 0;
#if defined(__SSE2__)
    if (n >= 8)
    {
      __m128 lowest = _mm_set1_ps(smallest);
      for (; i + 4 <= n; i += 4)
      {
        // Entries i..i+3 are {K, Id} pairs: keep the keys (lanes 0 and 2 of each half).
        const __m128 a = _mm_loadu_ps(reinterpret_cast<const float*>(e + i));
        const __m128 b = _mm_loadu_ps(reinterpret_cast<const float*>(e + i + 2));
        lowest = _mm_min_ps(lowest, _mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)));
      }
      lowest = _mm_min_ps(lowest, _mm_shuffle_ps(lowest, lowest, _MM_SHUFFLE(1, 0, 3, 2)));
      lowest = _mm_min_ps(lowest, _mm_shuffle_ps(lowest, lowest, _MM_SHUFFLE(2, 3, 0, 1)));
      smallest = _mm_cvtss_f32(lowest);
    }
#endif
    for (; i < n; ++i)
    {
      smallest = e[i].K < smallest ? e[i].K : smallest;
    }
    size_t best = n - 1;
    Index id = e[n - 1].K == smallest ? e[n - 1].Id : std::numeric_limits<Index>::max();
    size_t j = 0;
#if defined(__SSE2__)
    // Four keys compared at once; only the entries of the smallest key (usually one) look at ids.
    const __m128 target = _mm_set1_ps(smallest);
    for (; j + 4 <= n; j += 4)
    {
      const __m128 a = _mm_loadu_ps(reinterpret_cast<const float*>(e + j));
      const __m128 b = _mm_loadu_ps(reinterpret_cast<const float*>(e + j + 2));
      for (int mask = _mm_movemask_ps(_mm_cmpeq_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)), target)); mask != 0;
           mask &= mask - 1)
      {
        const size_t k = j + size_t(__builtin_ctz(static_cast<unsigned>(mask)));
        best = e[k].Id < id ? k : best;
        id = e[k].Id < id ? e[k].Id : id;
      }
    }
#endif
    for (; j < n; ++j)
    {
      const bool better = e[j].K == smallest && e[j].Id < id;
      best = better ? j : best;
      id = better ? e[j].Id : id;
    }
    return best;
  }

  static Index BucketOf(float key)
  {
    if (!(key > 0.0f))
    {
      // Negative keys and both zeros go to the first bucket (the bits of -0 would index past the
      // last one), NaN to the last finite ones.
      key = key <= 0.0f ? 0.0f : 3.0e38f;
    }
    std::uint32_t bits;
    std::memcpy(&bits, &key, sizeof(bits));
    return static_cast<Index>(bits >> (31 - BucketBits));
  }

  std::vector<std::vector<Entry>> Buckets;
  std::vector<Index> Slot;
  std::vector<std::uint16_t> BucketId; // bucket of each present id
  Index Lowest = 0;
  Index Count = 0;
};
} // namespace slod

#endif
