// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm TriangleCollapse: the ranking stage of the pass schedule
// (TriangleCollapseOptions::Schedule = CollapseSchedule::Passes).
//
// A pass costs every candidate at once, ranks them by cost and performs an independent set of the
// cheapest in rank order (meshoptimizer's simplifier works in such passes). This file holds the
// ranking, which knows nothing of meshes: per element a float key (its cost; +infinity or NaN: no
// candidate), and the pass takes the elements up to a cost limit, sorted by key and then by index
// so that the order is one total order whatever the number of threads.
#ifndef slodCollapsePasses_h
#define slodCollapsePasses_h

#include "slodTriangleMesh.h" // Index

#include <cstdint>
#include <vector>

namespace slod
{
// One pass's candidates in rank order and the cost limit that selected them.
struct PassRanking
{
  // Key bits (high 32) and element index (low 32): ascending order is cost order, ties by index.
  std::vector<std::uint64_t> Order;
  float Limit = 0.0f;
  // Every finite key is in Order (the limit cut nothing off).
  bool Everything = false;
  Index Candidates = 0; // elements with a finite key
};

inline Index RankedElement(std::uint64_t entry)
{
  return static_cast<Index>(entry & 0xffffffffu);
}

// The limit of a pass, as meshoptimizer's: `factor` times the key of rank `goalRank` among the
// finite keys (many of the cheapest are locked by a neighbour's collapse, hence the factor), but
// never below `floor` (the costliest collapse performed so far: cheaper ones are always worth
// taking). `alive` (optional) says which elements count. Keys must be non-negative.
SURFACELODFILTERS_EXPORT void RankPassCandidates(const std::vector<float>& keys, const unsigned char* alive,
  Index goalRank, double factor, float floor, PassRanking& ranking);
} // namespace slod

#endif
