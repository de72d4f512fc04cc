// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: Turk's removal of an old vertex with its whole ring re-triangulated
// (Turk 1992, section 4.3), where every fan from a neighbour leaves a tile facing against the
// original surface. The ring is first fanned from a neighbour c (the half-edge collapse r -> c),
// then the fan's edges are flipped while a flip leaves fewer of the ring's tiles facing against
// the surface. Any triangulation of the ring can be reached from a fan by flips; this greedy walk
// finds one facing the surface's way in most rings where a fan does not (the rest keep the fan's
// collapse, as before). Only tried, then undone: the caller performs the collapse and replays the
// flips (so they can be recorded for the nested levels' tracking).
#ifndef slodRetileRing_h
#define slodRetileRing_h

#include "slodEditableMesh.h"

#include <functional>
#include <utility>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT RingRetriangulation
{
  RingRetriangulation(EditableMesh& edit, std::vector<Vec3>& reference)
    : Edit(edit)
    , Reference(reference)
  {
  }

  EditableMesh& Edit;
  // Per vertex: what the original surface faces there. A tile faces the surface's way when its
  // normal's dot with the reference of each of its vertices is above MinimumFacing.
  std::vector<Vec3>& Reference;
  double MinimumFacing = 0.0;
  // Edges that are never flipped (feature lines); may be empty.
  std::function<bool(Index, Index)> IsFixedEdge;

  // Tries removing r by the collapse onto neighbour c (c placed at `position`, its reference
  // normal `targetReference` afterwards), then flips. True when every tile of the new ring faces
  // the surface's way and none is degenerate: `flips` (edges (x, y) to flip in order after the
  // collapse), `smallestAngle` (radians) and `distance` (from r's position to the new ring: how
  // far the surface moved there) are then set. The mesh is left as it was either way.
  bool Try(Index r, Index c, const Vec3& position, const Vec3& targetReference,
    std::vector<std::pair<Index, Index>>& flips, double& smallestAngle, double& distance);

private:
  bool FacesWrong(const Index* tri) const;
  bool FlipLeavesFewerWrong(Index t, Index x, Index y, Index q, Index z) const;
  Index Across(Index t, Index x, Index y) const;
  bool FlipOneWrongTile(std::vector<std::pair<Index, Index>>& flips, std::vector<FlipRecord>& undo);
  std::vector<Index> Ring; // the tiles the collapse changed (same ids through the flips)
  // Scratch reused by every Try (one removal tries several targets): no allocation per try.
  CollapseRecord Collapse;
  std::vector<FlipRecord> Undo;
};
} // namespace slod

#endif
