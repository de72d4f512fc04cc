#include "slodPolygonTriangulation.h"

#include <cmath>
#include <limits>

namespace slod
{
Vec3 PolygonNormal(const std::vector<Vec3>& polygon)
{
  Vec3 n{ 0, 0, 0 };
  const size_t count = polygon.size();
  for (size_t i = 0; i < count; ++i)
  {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % count];
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  return n;
}

namespace
{
using Vec2 = std::array<double, 2>;

double Cross2(const Vec2& o, const Vec2& a, const Vec2& b)
{
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

bool InsideTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c)
{
  return Cross2(a, b, p) >= 0 && Cross2(b, c, p) >= 0 && Cross2(c, a, p) >= 0;
}

// Interior angle at b of the corner a-b-c of a counter-clockwise polygon: the counter-clockwise
// turn from (c - b) to (a - b), in [0, 2pi).
double CornerAngle(const Vec2& a, const Vec2& b, const Vec2& c)
{
  const double ux = c[0] - b[0], uy = c[1] - b[1], wx = a[0] - b[0], wy = a[1] - b[1];
  const double angle = std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
  return angle < 0 ? angle + 2 * M_PI : angle;
}
} // namespace

PolygonTriangulationResult TriangulatePolygon(const std::vector<Vec3>& polygon, const Vec3& normal)
{
  PolygonTriangulationResult result;
  const size_t n = polygon.size();
  if (n < 3)
  {
    return result;
  }
  // Orthonormal frame (u, v) of the projection plane, oriented by the normal.
  const Vec3 w = Normalized(normal);
  const Vec3 helper = std::fabs(w[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  const Vec3 u = Normalized(Cross(helper, w));
  const Vec3 v = Cross(w, u);
  std::vector<Vec2> p(n);
  for (size_t i = 0; i < n; ++i)
  {
    p[i] = { Dot(polygon[i], u), Dot(polygon[i], v) };
  }
  std::vector<size_t> ring(n);
  for (size_t i = 0; i < n; ++i)
  {
    ring[i] = i;
  }
  auto isEar = [&](size_t k) {
    const size_t m = ring.size();
    const Vec2& a = p[ring[(k + m - 1) % m]];
    const Vec2& b = p[ring[k]];
    const Vec2& c = p[ring[(k + 1) % m]];
    if (Cross2(a, b, c) <= 0)
    {
      return false; // reflex or flat corner
    }
    for (size_t j = 0; j < m; ++j)
    {
      if (j == k || j == (k + 1) % m || j == (k + m - 1) % m)
      {
        continue;
      }
      const Vec2& q = p[ring[j]];
      if ((q[0] == a[0] && q[1] == a[1]) || (q[0] == b[0] && q[1] == b[1]) || (q[0] == c[0] && q[1] == c[1]))
      {
        continue; // a repeated point of the boundary does not block the ear
      }
      if (InsideTriangle(q, a, b, c))
      {
        return false;
      }
    }
    return true;
  };
  while (ring.size() > 3)
  {
    const size_t m = ring.size();
    size_t best = m;
    double bestAngle = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < m; ++k)
    {
      if (!isEar(k))
      {
        continue;
      }
      const double angle = CornerAngle(p[ring[(k + m - 1) % m]], p[ring[k]], p[ring[(k + 1) % m]]);
      if (angle < bestAngle)
      {
        bestAngle = angle;
        best = k;
      }
    }
    if (best == m)
    {
      // Not simple in projection: clip the most convex corner (largest signed area) anyway.
      result.UsedFallback = true;
      double bestArea = -std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < m; ++k)
      {
        const double area = Cross2(p[ring[(k + m - 1) % m]], p[ring[k]], p[ring[(k + 1) % m]]);
        if (area > bestArea)
        {
          bestArea = area;
          best = k;
        }
      }
    }
    result.Triangles.push_back({ static_cast<Index>(ring[(best + m - 1) % m]), static_cast<Index>(ring[best]),
      static_cast<Index>(ring[(best + 1) % m]) });
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(best));
  }
  result.Triangles.push_back(
    { static_cast<Index>(ring[0]), static_cast<Index>(ring[1]), static_cast<Index>(ring[2]) });
  return result;
}
} // namespace slod
