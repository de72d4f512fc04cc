// SPDX-License-Identifier: BSD-3-Clause
#include "slodCollapsePasses.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace slod
{
namespace
{
std::uint64_t RankKey(float key, Index element)
{
  // Non-negative floats order as their bit patterns.
  std::uint32_t bits = 0;
  std::memcpy(&bits, &key, sizeof(bits));
  return (std::uint64_t(bits) << 32) | std::uint64_t(static_cast<std::uint32_t>(element));
}

float KeyOf(std::uint64_t entry)
{
  const std::uint32_t bits = static_cast<std::uint32_t>(entry >> 32);
  float key = 0.0f;
  std::memcpy(&key, &bits, sizeof(key));
  return key;
}

// Fixed-size chunks (not one per thread), so that every count below is the same for any thread
// count.
constexpr size_t RankChunk = size_t(1) << 16;

bool IsCandidate(const std::vector<float>& keys, const unsigned char* alive, size_t i)
{
  return (!alive || alive[i]) && std::isfinite(keys[i]);
}

std::uint32_t KeyBits(float key)
{
  std::uint32_t bits = 0;
  key = std::max(0.0f, key);
  std::memcpy(&bits, &key, sizeof(bits));
  return bits;
}

// The bits of the candidate key of rank `rank` (0 <= rank < candidates) by a radix select: three
// parallel histogram passes over the keys (12, 12 and 8 bits) instead of a serial nth_element.
std::uint32_t SelectKeyBits(const std::vector<float>& keys, const unsigned char* alive, Index rank)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  std::uint32_t prefix = 0;
  std::uint64_t remaining = std::uint64_t(rank);
  const int widths[3] = { 12, 12, 8 };
  int known = 0; // leading bits of the answer fixed so far
  for (int width : widths)
  {
    const int shift = 32 - known - width;
    const size_t buckets = size_t(1) << width;
    std::vector<std::uint32_t> histograms(chunks * buckets, 0);
    vtkSMPTools::For(0, static_cast<vtkIdType>(chunks), 1, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType c = first; c < last; ++c)
      {
        std::uint32_t* h = histograms.data() + size_t(c) * buckets;
        const size_t end = std::min(keys.size(), size_t(c + 1) * RankChunk);
        for (size_t i = size_t(c) * RankChunk; i < end; ++i)
        {
          const std::uint32_t bits = KeyBits(keys[i]);
          if (IsCandidate(keys, alive, i) && (known == 0 || (bits >> (32 - known)) == prefix))
          {
            ++h[(bits >> shift) & (buckets - 1)];
          }
        }
      }
    });
    size_t bucket = 0;
    for (; bucket < buckets; ++bucket)
    {
      std::uint64_t count = 0;
      for (size_t c = 0; c < chunks; ++c)
      {
        count += histograms[c * buckets + bucket];
      }
      if (remaining < count)
      {
        break;
      }
      remaining -= count;
    }
    prefix = (prefix << width) | static_cast<std::uint32_t>(bucket);
    known += width;
  }
  return prefix;
}

// The candidates with key bits <= `limit` in index order into `order` when given (per-chunk
// counts, then each chunk writes its own part); returns how many candidates there are in all.
Index CollectCandidates(const std::vector<float>& keys, const unsigned char* alive, std::uint32_t limit,
  std::vector<std::uint64_t>* order)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  std::vector<size_t> taken(chunks + 1, 0), finite(chunks, 0);
  auto chunkEnd = [&](size_t c) { return std::min(keys.size(), (c + 1) * RankChunk); };
  vtkSMPTools::For(0, static_cast<vtkIdType>(chunks), 1, [&](vtkIdType first, vtkIdType last) {
    for (size_t c = size_t(first); c < size_t(last); ++c)
    {
      for (size_t i = c * RankChunk; i < chunkEnd(c); ++i)
      {
        const bool candidate = IsCandidate(keys, alive, i);
        finite[c] += candidate ? 1 : 0;
        taken[c + 1] += candidate && KeyBits(keys[i]) <= limit ? 1 : 0;
      }
    }
  });
  for (size_t c = 0; c < chunks; ++c)
  {
    taken[c + 1] += taken[c];
  }
  size_t candidates = 0;
  for (size_t count : finite)
  {
    candidates += count;
  }
  if (!order)
  {
    return static_cast<Index>(candidates);
  }
  order->resize(taken[chunks]);
  std::uint64_t* entries = order->data();
  vtkSMPTools::For(0, static_cast<vtkIdType>(chunks), 1, [&](vtkIdType first, vtkIdType last) {
    for (size_t c = size_t(first); c < size_t(last); ++c)
    {
      size_t out = taken[c];
      for (size_t i = c * RankChunk; i < chunkEnd(c); ++i)
      {
        if (IsCandidate(keys, alive, i) && KeyBits(keys[i]) <= limit)
        {
          entries[out++] = RankKey(std::max(0.0f, keys[i]), static_cast<Index>(i));
        }
      }
    }
  });
  return static_cast<Index>(candidates);
}
} // namespace


void RankPassCandidates(const std::vector<float>& keys, const unsigned char* alive, Index goalRank, double factor,
  float floor, PassRanking& ranking)
{
  // All in parallel and chunked: the candidate count, the key of rank goalRank (radix select), the
  // candidates under the limit; then sorted. The same ranking as a serial nth_element and
  // partition would give, for any thread count.
  std::vector<std::uint64_t>& order = ranking.Order;
  const std::uint32_t all = KeyBits(std::numeric_limits<float>::max());
  ranking.Candidates = CollectCandidates(keys, alive, all, nullptr);
  ranking.Limit = std::numeric_limits<float>::infinity();
  ranking.Everything = true;
  if (goalRank < 0 || goalRank >= ranking.Candidates)
  {
    CollectCandidates(keys, alive, all, &order);
  }
  else
  {
    float goalKey = 0.0f;
    const std::uint32_t bits = SelectKeyBits(keys, alive, goalRank);
    std::memcpy(&goalKey, &bits, sizeof(goalKey));
    const double limit = std::max<double>(floor, factor * double(goalKey));
    ranking.Limit = static_cast<float>(std::min<double>(limit, std::numeric_limits<float>::max()));
    const Index candidates = ranking.Candidates;
    CollectCandidates(keys, alive, KeyBits(ranking.Limit), &order);
    ranking.Everything = Index(order.size()) == candidates;
  }
  // A total order (key, then index): the same result whatever sort and thread count.
  vtkSMPTools::Sort(order.begin(), order.end());
}
} // namespace slod
