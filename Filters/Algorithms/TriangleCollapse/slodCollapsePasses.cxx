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

// Per chunk, the candidates' counts by the keys' top bits (Buckets of them, chunk after chunk).
std::vector<std::uint32_t> ChunkHistograms(const std::vector<float>& keys, const unsigned char* alive)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  std::vector<std::uint32_t> histograms(chunks * Buckets, 0);
  ForChunks(keys, [&](size_t c) {
    std::uint32_t* h = histograms.data() + c * Buckets;
    ForCandidatesOfChunk(keys, alive, c, [&](size_t, std::uint32_t bits) { ++h[bits >> BucketShift]; });
  });
  return histograms;
}

// The pass's limit for a goal key, as a float.
float PassLimit(float goalKey, double factor, float floor)
{
  const double limit = std::max<double>(floor, factor * double(goalKey));
  return static_cast<float>(std::min<double>(limit, std::numeric_limits<float>::max()));
}

float BitsKey(std::uint32_t bits)
{
  float key = 0.0f;
  std::memcpy(&key, &bits, sizeof(key));
  return key;
}

// One sweep over the keys: per chunk, the candidates with key bits <= bound as rank entries (in
// index order) and the key bits that fall in `bucket` (none when bucket is Buckets).
void CollectUnder(const std::vector<float>& keys, const unsigned char* alive, std::uint32_t bound, size_t bucket,
  std::vector<std::vector<std::uint64_t>>& parts, std::vector<std::vector<std::uint32_t>>& inBucket)
{
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
  parts.assign(chunks, {});
  inBucket.assign(chunks, {});
  ForChunks(keys, [&](size_t c) {
    ForCandidatesOfChunk(keys, alive, c, [&](size_t i, std::uint32_t bits) {
      if ((bits >> BucketShift) == bucket)
      {
        inBucket[c].push_back(bits);
      }
      if (bits <= bound)
      {
        // Key bits (high 32) and element index (low 32): the order of PassRanking::Order.
        parts[c].push_back((std::uint64_t(bits) << 32) | std::uint64_t(static_cast<std::uint32_t>(i)));
      }
    });
  });
}
} // namespace


void RankPassCandidates(const std::vector<float>& keys, const unsigned char* alive, Index goalRank, double factor,
  float floor, PassRanking& ranking)
{
  // In parallel over fixed chunks: a histogram of the keys' top bits (which also counts the
  // candidates) finds the bucket of the goal rank; one sweep then collects the keys of that bucket
  // and every candidate under the largest limit a key of that bucket can give (session 27: before,
  // a second sweep collected the candidates once the goal key was known); the goal key is selected
  // among its bucket's keys, the collected entries over its limit dropped, the rest sorted. The
  // same ranking as an nth_element and a partition of all candidates, for any thread count.
  const std::vector<std::uint32_t> histograms = ChunkHistograms(keys, alive);
  const size_t chunks = (keys.size() + RankChunk - 1) / RankChunk;
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
  ranking.Candidates = static_cast<Index>(total);
  ranking.Limit = std::numeric_limits<float>::infinity();
  std::uint32_t limitBits = KeyBits(std::numeric_limits<float>::max());
  const bool selects = goalRank >= 0 && size_t(goalRank) < total;
  size_t bucket = Buckets, below = 0;
  std::uint32_t bound = limitBits;
  if (selects)
  {
    for (bucket = 0; below + counts[bucket] <= size_t(goalRank); ++bucket)
    {
      below += counts[bucket];
    }
    // The limit is monotone in the goal key (either way, whatever the factor's sign): the larger of
    // the limits of the bucket's smallest and largest keys bounds it.
    const std::uint32_t lowest = std::uint32_t(bucket) << BucketShift;
    const std::uint32_t highest = lowest | ((std::uint32_t(1) << BucketShift) - 1);
    const float a = PassLimit(BitsKey(lowest), factor, floor), b = PassLimit(BitsKey(highest), factor, floor);
    bound = std::isnan(a) || std::isnan(b) ? bound : std::min(bound, std::max(KeyBits(a), KeyBits(b)));
  }
  std::vector<std::vector<std::uint64_t>> parts;
  std::vector<std::vector<std::uint32_t>> inBucket;
  CollectUnder(keys, alive, bound, bucket, parts, inBucket);
  if (selects)
  {
    std::vector<std::uint32_t> bits;
    bits.reserve(counts[bucket]);
    for (const auto& part : inBucket)
    {
      bits.insert(bits.end(), part.begin(), part.end());
    }
    std::nth_element(bits.begin(), bits.begin() + (size_t(goalRank) - below), bits.end());
    ranking.Limit = PassLimit(BitsKey(bits[size_t(goalRank) - below]), factor, floor);
    limitBits = KeyBits(ranking.Limit);
  }
  std::vector<size_t> offset(chunks + 1, 0);
  ForChunks(keys, [&](size_t c) {
    auto& part = parts[c];
    part.erase(std::remove_if(part.begin(), part.end(), [&](std::uint64_t e) { return (e >> 32) > limitBits; }),
      part.end());
  });
  for (size_t c = 0; c < chunks; ++c)
  {
    offset[c + 1] = offset[c] + parts[c].size();
  }
  ranking.Order.resize(offset[chunks]);
  ForChunks(keys, [&](size_t c) { std::copy(parts[c].begin(), parts[c].end(), ranking.Order.begin() + offset[c]); });
  ranking.Everything = Index(ranking.Order.size()) == ranking.Candidates;
  // A total order (key, then index): the same result whatever sort and thread count.
  vtkSMPTools::Sort(ranking.Order.begin(), ranking.Order.end());
}
} // namespace slod
