// SPDX-License-Identifier: BSD-3-Clause
// Topological noise removal (Guskov & Wood 2001): finding short loops around handles.
//
// A geodesic region grows from a seed vertex (Dijkstra over edge lengths). While it stays a
// topological disk, the neighbours of each newly settled vertex that are already settled form one
// arc of its link. Two arcs or more mean that two parts of the front meet at the vertex: the
// region closes a cycle, around a handle, a tunnel or merely a bump not covered yet. The cycle
// (the two shortest paths from the seed to the meeting vertex's two arcs) is a candidate loop;
// CuttableMesh::TestSeparation then tells handles (non-separating) from the rest.
//
// Work bounds: a growth stops at its radius or after MaximumSettled vertices, and records at most
// MaximumLoops candidates; seeds are spaced so that balls of radius SeedSpacing cover the mesh.
#ifndef slodHandleDetection_h
#define slodHandleDetection_h

#include "slodCuttableMesh.h"
#include "slodIndexedHeap.h"

#include <utility>
#include <vector>

namespace slod
{
struct CandidateLoop
{
  std::vector<Index> Vertices; // closed loop, first not repeated
  double Length = 0.0;
};

struct RegionGrowthLimits
{
  double Radius = 0.0;            // geodesic radius of a region
  double MaximumLoopLength = 0.0; // longer candidates are not recorded
  Index MaximumSettled = 100000;  // vertices per region
  int MaximumLoops = 64;          // candidates per region
};

// Per-thread state of the growths: vertex and triangle arrays sized once, reset through the
// lists of what a growth touched (so a growth costs what it visits, not the mesh size).
class SURFACELODFILTERS_EXPORT GeodesicRegion
{
public:
  // Settles vertices from `sources` (distance 0) in order of distance up to `radius` (and at most
  // `maximumSettled`), never through locked vertices; calls settle(v) for each, which returns false
  // to stop. Returns the number settled.
  template <typename Settle>
  Index Grow(const CuttableMesh& mesh, const std::vector<Index>& sources, double radius, Index maximumSettled,
    Settle&& settle);
  // The candidate loops met while growing from `seed` (appended to `loops`).
  void FindLoops(const CuttableMesh& mesh, Index seed, const RegionGrowthLimits& limits, std::vector<CandidateLoop>& loops);

  double Distance(Index v) const { return this->Dist[v]; }

private:
  void Reset(const CuttableMesh& mesh);
  bool Settled(Index v) const { return this->State[v] & SettledFlag; }
  Index FrontMeeting(const CuttableMesh& mesh, Index v);
  bool LoopThrough(Index a, Index b, const CuttableMesh& mesh, CandidateLoop& loop) const;

  enum : unsigned char
  {
    SettledFlag = 1,
    QueuedFlag = 2
  };
  std::vector<double> Dist;
  std::vector<Index> Parent;
  std::vector<unsigned char> State;
  std::vector<Index> TouchedVertices;
  std::vector<std::pair<Index, Index>> Link; // of the vertex being settled: its triangles' far edges
  std::vector<Index> ParentArc;
  IndexedHeap<double> Heap; // unsettled queued vertices by tentative distance, ties by id
};

// Seeds whose balls of radius `spacing` cover every unlocked vertex (greedy, in vertex order).
SURFACELODFILTERS_EXPORT std::vector<Index> CoveringSeeds(const CuttableMesh& mesh, double spacing);

// For each seed, its candidate loops (in parallel, the same result on any number of threads).
SURFACELODFILTERS_EXPORT std::vector<std::vector<CandidateLoop>> FindCandidateLoops(
  const CuttableMesh& mesh, const std::vector<Index>& seeds, const RegionGrowthLimits& limits);

// The seeds within `radius` of any of `changed` (whose regions may differ after a cut).
SURFACELODFILTERS_EXPORT std::vector<Index> SeedsNear(
  const CuttableMesh& mesh, const std::vector<Index>& seeds, const std::vector<Index>& changed, double radius);
} // namespace slod

#endif
