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

#include "slodTriangleMesh.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace slod
{
class BucketQueue
{
public:
  static constexpr int BucketBits = 15;
  static constexpr Index ScanLimit = 512;

  void Reset(Index n)
  {
    this->Slot.assign(size_t(n), InvalidIndex);
    this->BucketId.assign(size_t(n), 0);
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
      for (size_t i = 0; i + 1 < bucket.size(); ++i)
      {
        const Entry& e = bucket[i];
        if (e.K < bucket[best].K || (!(bucket[best].K < e.K) && e.Id < bucket[best].Id))
        {
          best = i;
        }
      }
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
  static Index BucketOf(float key)
  {
    if (!(key >= 0.0f))
    {
      key = key < 0.0f ? 0.0f : 3.0e38f; // NaN: last
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
