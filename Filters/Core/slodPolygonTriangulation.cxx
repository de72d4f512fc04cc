#include "slodPolygonTriangulation.h"

#include <algorithm>
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

// Coordinates in an orthonormal frame (u, v) of the plane orthogonal to the normal, oriented by it.
std::vector<Vec2> ProjectOntoPlane(const std::vector<Vec3>& polygon, const Vec3& normal)
{
  const Vec3 w = Normalized(normal);
  const Vec3 helper = std::fabs(w[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  const Vec3 u = Normalized(Cross(helper, w));
  const Vec3 v = Cross(w, u);
  std::vector<Vec2> p(polygon.size());
  for (size_t i = 0; i < polygon.size(); ++i)
  {
    p[i] = { Dot(polygon[i], u), Dot(polygon[i], v) };
  }
  return p;
}

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
// True when q lies within `tolerance` of the segment ab (strictly between its ends).
bool NearSegment(const Vec2& q, const Vec2& a, const Vec2& b, double tolerance)
{
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double length2 = dx * dx + dy * dy;
  if (length2 <= 0)
  {
    return false;
  }
  const double t = ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / length2;
  if (t <= 0 || t >= 1)
  {
    return false;
  }
  const double cross = dx * (q[1] - a[1]) - dy * (q[0] - a[0]);
  return cross * cross <= tolerance * tolerance * length2;
}

// Proper crossing of segments ab and cd (touching at shared endpoints does not count).
bool SegmentsCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d)
{
  const double d1 = Cross2(a, b, c), d2 = Cross2(a, b, d), d3 = Cross2(c, d, a), d4 = Cross2(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}
} // namespace

PolygonTriangulationResult TriangulatePolygon(const std::vector<Vec3>& polygon, const Vec3& normal)
{
  return TriangulatePolygon(polygon, normal, PolygonTriangulationOptions());
}

PolygonTriangulationResult TriangulatePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal, const PolygonTriangulationOptions& options)
{
  PolygonTriangulationResult result;
  const size_t n = polygon.size();
  if (n < 3)
  {
    result.Failed = n > 0;
    return result;
  }
  const std::vector<Vec2> p = ProjectOntoPlane(polygon, normal);
  // Doubly linked ring of remaining corners.
  std::vector<size_t> prev(n), next(n);
  for (size_t i = 0; i < n; ++i)
  {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  // Distances below this (relative to the polygon's size) count as zero in strict mode.
  double extent = 0;
  for (size_t i = 0; i < n; ++i)
  {
    extent = std::max({ extent, std::fabs(p[i][0] - p[0][0]), std::fabs(p[i][1] - p[0][1]) });
  }
  const double tolerance = 1e-9 * extent;
  std::vector<char> removed(n, 0);
  size_t remaining = n;
  size_t start = 0; // some remaining corner

  auto isEar = [&](size_t k) {
    const size_t ia = prev[k], ic = next[k];
    const Vec2& a = p[ia];
    const Vec2& b = p[k];
    const Vec2& c = p[ic];
    if (Cross2(a, b, c) <= 0)
    {
      return false; // reflex or flat corner
    }
    if (!options.AllowFallback && IsDegenerate(polygon[ia], polygon[k], polygon[ic]))
    {
      return false; // strict mode: no (numerically) zero-area triangle
    }
    size_t j = next[ic];
    while (j != ia)
    {
      const Vec2& q = p[j];
      const bool repeated =
        (q[0] == a[0] && q[1] == a[1]) || (q[0] == b[0] && q[1] == b[1]) || (q[0] == c[0] && q[1] == c[1]);
      // A repeated point of the boundary does not block the ear. In strict mode a point (almost)
      // on the diagonal blocks it too: clipping there would leave a collinear, unclippable rest.
      if (!repeated && (InsideTriangle(q, a, b, c) || (!options.AllowFallback && NearSegment(q, a, c, tolerance))))
      {
        return false;
      }
      // The diagonal a-c must not cross an edge of the remaining polygon.
      if (SegmentsCross(a, c, q, p[next[j]]))
      {
        return false;
      }
      j = next[j];
    }
    if (options.AcceptEar &&
      !options.AcceptEar(static_cast<Index>(ia), static_cast<Index>(k), static_cast<Index>(ic)))
    {
      return false;
    }
    return true;
  };
  auto angleOf = [&](size_t k) { return CornerAngle(p[prev[k]], p[k], p[next[k]]); };

  // Ears ordered by angle; entries are validated against a per-corner version when popped.
  struct Entry
  {
    double Angle;
    size_t Corner;
    unsigned Version;
    bool operator<(const Entry& o) const
    {
      return this->Angle > o.Angle || (this->Angle == o.Angle && this->Corner > o.Corner);
    }
  };
  std::vector<Entry> heap;
  std::vector<unsigned> version(n, 0);
  auto refresh = [&](size_t k) {
    ++version[k];
    if (isEar(k))
    {
      heap.push_back({ angleOf(k), k, version[k] });
      std::push_heap(heap.begin(), heap.end());
    }
  };
  auto rescan = [&]() {
    heap.clear();
    size_t k = start;
    for (size_t i = 0; i < remaining; ++i, k = next[k])
    {
      refresh(k);
    }
  };
  auto clip = [&](size_t k) {
    result.Triangles.push_back({ static_cast<Index>(prev[k]), static_cast<Index>(k), static_cast<Index>(next[k]) });
    next[prev[k]] = next[k];
    prev[next[k]] = prev[k];
    removed[k] = 1;
    start = next[k];
    --remaining;
  };

  rescan();
  bool rescanned = true;
  while (remaining > 3)
  {
    size_t best = n;
    while (!heap.empty())
    {
      std::pop_heap(heap.begin(), heap.end());
      const Entry e = heap.back();
      heap.pop_back();
      if (!removed[e.Corner] && e.Version == version[e.Corner])
      {
        best = e.Corner;
        break;
      }
    }
    if (best == n)
    {
      if (!rescanned)
      {
        rescan(); // far corners may have become ears since their last test
        rescanned = true;
        continue;
      }
      if (!options.AllowFallback)
      {
        result.Failed = true;
        return result;
      }
      // Not simple in projection: clip the most convex corner (largest signed area) anyway.
      result.UsedFallback = true;
      double bestArea = -std::numeric_limits<double>::infinity();
      size_t k = start;
      for (size_t i = 0; i < remaining; ++i, k = next[k])
      {
        const double area = Cross2(p[prev[k]], p[k], p[next[k]]);
        if (area > bestArea)
        {
          bestArea = area;
          best = k;
        }
      }
    }
    const size_t a = prev[best], c = next[best];
    clip(best);
    rescanned = false;
    refresh(a);
    refresh(c);
  }
  const size_t a = start, b = next[a], c = next[b];
  // The last triangle adds no diagonal; in strict mode it must still be counter-clockwise.
  if (!options.AllowFallback && (Cross2(p[a], p[b], p[c]) <= 0 || IsDegenerate(polygon[a], polygon[b], polygon[c])))
  {
    result.Failed = true;
    return result;
  }
  result.Triangles.push_back({ static_cast<Index>(a), static_cast<Index>(b), static_cast<Index>(c) });
  return result;
}

PolygonTriangulationResult TriangulatePolygonMinimumCost(
  const std::vector<Vec3>& polygon, const Vec3& normal, const MinimumCostTriangulationOptions& options)
{
  PolygonTriangulationResult result;
  const size_t n = polygon.size();
  if (n < 3)
  {
    result.Failed = n > 0;
    return result;
  }
  const std::vector<Vec2> p = ProjectOntoPlane(polygon, normal);
  double extent = 0;
  for (size_t i = 0; i < n; ++i)
  {
    extent = std::max({ extent, std::fabs(p[i][0] - p[0][0]), std::fabs(p[i][1] - p[0][1]) });
  }
  const double tolerance = 1e-9 * extent;
  auto at = [n](size_t i, size_t j) { return i * n + j; };
  // Diagonal validity and cost (i < j); polygon edges are valid with cost 0.
  std::vector<char> valid(n * n, 0);
  std::vector<double> cost(n * n, 0.0);
  auto inCone = [&](size_t i, size_t j) {
    const Vec2& a = p[(i + n - 1) % n];
    const Vec2& b = p[(i + 1) % n];
    if (Cross2(a, p[i], b) >= 0) // convex corner
    {
      return Cross2(p[i], p[j], a) > 0 && Cross2(p[j], p[i], b) > 0;
    }
    return !(Cross2(p[i], p[j], b) >= 0 && Cross2(p[j], p[i], a) >= 0);
  };
  for (size_t i = 0; i < n; ++i)
  {
    valid[at(i, (i + 1) % n)] = valid[at((i + 1) % n, i)] = 1;
  }
  for (size_t i = 0; i + 2 < n; ++i)
  {
    for (size_t j = i + 2; j < n; ++j)
    {
      if (i == 0 && j == n - 1)
      {
        continue;
      }
      bool ok = inCone(i, j) && inCone(j, i);
      for (size_t k = 0; k < n && ok; ++k)
      {
        const size_t k1 = (k + 1) % n;
        if (k != i && k != j && NearSegment(p[k], p[i], p[j], tolerance))
        {
          ok = false;
        }
        else if (k != i && k != j && k1 != i && k1 != j && SegmentsCross(p[i], p[j], p[k], p[k1]))
        {
          ok = false;
        }
      }
      ok = ok && (!options.AcceptDiagonal || options.AcceptDiagonal(static_cast<Index>(i), static_cast<Index>(j)));
      if (ok)
      {
        valid[at(i, j)] = valid[at(j, i)] = 1;
        cost[at(i, j)] = cost[at(j, i)] =
          options.DiagonalCost ? options.DiagonalCost(static_cast<Index>(i), static_cast<Index>(j)) : 0.0;
      }
    }
  }
  // best[i][j]: triangulation of the sub-polygon i, i+1, ..., j closed by the edge (i, j).
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> bestMax(n * n, infinity), bestSum(n * n, infinity);
  std::vector<Index> split(n * n, -1);
  for (size_t i = 0; i + 1 < n; ++i)
  {
    bestMax[at(i, i + 1)] = bestSum[at(i, i + 1)] = 0;
  }
  auto thinness = [&](size_t a, size_t b, size_t c) {
    const double area2 = Norm(Cross(polygon[b] - polygon[a], polygon[c] - polygon[a]));
    const double l0 = Norm(polygon[b] - polygon[a]), l1 = Norm(polygon[c] - polygon[b]),
                 l2 = Norm(polygon[a] - polygon[c]);
    // sin of the smallest angle = area2 / (product of the two longest edges)
    const double longest = std::max({ l0, l1, l2 });
    const double middle = l0 + l1 + l2 - longest - std::min({ l0, l1, l2 });
    return longest * middle > 0 ? 1.0 - area2 / (longest * middle) : 1.0;
  };
  for (size_t length = 2; length < n; ++length)
  {
    for (size_t i = 0; i + length < n; ++i)
    {
      const size_t j = i + length;
      if (!valid[at(i, j)])
      {
        continue;
      }
      double& bm = bestMax[at(i, j)];
      double& bs = bestSum[at(i, j)];
      for (size_t k = i + 1; k < j; ++k)
      {
        if (!valid[at(i, k)] || !valid[at(k, j)] || bestMax[at(i, k)] == infinity ||
          bestMax[at(k, j)] == infinity)
        {
          continue;
        }
        if (Cross2(p[i], p[k], p[j]) <= 0 || IsDegenerate(polygon[i], polygon[k], polygon[j]))
        {
          continue;
        }
        const double m = std::max({ bestMax[at(i, k)], bestMax[at(k, j)], cost[at(i, k)], cost[at(k, j)] });
        const double sum = bestSum[at(i, k)] + bestSum[at(k, j)] + cost[at(i, k)] + cost[at(k, j)] +
          options.AngleWeight * thinness(i, k, j);
        const double slack = 1e-9 * std::max(m, bm == infinity ? 0.0 : bm);
        if (m < bm - slack || (m <= bm + slack && sum < bs))
        {
          bm = m;
          bs = sum;
          split[at(i, j)] = static_cast<Index>(k);
        }
      }
    }
  }
  if (split[at(0, n - 1)] < 0)
  {
    result.Failed = true;
    return result;
  }
  std::vector<std::array<size_t, 2>> stack{ { 0, n - 1 } };
  while (!stack.empty())
  {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2)
    {
      continue;
    }
    const size_t k = static_cast<size_t>(split[at(i, j)]);
    result.Triangles.push_back({ static_cast<Index>(i), static_cast<Index>(k), static_cast<Index>(j) });
    stack.push_back({ i, k });
    stack.push_back({ k, j });
  }
  return result;
}
} // namespace slod
