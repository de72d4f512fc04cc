// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm PatchBoundaryMerge: final half-edge collapses toward a count target that
// the patches alone cannot reach (extension, issue 15; not in Ho 1999).
//
// On rough scans SPBM stops far above an aggressive target (noisy:137: ~71,000 triangles for
// 25,148): the removal's collapses turn most patches into triangles, a triangle patch cannot lose
// a corner, and merging them back makes patches whose every triangulation needs an existing edge,
// which the fallback passes unmerge again (Documentation/PatchBoundaryMerge.md, session 19). The
// level itself has no such limit: its triangles are an ordinary manifold mesh over input vertices.
// So the level is finished by half-edge collapses u -> v (v a level vertex: the output keeps
// original vertices only), cheapest first by the quadric of the planes of the level's and the
// input's triangles around u and v (and planes through the border edges), each accepted only when
// slod::EditableMesh::CheckCollapse keeps the topology (link condition; no loop closes, splits or
// vanishes) and turns no triangle by more than the stage's angle. Vertices of non-manifold edges
// and pinch vertices are locked, border vertices move only along their border edges, so the Euler
// characteristic, the border loops and the non-manifold edges stay the level's (the input's).
// Triangles keep their merged patch; the profile curves follow the collapses (each removed vertex
// replaced by the vertex it went to: a curve stays on the output's edges).
#ifndef slodSpbmFinalCollapses_h
#define slodSpbmFinalCollapses_h

#include "slodPatchBoundaryMerge.h"

#include <algorithm>

namespace slod
{
struct SURFACELODFILTERS_EXPORT SpbmFinalCollapseStatistics
{
  Index StartTriangles = 0;
  Index Vertices = 0; // the level's vertices the collapser was set up over (not the input's)
  Index Collapses = 0;
  long long Attempts = 0;  // CheckCollapse calls
  long long Refused[10] = {}; // by slod::CollapseStatus (NonManifold, BoundaryChange, Flip, ...)
  int Stages = 0;          // normal-turn stages run (each reseeds the queue)
  bool Reached = false;    // the level has at most the target's count (+ 2%) afterwards
  bool WorkBoundReached = false;
};

// How far above its target a level may end without final collapses (2%, at least 2 triangles).
inline Index SpbmFinalCollapseTolerance(Index target)
{
  return std::max<Index>(2, target / 50);
}

// Collapses vertices of `level` (over `mesh`'s points) until it has at most `target` triangles or
// no collapse keeps the topology and the normal bound of the last stage. Deterministic (one queue,
// ties by vertex id), sequential.
SURFACELODFILTERS_EXPORT void SpbmFinalCollapses(
  const TriangleMesh& mesh, Index target, SpbmLevel& level, SpbmFinalCollapseStatistics& statistics);
} // namespace slod

#endif
