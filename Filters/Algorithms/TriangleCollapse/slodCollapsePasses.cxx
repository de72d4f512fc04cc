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
// Fixed-size chunks (not one per thread), so that every count below is the same for any thread
// count.
constexpr size_t RankChunk = size_t(1) << 16;
// The goal key's first selection step: the key's top bits (sign, exponent, 3 mantissa bits).
constexpr int BucketShift = 20;
constexpr size_t Buckets = size_t(1) << (32 - BucketShift);

// A key's bits (negative keys count as 0): non-negative floats order as their bit patterns.
std::uint32_t KeyBits(float key)
{
  std::uint32_t bits = 0;
  key = std::max(0.0f, key);
  std::memcpy(&bits, &key, sizeof(bits));
  return bits;
}

// Calls visit(i, bits) for every candidate of chunk c (alive, finite key) with its key's bits.
template <typename Visit>
void ForCandidatesOfChunk(const std::vector<float>& keys, const unsigned char* alive, size_t c, Visit&& visit)
{
  const size_t end = std::min(keys.size(), (c + 1) * RankChunk);
  for (size_t i = c * RankChunk; i < end; ++i)
  {
    if ((!alive || alive[i]) && std::isfinite(keys[i]))
    {
      visit(i, KeyBits(keys[i]));
    }
  }
}

// Runs work(c) for every chunk of the keys in parallel.
template <typename Work>
void ForChunks(const std::vector<float>& keys, Work&& work)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  vtkSMPTools::For(0, static_cast<vtkIdType>(chunks), 1, [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType c = first; c < last; ++c)
    {
      work(size_t(c));
    }
  });
}

// The bits of the candidate key of rank `rank`: a histogram of the keys' top bits (which also
// counts the candidates), then the keys of the bucket that holds the rank, selected among
// themselves. Returns false (and no key) when rank is negative or not below the count.
bool SelectKeyBits(const std::vector<float>& keys, const unsigned char* alive, Index rank, Index& candidates,
  std::uint32_t& selected)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  std::vector<std::uint32_t> histograms(chunks * Buckets, 0);
  ForChunks(keys, [&](size_t c) {
    std::uint32_t* h = histograms.data() + c * Buckets;
    ForCandidatesOfChunk(keys, alive, c, [&](size_t, std::uint32_t bits) { ++h[bits >> BucketShift]; });
  });
  std::vector<size_t> counts(Buckets, 0);
  size_t total = 0;
  for (size_t b = 0; b < Buckets; ++b)
  {
    for (size_t c = 0; c < chunks; ++c)
    {
      counts[b] += histograms[c * Buckets + b];
    }
    total += counts[b];
  }
  candidates = static_cast<Index>(total);
  if (rank < 0 || size_t(rank) >= total)
  {
    return false;
  }
  size_t bucket = 0, below = 0;
  for (; below + counts[bucket] <= size_t(rank); ++bucket)
  {
    below += counts[bucket];
  }
  std::vector<std::vector<std::uint32_t>> inBucket(chunks);
  ForChunks(keys, [&](size_t c) {
    ForCandidatesOfChunk(keys, alive, c, [&](size_t, std::uint32_t bits) {
      if ((bits >> BucketShift) == bucket)
      {
        inBucket[c].push_back(bits);
      }
    });
  });
  std::vector<std::uint32_t> bits;
  bits.reserve(counts[bucket]);
  for (const auto& part : inBucket)
  {
    bits.insert(bits.end(), part.begin(), part.end());
  }
  std::nth_element(bits.begin(), bits.begin() + (size_t(rank) - below), bits.end());
  selected = bits[size_t(rank) - below];
  return true;
}

// The candidates with key bits <= `limit` as rank entries, in index order (each chunk collects its
// own, then they are joined in chunk order).
void CollectCandidates(const std::vector<float>& keys, const unsigned char* alive, std::uint32_t limit,
  std::vector<std::uint64_t>& order)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  std::vector<std::vector<std::uint64_t>> parts(chunks);
  ForChunks(keys, [&](size_t c) {
    ForCandidatesOfChunk(keys, alive, c, [&](size_t i, std::uint32_t bits) {
      if (bits <= limit)
      {
        // Key bits (high 32) and element index (low 32): the order of PassRanking::Order.
        parts[c].push_back((std::uint64_t(bits) << 32) | std::uint64_t(static_cast<std::uint32_t>(i)));
      }
    });
  });
  std::vector<size_t> offset(chunks + 1, 0);
  for (size_t c = 0; c < chunks; ++c)
  {
    offset[c + 1] = offset[c] + parts[c].size();
  }
  order.resize(offset[chunks]);
  ForChunks(keys, [&](size_t c) { std::copy(parts[c].begin(), parts[c].end(), order.begin() + offset[c]); });
}
} // namespace


void RankPassCandidates(const std::vector<float>& keys, const unsigned char* alive, Index goalRank, double factor,
  float floor, PassRanking& ranking)
{
  // In parallel over fixed chunks: the key of rank goalRank (a histogram, then a selection among
  // the few keys of one bucket), the candidates under the limit; then sorted. The same ranking as
  // an nth_element and a partition of all candidates, for any thread count.
  std::uint32_t goalBits = 0;
  ranking.Limit = std::numeric_limits<float>::infinity();
  std::uint32_t limitBits = KeyBits(std::numeric_limits<float>::max());
  if (SelectKeyBits(keys, alive, goalRank, ranking.Candidates, goalBits))
  {
    float goalKey = 0.0f;
    std::memcpy(&goalKey, &goalBits, sizeof(goalKey));
    const double limit = std::max<double>(floor, factor * double(goalKey));
    ranking.Limit = static_cast<float>(std::min<double>(limit, std::numeric_limits<float>::max()));
    limitBits = KeyBits(ranking.Limit);
  }
  CollectCandidates(keys, alive, limitBits, ranking.Order);
  ranking.Everything = Index(ranking.Order.size()) == ranking.Candidates;
  // A total order (key, then index): the same result whatever sort and thread count.
  vtkSMPTools::Sort(ranking.Order.begin(), ranking.Order.end());
}
} // namespace slod
