// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: triangulation of simple polygons in 3D by ear clipping.
//
// The polygon is projected on the plane orthogonal to a given normal (pass the Newell normal for a
// general polygon, or a patch normal). Ears are clipped smallest interior angle first, which avoids
// slivers. An ear is valid when its corner is convex in projection, no other polygon vertex lies in
// it and its diagonal crosses no polygon edge; callers may add their own test (AcceptEar, e.g.
// "this diagonal is not already an edge elsewhere in the mesh"). When the projection is not simple
// (no valid ear is left), the remaining polygon is by default finished by clipping the best
// remaining convex corner, so the result always covers the polygon with exactly n - 2 triangles
// (never a hole); with AllowFallback off the call stops instead and reports Failed.
// Cost: O(n^2) for simple polygons (ear status is cached and only refreshed next to a clipped ear,
// with a full rescan before giving up).
#ifndef slodPolygonTriangulation_h
#define slodPolygonTriangulation_h

#include "slodTriangleMesh.h"

#include <array>
#include <functional>
#include <vector>

namespace slod
{
// Newell normal of a closed polygon (unnormalised; zero for degenerate polygons).
SURFACELODFILTERS_EXPORT Vec3 PolygonNormal(const std::vector<Vec3>& polygon);

struct PolygonTriangulationResult
{
  std::vector<std::array<Index, 3>> Triangles; // indices into the polygon, same orientation
  bool UsedFallback = false;                   // some ear was not valid in projection
  bool Failed = false; // AllowFallback off and no acceptable ear left: Triangles is incomplete
};

struct PolygonTriangulationOptions
{
  // Extra test of a candidate ear (previous, corner, next: polygon indices); false rejects it.
  std::function<bool(Index, Index, Index)> AcceptEar;
  // No valid ear left: clip the most convex corner anyway (true) or stop with Failed (false).
  bool AllowFallback = true;
};

SURFACELODFILTERS_EXPORT PolygonTriangulationResult TriangulatePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal);
SURFACELODFILTERS_EXPORT PolygonTriangulationResult TriangulatePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal, const PolygonTriangulationOptions& options);

// Triangulation of a simple polygon that minimises a per-diagonal cost (dynamic programming over
// all valid diagonals, O(n^3) time, O(n^2) memory: meant for small polygons). A diagonal is valid
// when it lies inside the polygon in projection (cone test at both ends), crosses no polygon edge,
// passes through no other vertex and AcceptDiagonal (optional) accepts it; every triangle must be
// counter-clockwise in projection and not degenerate. The result minimises the largest cost of a
// used diagonal, then the sum of the used diagonals' costs plus a small penalty for thin
// triangles (AngleWeight times the sum of (1 - sin of the smallest angle), in cost units).
// A triangle turned away from `normal` by more than the angle of cosine FoldedTriangleCosine
// stands across the polygon's plane (three points of a curved crease chain whose diagonal lies on
// the face beyond the crease, where its distance from the surface reads zero): its extent along
// `normal` counts as a cost too, in the largest and in the sum (off by default).
// Strict: Failed (and no triangles) when no valid triangulation exists.
struct MinimumCostTriangulationOptions
{
  std::function<bool(Index, Index)> AcceptDiagonal; // polygon indices i < j
  std::function<double(Index, Index)> DiagonalCost; // polygon indices i < j; >= 0; null = 0
  double AngleWeight = 0.0;
  double FoldedTriangleCosine = -1.0; // -1: no triangle counts as folded
};
SURFACELODFILTERS_EXPORT PolygonTriangulationResult TriangulatePolygonMinimumCost(
  const std::vector<Vec3>& polygon, const Vec3& normal, const MinimumCostTriangulationOptions& options);
} // namespace slod

#endif
