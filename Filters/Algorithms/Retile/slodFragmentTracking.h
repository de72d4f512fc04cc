// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: polygon fragment tracking through vertex removals (Turk 1992,
// section 6.2), the exact correspondence between two nested levels that RetileNested made.
//
// Every high-detail triangle starts as one fragment. The removals that turn the high level into the
// low one (RetilingResult::Removals: half-edge collapses r -> c) are replayed in order; for each:
//  1. LayOutStar: r's star in the plane (a polar map: angles around r scaled to a full turn, or a
//     half turn on a border; radii the edge lengths), or, where the fan from c would fold in that
//     map, the ring on a circle (convex: every fan from a ring vertex is valid);
//  2. the fragments of r's old triangles are split by the hole's new edges (the chords from c) and
//     each piece goes to the new triangle it lies in;
//  3. every fragment vertex of the hole that depended on r (r itself: the removed vertex is
//     flattened onto the new triangle it falls in) is expressed anew in the new triangles.
// Each fragment vertex keeps its high-detail position and its location as weights over the
// current mesh's vertices, so at the end every fragment lies in one low triangle: T = 0 is the low
// level exactly (to rounding) and T = 1 the high level. The paper's coalescing of sibling fragments
// is not done (they stay separate fragments of the same high triangle).
#ifndef slodFragmentTracking_h
#define slodFragmentTracking_h

#include "slodLevelInterpolation.h"

namespace slod
{
// Fills result as InterpolateLevels does (SharedVertices: the low vertices; FlattenedVertices: the
// removed ones; Crossings: the vertices made where a new edge cut a fragment). Fails (Valid false,
// Error set) when a removal cannot be replayed (a vertex not alive or not a neighbour, a star that
// is not a disk, a collapse that breaks the mesh) or when the replay does not give `low` (its
// vertices at the same positions, the same triangles). The records of several levels in a row
// (each in the ids of the level it starts from: a level's vertices are the first vertices of every
// finer level, in the same order) replay as one sequence, so any pair of nested levels is tracked.
// Reports progress (the replay, then the fragments' triangulation); when progress returns false it
// stops with Aborted set (Valid false, no error).
SURFACELODFILTERS_EXPORT void TrackLevels(const TriangleMesh& high, const TriangleMesh& low,
  const std::vector<Index>& removals, LevelInterpolation& result, const ProgressFunction& progress = nullptr);
} // namespace slod

#endif
