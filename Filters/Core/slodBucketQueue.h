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
// A scan keeps the smallest entries it finds in Pop's order (PopCache), so that the next pops of
// the same bucket take them without scanning it again; Set and Remove keep that list exact.
#ifndef slodBucketQueue_h
#define slodBucketQueue_h

#include "slodHugePages.h"
#include "slodTriangleMesh.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace slod
{
// Where the queue keeps each id's bucket number (2 bytes per id): by default an array of its own
// (BucketIdStride = 2); a caller that holds a record per id with two spare bytes (padding) can lend
// them instead (LendBucketIds, with the record's size as the stride), so that the queue needs no
// array of its own for them (session 44: the triangle collapse's 16-byte triangle state had two
// bytes of padding; 4 bytes per input vertex less at the working set's peak). The stride is a
// template argument so that the address of an id's bucket number costs what an array's does.
template <std::size_t BucketIdStride = sizeof(std::uint16_t)>
class BasicBucketQueue
{
public:
  static constexpr int BucketBits = 15;
  static constexpr Index ScanLimit = 512;
  static_assert(BucketIdStride % alignof(std::uint16_t) == 0, "the bucket numbers must be aligned");

  BasicBucketQueue() = default;
  // Not copied: the bucket numbers' address would still be the original's. Moves keep it (the
  // storage moves with the vector, or stays the caller's).
  BasicBucketQueue(const BasicBucketQueue&) = delete;
  BasicBucketQueue& operator=(const BasicBucketQueue&) = delete;
  BasicBucketQueue(BasicBucketQueue&&) = default;
  BasicBucketQueue& operator=(BasicBucketQueue&&) = default;

  // Lends the queue the bucket numbers' storage: the 16-bit field of id 0's record at `first`, and
  // of id i at BucketIdStride * i bytes after it, for `n` ids (n at least the next Reset's or
  // Build's). The records must stay where they are while the queue is used, and the caller must
  // not write that field (a copy of a whole record over another would). Reset does not clear it:
  // a bucket number is read only for an id that is present. Until the next Reset, an id's number
  // is valid only while it is present.
  void LendBucketIds(std::uint16_t* first, Index n)
  {
    std::vector<std::uint16_t>().swap(this->OwnBucketIds);
    this->BucketIdBase = reinterpret_cast<unsigned char*>(first);
    this->LentBucketIds = n;
  }

  void Reset(Index n)
  {
    AssignOnHugePages(this->Slot, size_t(n), InvalidIndex);
    if (this->LentBucketIds < n)
    {
      // (Not lent, or not enough: an array of its own, one stride per id.)
      this->LentBucketIds = 0;
      AssignOnHugePages(this->OwnBucketIds, size_t(n) * BucketIdStride / sizeof(std::uint16_t), std::uint16_t(0));
      this->BucketIdBase = reinterpret_cast<unsigned char*>(this->OwnBucketIds.data());
    }
    this->Buckets.assign(size_t(1) << BucketBits, {});
    this->Lowest = static_cast<Index>(this->Buckets.size());
    this->Count = 0;
    this->ScanCount = 0;
    this->Cache.Clear();
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
  // Scans of a bucket by Pop since Reset (each lists the bucket's smallest entries for the next pops).
  long long Scans() const { return this->ScanCount; }
  Index Size() const { return this->Count; }
  // Hint: id's entry is about to be changed.
  void Prefetch(Index id) const
  {
    __builtin_prefetch(&this->Slot[id]);
    __builtin_prefetch(&this->BucketIdOf(id));
  }
  // Second hint, once Prefetch(id) has landed: the bucket header of id's entry.
  void PrefetchBucket(Index id) const
  {
    if (this->Slot[id] != InvalidIndex)
    {
      __builtin_prefetch(&this->Buckets[this->BucketIdOf(id)]);
    }
  }
  // Third hint, once PrefetchBucket(id) has landed: the entries a Set or Remove of id moves (its
  // own and the last of its bucket, which takes its place).
  void PrefetchEntries(Index id) const
  {
    const Index s = this->Slot[id];
    if (s != InvalidIndex)
    {
      const auto& bucket = this->Buckets[this->BucketIdOf(id)];
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
      __builtin_prefetch(&this->Slot[this->Buckets[this->BucketIdOf(id)].back().Id], 1);
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

  // The next pops in Pop's order, up to `count` (into ids and keys; returns how many): the pop
  // cache's list of the lowest bucket, filled first as the next Pop would fill it (the same scan,
  // which that Pop then does not repeat: the same pops). 0 for a bucket Pop does not list (served
  // from the back, or the NaN bucket and those above it).
  int Listed(int count, Index* ids, float* keys)
  {
    if (this->Empty())
    {
      return 0;
    }
    this->SkipEmptyBuckets();
    const auto& bucket = this->Buckets[this->Lowest];
    if (bucket.size() > size_t(ScanLimit) || this->Lowest >= BucketOf(3.0e38f))
    {
      return 0;
    }
    if (this->Cache.Bucket != this->Lowest || this->Cache.Empty())
    {
      this->Cache.Fill(this->Lowest, bucket);
      ++this->ScanCount;
    }
    const int n = std::min(count, this->Cache.End - this->Cache.Begin);
    for (int i = 0; i < n; ++i)
    {
      ids[i] = this->Cache.Sorted[this->Cache.Begin + i].Id;
      keys[i] = this->Cache.Sorted[this->Cache.Begin + i].K;
    }
    return n > 0 ? n : 0;
  }

  // How many entries have a key at most `bound` (a finite key), counting up to `limit`: the size
  // of a selection that pops while the keys stay within the bound (session 42's batches). Reads
  // only; a bucket too large to scan (served from the back, not in key order) counts as `limit`.
  int CountAtMost(float bound, int limit) const
  {
    int n = 0;
    const Index last = std::min<Index>(BucketOf(bound), static_cast<Index>(this->Buckets.size()) - 1);
    for (Index b = this->Lowest; b <= last && n < limit; ++b)
    {
      const auto& bucket = this->Buckets[b];
      if (bucket.size() > size_t(ScanLimit))
      {
        return limit;
      }
      for (size_t i = 0; i < bucket.size() && n < limit; ++i)
      {
        n += bucket[i].K <= bound ? 1 : 0;
      }
    }
    return n < limit ? n : limit;
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
    this->BucketIdOf(id) = static_cast<std::uint16_t>(b);
    bucket.push_back({ key, id });
    this->Lowest = b < this->Lowest ? b : this->Lowest;
    ++this->Count;
    if (b == this->Cache.Bucket && !Before(this->Cache.Limit, { key, id }))
    {
      this->Cache.Insert({ key, id });
    }
  }

  void Remove(Index id)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      return;
    }
    // The entry's bucket follows from its key.
    const Index b = this->BucketIdOf(id);
    auto& bucket = this->Buckets[b];
    if (b == this->Cache.Bucket && !Before(this->Cache.Limit, bucket[s]))
    {
      this->Cache.Erase(bucket[s].Id);
    }
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
    Entry e = bucket.back();
    if (bucket.size() <= size_t(ScanLimit))
    {
      // NaN keys share the bucket of 3e38 (BucketOf) and compare neither smaller nor larger:
      // that bucket and those above it are scanned in order, without the cache.
      if (this->Lowest >= BucketOf(3.0e38f))
      {
        e = bucket[SmallestInOrder(bucket)];
        ++this->ScanCount;
      }
      else
      {
        if (this->Cache.Bucket != this->Lowest || this->Cache.Empty())
        {
          this->Cache.Fill(this->Lowest, bucket);
          ++this->ScanCount;
        }
        e = this->Cache.Front();
      }
    }
    if (key)
    {
      *key = e.K;
    }
    this->Remove(e.Id);
    return e.Id;
  }

  size_t MemoryBytes() const
  {
    // (Lent bucket numbers are the caller's bytes.)
    size_t bytes = this->Slot.capacity() * sizeof(Index) + this->OwnBucketIds.capacity() * sizeof(std::uint16_t) +
      this->Buckets.capacity() * sizeof(this->Buckets[0]);
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
  // The pop cache's scans read the entries as pairs of floats, four keys per two 16-byte loads.
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

  // Pop's order on entries whose keys are not NaN: key, then id (-0 and +0 are equal keys).
  static bool Before(const Entry& a, const Entry& b) { return a.K < b.K || (a.K == b.K && a.Id < b.Id); }

  // The smallest entries of one bucket in Pop's order, and a limit: every entry of that bucket
  // that is not listed comes after Limit in Pop's order. Pop takes the front; Set and Remove keep
  // the list exact for the entries at or before Limit (Insert, Erase), so that one scan serves
  // the next pops of the bucket: the pop scan was the largest part of the collapse loop's own
  // in-order work (about 300 instructions per pop on the marching-cubes mesh, session 34).
  struct PopCache
  {
    static constexpr int Capacity = 32;
    Index Bucket = InvalidIndex; // the bucket listed, or none
    int Begin = 0, End = 0;      // the listed entries are Sorted[Begin, End)
    Entry Limit{ 0.0f, 0 };
    Entry Sorted[Capacity];

    void Clear()
    {
      this->Bucket = InvalidIndex;
      this->Begin = this->End = 0;
    }
    bool Empty() const { return this->Begin == this->End; }
    const Entry& Front() const { return this->Sorted[this->Begin]; }
    // Lists e, an entry of the bucket at or before the limit (out of line: Set's common path is
    // the test before the call).
    __attribute__((noinline)) void Insert(const Entry& e)
    {
      if (this->End == Capacity && this->Begin > 0)
      {
        std::memmove(this->Sorted, this->Sorted + this->Begin, size_t(this->End - this->Begin) * sizeof(Entry));
        this->End -= this->Begin;
        this->Begin = 0;
      }
      if (this->End == Capacity)
      {
        // Full: the last entry leaves the list, and the limit moves before it.
        --this->End;
        this->Limit = this->Sorted[this->End - 1];
        if (Before(this->Limit, e))
        {
          return;
        }
      }
      int i = this->End++;
      for (; i > this->Begin && Before(e, this->Sorted[i - 1]); --i)
      {
        this->Sorted[i] = this->Sorted[i - 1];
      }
      this->Sorted[i] = e;
    }
    // Takes the entry of id (at or before the limit, so listed) off the list; the front is a pop.
    void Erase(Index id)
    {
      int i = this->Begin;
      while (i < this->End && this->Sorted[i].Id != id)
      {
        ++i;
      }
      if (i == this->End)
      {
        return; // not reached: every entry at or before the limit is listed
      }
      if (i == this->Begin)
      {
        ++this->Begin; // a pop
        return;
      }
      std::memmove(this->Sorted + i, this->Sorted + i + 1, size_t(this->End - i - 1) * sizeof(Entry));
      --this->End;
    }
    // Lists the smallest entries of bucket b (not empty, at most ScanLimit entries, no NaN key).
    void Fill(Index b, const std::vector<Entry>& bucket)
    {
      Entry found[ScanLimit];
      const int count = bucket.size() <= size_t(Capacity) ? CopyAll(bucket, found) : Smallest(bucket, found);
      const int listed = count < Capacity ? count : Capacity;
      const bool many = count > 2 * Capacity; // ties at the threshold: select, then sort the few
      if (many)
      {
        std::nth_element(found, found + listed, found + count, [](const Entry& x, const Entry& y) { return Before(x, y); });
      }
      SortFew(found, many ? listed : count);
      std::memcpy(this->Sorted, found, size_t(listed) * sizeof(Entry));
      this->Bucket = b;
      this->Begin = 0;
      this->End = listed;
      this->Limit = this->Sorted[listed - 1];
    }
    // Insertion sort in Pop's order: the lists are short (about 16 entries).
    static void SortFew(Entry* e, int n)
    {
      for (int i = 1; i < n; ++i)
      {
        const Entry x = e[i];
        int j = i;
        for (; j > 0 && Before(x, e[j - 1]); --j)
        {
          e[j] = e[j - 1];
        }
        e[j] = x;
      }
    }
    static int CopyAll(const std::vector<Entry>& bucket, Entry* found)
    {
      std::memcpy(found, bucket.data(), bucket.size() * sizeof(Entry));
      return static_cast<int>(bucket.size());
    }
    // The entries at or below the largest of eight minima (of the entries at positions i, i + 8,
    // i + 16, ... for i = 0..7), so at least eight and about 16 on a bucket in random order, found
    // with no branch per entry; returns how many (more than 32 entries in the bucket).
    static int Smallest(const std::vector<Entry>& bucket, Entry* found)
    {
      const size_t n = bucket.size();
      const Entry* e = bucket.data();
      const float threshold = LargestOfEightMinima(e, n);
      int count = 0;
      size_t j = 0;
#if defined(__SSE2__)
      const __m128 t = _mm_set1_ps(threshold);
      for (; j + 4 <= n; j += 4)
      {
        // Entries j..j+3 are {K, Id} pairs: keep the keys (lanes 0 and 2 of each half).
        const __m128 a = _mm_loadu_ps(reinterpret_cast<const float*>(e + j));
        const __m128 c = _mm_loadu_ps(reinterpret_cast<const float*>(e + j + 2));
        for (int mask = _mm_movemask_ps(_mm_cmple_ps(_mm_shuffle_ps(a, c, _MM_SHUFFLE(2, 0, 2, 0)), t)); mask != 0;
             mask &= mask - 1)
        {
          found[count++] = e[j + size_t(__builtin_ctz(static_cast<unsigned>(mask)))];
        }
      }
#endif
      for (; j < n; ++j)
      {
        if (e[j].K <= threshold)
        {
          found[count++] = e[j];
        }
      }
      return count;
    }
    static float LargestOfEightMinima(const Entry* e, size_t n)
    {
      size_t i = 0;
#if defined(__SSE2__)
      __m128 low = _mm_set1_ps(std::numeric_limits<float>::infinity()), high = low;
      for (; i + 8 <= n; i += 8)
      {
        const __m128 a = _mm_loadu_ps(reinterpret_cast<const float*>(e + i));
        const __m128 b = _mm_loadu_ps(reinterpret_cast<const float*>(e + i + 2));
        const __m128 c = _mm_loadu_ps(reinterpret_cast<const float*>(e + i + 4));
        const __m128 d = _mm_loadu_ps(reinterpret_cast<const float*>(e + i + 6));
        low = _mm_min_ps(low, _mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)));
        high = _mm_min_ps(high, _mm_shuffle_ps(c, d, _MM_SHUFFLE(2, 0, 2, 0)));
      }
      __m128 m = _mm_max_ps(low, high);
      m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
      m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
      return _mm_cvtss_f32(m);
#else
      float minima[8];
      std::fill(minima, minima + 8, std::numeric_limits<float>::infinity());
      for (; i + 8 <= n; i += 8)
      {
        for (int k = 0; k < 8; ++k)
        {
          minima[k] = e[i + size_t(k)].K < minima[k] ? e[i + size_t(k)].K : minima[k];
        }
      }
      return *std::max_element(minima, minima + 8);
#endif
    }
  };

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
  // The bucket of each present id: at BucketIdBase + BucketIdStride * id, in OwnBucketIds or in
  // the caller's records (LendBucketIds; LentBucketIds ids).
  std::vector<std::uint16_t> OwnBucketIds;
  unsigned char* BucketIdBase = nullptr;
  Index LentBucketIds = 0;
  std::uint16_t& BucketIdOf(Index id) const
  {
    return *reinterpret_cast<std::uint16_t*>(this->BucketIdBase + BucketIdStride * size_t(id));
  }
  Index Lowest = 0;
  Index Count = 0;
  long long ScanCount = 0;
  PopCache Cache;
};
using BucketQueue = BasicBucketQueue<>;
} // namespace slod

#endif
