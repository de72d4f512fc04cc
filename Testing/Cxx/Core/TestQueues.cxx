// SPDX-License-Identifier: BSD-3-Clause
// Shared priority queues (slod::BucketQueue, slod::IndexedHeap): pop order against a sorted
// reference under updates and removals, termination with large buckets of equal keys,
// WouldBeFirst agreeing with Pop at the bucket scan limit, the scan's order with ties, signed
// zeros and negative keys, and the release of drained buckets.
#include "slodBucketQueue.h"
#include "slodIndexedHeap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace slod;

TEST(PriorityQueues, BucketQueueAndIndexedHeapPopInKeyOrder)
{
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const Index n = 5000;
  std::vector<float> keys(n);
  BucketQueue buckets;
  IndexedHeap<float> heap;
  buckets.Reset(n);
  heap.Reset(n);
  for (Index i = 0; i < n; ++i)
  {
    keys[i] = std::pow(uniform(random), 4.0f) * 1e-6f; // many octaves
    buckets.Set(i, keys[i]);
    heap.Set(i, keys[i]);
  }
  // Updates and removals.
  for (Index i = 0; i < n; i += 7)
  {
    keys[i] *= 3.0f;
    buckets.Set(i, keys[i]);
    heap.Set(i, keys[i]);
  }
  for (Index i = 3; i < n; i += 11)
  {
    buckets.Remove(i);
    heap.Remove(i);
    keys[i] = -1;
  }
  std::vector<std::pair<float, Index>> expected;
  for (Index i = 0; i < n; ++i)
  {
    if (keys[i] >= 0)
    {
      expected.push_back({ keys[i], i });
    }
  }
  std::sort(expected.begin(), expected.end());
  ASSERT_EQ(buckets.Size(), Index(expected.size()));
  for (const auto& e : expected)
  {
    EXPECT_TRUE(buckets.WouldBeFirst(e.first));
    float key;
    ASSERT_EQ(buckets.Pop(&key), e.second);
    ASSERT_EQ(heap.Pop(), e.second);
  }
  EXPECT_TRUE(buckets.Empty());
  EXPECT_TRUE(heap.Empty());
}

TEST(PriorityQueues, LargeTieBucketTerminates)
{
  // More equal keys than a bucket scan covers: served last-in first, and a re-inserted element
  // counts as first so that a caller's "still the cheapest?" test cannot requeue it forever.
  BucketQueue queue;
  const Index n = 3 * BucketQueue::ScanLimit;
  queue.Reset(n + 1);
  for (Index i = 0; i < n; ++i)
  {
    queue.Set(i, 0.5f);
  }
  const Index first = queue.Pop();
  EXPECT_TRUE(queue.WouldBeFirst(0.5f));
  EXPECT_FALSE(queue.WouldBeFirst(0.75f));
  queue.Set(first, 0.5f);
  Index count = 0;
  while (!queue.Empty())
  {
    queue.Pop();
    ++count;
  }
  EXPECT_EQ(count, n);
}

// WouldBeFirst must agree with Pop at every bucket size, in particular when re-inserting the
// popped element makes the bucket cross ScanLimit (Pop then serves it last-in without a scan). A
// "not first" answer followed by Pop returning the same element is a livelock of a caller that
// defers it (seen on a 2.1M-triangle MRI isosurface).
TEST(PriorityQueues, WouldBeFirstAgreesWithPopAtEveryBucketSize)
{
  for (Index size = BucketQueue::ScanLimit - 2; size <= BucketQueue::ScanLimit + 2; ++size)
  {
    SCOPED_TRACE(size);
    BucketQueue queue;
    queue.Reset(size + 1);
    // Distinct keys within one bucket (relative spacing far below a bucket's width).
    for (Index i = 0; i < size + 1; ++i)
    {
      queue.Set(i, 1.0f + 1e-6f * static_cast<float>(size + 1 - i));
    }
    const Index popped = queue.Pop();
    const float later = 1.0f + 1e-6f * static_cast<float>(size + 2);
    const bool first = queue.WouldBeFirst(later);
    queue.Set(popped, later);
    EXPECT_EQ(first, queue.Pop() == popped);
  }
}

// Clear() empties only what is queued and Reserve() grows the id range in place: a reused heap
// (many small Dijkstra regions, ear clippings) must behave as a fresh one, and equal keys pop by id.
TEST(PriorityQueues, IndexedHeapClearedAndGrownBehavesAsFresh)
{
  IndexedHeap<double> heap;
  heap.Reset(4);
  heap.Set(3, 2.0);
  heap.Set(1, 5.0);
  heap.Clear();
  EXPECT_TRUE(heap.Empty());
  EXPECT_FALSE(heap.Contains(3));
  EXPECT_FALSE(heap.Contains(1));
  heap.Reserve(10);
  heap.Set(9, 1.0);
  heap.Set(2, 1.0);
  heap.Set(7, 0.5);
  heap.Set(1, 1.0);
  const std::vector<Index> expected = { 7, 1, 2, 9 };
  std::vector<Index> popped;
  while (!heap.Empty())
  {
    popped.push_back(heap.Pop());
  }
  EXPECT_EQ(popped, expected);
}

// A bucket drained as the lowest key rises gives its storage back: after the keys moved up, the
// queue holds about what its entries need, not every bucket's largest size.
TEST(PriorityQueues, BucketQueueReleasesDrainedBuckets)
{
  const Index n = 20000;
  BucketQueue queue;
  queue.Reset(n);
  for (Index i = 0; i < n; ++i)
  {
    queue.Set(i, 1.0f + 1e-3f * static_cast<float>(i % 97)); // low buckets
  }
  const size_t full = queue.MemoryBytes();
  // Every popped element comes back with a key a thousand times higher (as costs rise in a
  // collapse loop), until the low buckets are drained; the last pop reaches the high buckets.
  for (Index k = 0; k < n; ++k)
  {
    float key = 0.0f;
    const Index id = queue.Pop(&key);
    queue.Set(id, key * 1000.0f);
  }
  queue.Pop();
  const size_t entries = size_t(n) * 2 * sizeof(float);
  // Without the release the drained low buckets keep their capacity on top of the high ones'.
  EXPECT_LT(queue.MemoryBytes(), full + entries / 2);
}

// The scan of a bucket finds the smallest key, then the smallest id among equal keys (-0 and +0
// are equal), for negative keys (bucket 0) too and at every bucket size up to the scan limit, as
// the one-by-one comparison that defines the order.
TEST(PriorityQueues, BucketQueueScanBreaksTiesBySmallestId)
{
  std::mt19937 random(5);
  for (Index size : { Index(1), Index(2), Index(3), Index(7), Index(8), Index(9), Index(100), BucketQueue::ScanLimit })
  {
    SCOPED_TRACE(size);
    std::uniform_int_distribution<int> pick(0, 5);
    const float values[] = { 0.0f, -0.0f, -1e-30f, 1e-30f, 1.5f, 1.5f * (1.0f + 1e-6f) };
    BucketQueue queue;
    queue.Reset(2 * size);
    std::vector<std::pair<float, Index>> expected;
    // Ids set in a shuffled order, so that the entries' positions in a bucket are not by id.
    std::vector<Index> ids(static_cast<size_t>(size));
    for (Index i = 0; i < size; ++i)
    {
      ids[size_t(i)] = 2 * i + (i % 3 == 0 ? 1 : 0);
    }
    std::shuffle(ids.begin(), ids.end(), random);
    for (Index id : ids)
    {
      const float key = values[pick(random)];
      queue.Set(id, key);
      expected.push_back({ key, id });
    }
    auto before = [](const std::pair<float, Index>& a, const std::pair<float, Index>& b) {
      return a.first < b.first || (!(b.first < a.first) && a.second < b.second);
    };
    std::sort(expected.begin(), expected.end(), before);
    for (const auto& e : expected)
    {
      ASSERT_EQ(queue.Pop(), e.second);
    }
  }
}

// Upcoming (the collapse loop's prefetch hints, session 31) names entries of the lowest non-empty
// bucket, i.e. pops of the near future, and changes nothing: a scanned bucket's entries are all
// named by a cyclic walk from any position, a bucket too large to scan names its next pops in
// Pop's order (from the back), and the pop order with the hints taken equals a twin queue's.
TEST(PriorityQueues, UpcomingNamesTheLowestBucketAndChangesNothing)
{
  std::mt19937 random(31);
  std::uniform_real_distribution<float> within(0.0f, 1e-4f); // far below a bucket's width at 1.0
  const Index low = 50, high = 200, ties = BucketQueue::ScanLimit + 20;
  BucketQueue queue, twin;
  queue.Reset(low + high + ties);
  twin.Reset(low + high + ties);
  Index ids[8];
  EXPECT_EQ(queue.Upcoming(0, 8, ids), 0); // empty: nothing named
  std::vector<Index> order(size_t(low + high));
  for (Index i = 0; i < low + high; ++i)
  {
    order[size_t(i)] = i;
  }
  std::shuffle(order.begin(), order.end(), random);
  for (Index id : order)
  {
    // ids below `low` share the bucket of 1.0; the others lie in buckets of their own from 2.0 up
    // (2 % apart: a bucket spans under 0.8 %).
    const float key = id < low ? 1.0f + within(random) : 2.0f * std::pow(1.02f, static_cast<float>(id - low));
    queue.Set(id, key);
    twin.Set(id, key);
  }
  for (Index popped = 0; popped < low; ++popped)
  {
    // The remaining low entries, all named by a walk of the bucket from an arbitrary position.
    std::set<Index> named;
    const size_t from = size_t(7 * popped);
    for (size_t at = from; at < from + size_t(low - popped); at += 3)
    {
      const int n = queue.Upcoming(at, 3, ids);
      ASSERT_GE(n, 1);
      ASSERT_LE(n, 3);
      for (int i = 0; i < n; ++i)
      {
        EXPECT_LT(ids[i], low) << "an entry of a higher bucket was named";
        EXPECT_TRUE(queue.Contains(ids[i]));
        named.insert(ids[i]);
      }
    }
    EXPECT_EQ(named.size(), size_t(low - popped));
    const Index next = queue.Pop();
    ASSERT_EQ(next, twin.Pop());
    EXPECT_EQ(named.count(next), 1u) << "the next pop was not among the named entries";
  }
  // The low bucket is drained: the next non-empty bucket is named (the smallest key of the rest).
  ASSERT_EQ(queue.Upcoming(0, 1, ids), 1);
  EXPECT_EQ(ids[0], queue.Pop());
  twin.Pop();
  // A bucket too large to scan (ties below every other key): its next pops, in order.
  for (Index i = 0; i < ties; ++i)
  {
    queue.Set(low + high + i, 0.25f);
    twin.Set(low + high + i, 0.25f);
  }
  const int n = queue.Upcoming(0, 8, ids);
  ASSERT_EQ(n, 8);
  for (int i = 0; i < n; ++i)
  {
    const Index next = queue.Pop();
    EXPECT_EQ(ids[i], next);
    EXPECT_EQ(twin.Pop(), next);
  }
  while (!twin.Empty())
  {
    queue.Upcoming(size_t(twin.Size()), 4, ids);
    ASSERT_EQ(queue.Pop(), twin.Pop());
  }
  EXPECT_TRUE(queue.Empty());
}

// The pop cache (session 35): a scan of the lowest bucket lists its smallest entries for the next
// pops, and Set and Remove keep that list exact. Under a churn of insertions (below the current
// minimum, at the list's end, ties broken by id, signed zeros), key changes and removals of listed
// and unlisted entries inside one scanned bucket, every pop is the reference's smallest (key,
// then id), and a scan serves several pops: each lists at least eight entries of a bucket above
// the list's capacity, and only pops and removals take them off.
TEST(PriorityQueues, PopCacheServesSeveralPopsPerScanInKeyOrder)
{
  for (const float base : { 1.0f, 0.0f })
  {
    std::mt19937 random(base == 0.0f ? 350 : 35);
    // Keys of one bucket: 1.0 to 1.0 + 1e-4 (a bucket spans about 0.8 %), or for base 0 the
    // first bucket, which holds both zeros and the negative keys.
    std::uniform_real_distribution<float> within(0.0f, 1e-4f);
    std::uniform_int_distribution<int> coarse(0, 15); // few distinct keys: many ties
    auto draw = [&]() {
      if (base == 0.0f)
      {
        const int c = coarse(random);
        return c == 0 ? -0.0f : c == 1 ? 0.0f : -float(c);
      }
      return coarse(random) < 4 ? 1.0f + 1e-5f * float(coarse(random)) : 1.0f + within(random);
    };
    const Index n = 2000, resident = 300; // at most ScanLimit present: every pop scans
    ASSERT_LE(resident, BucketQueue::ScanLimit);
    BucketQueue queue;
    queue.Reset(n);
    std::vector<float> key(size_t(n), 0.0f);
    std::vector<bool> present(size_t(n), false);
    auto before = [&](Index a, Index b) { return key[a] < key[b] || (!(key[b] < key[a]) && a < b); };
    std::set<Index, decltype(before)> reference(before);
    std::uniform_int_distribution<Index> anyId(0, n - 1);
    std::uniform_int_distribution<int> action(0, 9);
    long long pops = 0;
    auto set = [&](Index id, float k) {
      reference.erase(id);
      key[size_t(id)] = k;
      present[size_t(id)] = true;
      queue.Set(id, k);
      reference.insert(id);
    };
    for (Index id = 0; id < resident; ++id)
    {
      set(id, draw());
    }
    for (int step = 0; step < 20000; ++step)
    {
      const int a = action(random);
      const Index id = anyId(random);
      if (a < 4 && !reference.empty())
      {
        const Index expected = *reference.begin();
        float popped = -2.0f;
        ASSERT_EQ(queue.Pop(&popped), expected) << "step " << step;
        EXPECT_EQ(popped, key[size_t(expected)]);
        reference.erase(reference.begin());
        present[size_t(expected)] = false;
        ++pops;
      }
      else if (a < 8 && Index(reference.size()) < resident)
      {
        // A new key, or one just below the current smallest (the list's front), or equal to it.
        const float k = a == 7 && !reference.empty() ? key[size_t(*reference.begin())] * (base == 0.0f ? 1.0f : 0.99999f) : draw();
        set(id, k);
      }
      else if (present[size_t(id)])
      {
        reference.erase(id);
        present[size_t(id)] = false;
        queue.Remove(id);
      }
      ASSERT_EQ(queue.Size(), Index(reference.size()));
    }
    EXPECT_GT(pops, 5000);
    // At least eight listed entries per scan; removals of listed entries are rare (a tenth of the
    // steps remove a random id, about one in twenty of them listed).
    EXPECT_LE(queue.Scans() * 4, pops) << queue.Scans() << " scans for " << pops << " pops, base " << base;
  }
}

// A scan lists the smallest entries at every number of entries tied at its threshold (one key for
// the whole bucket, or two or three keys): the list is chosen among them by key, then id, at and
// around the sizes where the selection changes (the list's capacity, twice it).
TEST(PriorityQueues, PopCacheListsTheSmallestAtEveryCountOfTies)
{
  std::mt19937 random(64);
  for (int distinct = 1; distinct <= 3; ++distinct)
  {
    for (Index size = 1; size <= 3 * 32 + 8; ++size)
    {
      SCOPED_TRACE(testing::Message() << size << " entries, " << distinct << " keys");
      BucketQueue queue;
      queue.Reset(4 * size);
      std::vector<std::pair<float, Index>> expected;
      std::vector<Index> ids(static_cast<size_t>(size));
      for (Index i = 0; i < size; ++i)
      {
        ids[size_t(i)] = 4 * i + i % 4;
      }
      std::shuffle(ids.begin(), ids.end(), random);
      for (Index id : ids)
      {
        const float key = 2.0f + 1e-4f * float(id % distinct); // one bucket
        queue.Set(id, key);
        expected.push_back({ key, id });
      }
      std::sort(expected.begin(), expected.end());
      for (const auto& e : expected)
      {
        ASSERT_EQ(queue.Pop(), e.second);
      }
    }
  }
}

// Listed (session 36) names the next pops in Pop's order (key, then id) from the pop cache, which
// it fills as the next Pop would: over a queue with ties, keys in one bucket and keys in buckets of
// their own, interleaved with key changes, insertions and removals, every listing is exactly the
// next pops of a twin queue that is never listed, and listing changes no pop. A bucket served from
// the back (too large to scan) is not listed.
TEST(PriorityQueues, ListedNamesTheNextPopsInOrder)
{
  std::mt19937 random(36);
  std::uniform_int_distribution<int> tie(0, 40);
  std::uniform_real_distribution<float> spread(1.0f, 4.0f);
  const Index count = 3000;
  BucketQueue queue, twin;
  queue.Reset(count);
  twin.Reset(count);
  auto keyOf = [&](Index id) { return id % 8 == 0 ? 1.0f + 1e-6f * static_cast<float>(tie(random)) : spread(random); };
  for (Index id = 0; id < count; ++id)
  {
    const float key = keyOf(id);
    queue.Set(id, key);
    twin.Set(id, key);
  }
  Index ids[32];
  float keys[32];
  long long listedTotal = 0;
  for (int step = 0; step < 2000 && !twin.Empty(); ++step)
  {
    const int n = queue.Listed(1 + step % 32, ids, keys);
    ASSERT_LE(n, 1 + step % 32);
    listedTotal += n;
    // The listed entries are the next pops of the twin, with their keys.
    std::vector<std::pair<Index, float>> popped;
    for (int i = 0; i < n; ++i)
    {
      float key = 0.0f;
      const Index next = twin.Pop(&key);
      popped.emplace_back(next, key);
      ASSERT_EQ(ids[i], next) << "step " << step << ", listed entry " << i;
      ASSERT_EQ(keys[i], key) << "step " << step;
    }
    for (const auto& e : popped)
    {
      twin.Set(e.first, e.second); // back, so that the queues stay equal
    }
    // Then a few pops, and a key change and a removal of arbitrary entries, on both.
    for (int i = 0; i < 1 + step % 3 && !twin.Empty(); ++i)
    {
      float a = 0.0f, b = 0.0f;
      ASSERT_EQ(queue.Pop(&a), twin.Pop(&b));
      ASSERT_EQ(a, b);
    }
    const Index changed = static_cast<Index>(random() % count), removed = static_cast<Index>(random() % count);
    if (queue.Contains(changed))
    {
      const float key = keyOf(changed);
      queue.Set(changed, key);
      twin.Set(changed, key);
    }
    if (queue.Contains(removed))
    {
      queue.Remove(removed);
      twin.Remove(removed);
    }
  }
  EXPECT_GT(listedTotal, 2000) << "the listings named few entries";
  // A bucket too large to scan is served from the back, not listed.
  BucketQueue ties;
  ties.Reset(BucketQueue::ScanLimit + 10);
  for (Index id = 0; id < BucketQueue::ScanLimit + 10; ++id)
  {
    ties.Set(id, 0.5f);
  }
  EXPECT_EQ(ties.Listed(8, ids, keys), 0);
  BucketQueue empty;
  empty.Reset(4);
  EXPECT_EQ(empty.Listed(8, ids, keys), 0);
}

// A queue whose bucket numbers live in the caller's records (LendBucketIds, session 44) pops what
// a queue with its own array pops, through sets, updates and removals, leaves the records' other
// fields as they were, and holds 2 bytes per id less.
TEST(PriorityQueues, LentBucketNumbersGiveTheSamePopsAndLessMemory)
{
  struct Record
  {
    float Payload[3];
    unsigned char Flags[2];
    std::uint16_t Bucket;
  };
  std::mt19937 random(11);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const Index n = 4000;
  std::vector<float> keys(n);
  for (float& key : keys)
  {
    key = std::pow(uniform(random), 3.0f) * 1e-3f;
  }
  std::vector<Record> records(size_t(n), Record{ { 1.0f, 2.0f, 3.0f }, { 4, 5 }, 0 });
  BucketQueue own;
  BasicBucketQueue<sizeof(Record)> lent;
  lent.LendBucketIds(&records[0].Bucket, n);
  own.Build(keys.data(), n);
  lent.Build(keys.data(), n);
  EXPECT_EQ(own.MemoryBytes() - lent.MemoryBytes(), size_t(n) * sizeof(std::uint16_t));
  for (Index i = 0; i < n; i += 5)
  {
    own.Set(i, keys[i] * 7.0f);
    lent.Set(i, keys[i] * 7.0f);
  }
  for (Index i = 2; i < n; i += 9)
  {
    own.Remove(i);
    lent.Remove(i);
  }
  ASSERT_EQ(own.Size(), lent.Size());
  while (!own.Empty())
  {
    float a = 0, b = 0;
    ASSERT_EQ(own.Pop(&a), lent.Pop(&b));
    ASSERT_EQ(a, b);
  }
  EXPECT_TRUE(lent.Empty());
  for (const Record& r : records)
  {
    ASSERT_TRUE(r.Payload[0] == 1.0f && r.Payload[1] == 2.0f && r.Payload[2] == 3.0f && r.Flags[0] == 4 && r.Flags[1] == 5);
  }
}
