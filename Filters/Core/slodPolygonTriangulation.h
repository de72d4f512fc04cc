// SurfaceLOD shared core: triangulation of simple polygons in 3D by ear clipping.
//
// The polygon is projected on the plane orthogonal to a given normal (pass the Newell normal for a
// general polygon, or a patch normal). Ears are clipped smallest interior angle first, which avoids
// slivers. When the projection is not simple (no valid ear is left), the remaining polygon is
// finished by clipping the best remaining convex corner, so the result always covers the polygon
// with exactly n - 2 triangles (never a hole).
#ifndef slodPolygonTriangulation_h
#define slodPolygonTriangulation_h

#include "slodTriangleMesh.h"

#include <array>
#include <vector>

namespace slod
{
// Newell normal of a closed polygon (unnormalised; zero for degenerate polygons).
SURFACELODFILTERS_EXPORT Vec3 PolygonNormal(const std::vector<Vec3>& polygon);

struct PolygonTriangulationResult
{
  std::vector<std::array<Index, 3>> Triangles; // indices into the polygon, same orientation
  bool UsedFallback = false;                   // some ear was not valid in projection
};

SURFACELODFILTERS_EXPORT PolygonTriangulationResult TriangulatePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal);
} // namespace slod

#endif
