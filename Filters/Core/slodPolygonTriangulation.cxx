// SPDX-License-Identifier: BSD-3-Clause
#include "slodPolygonTriangulation.h"

#include "slodIndexedHeap.h"

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

// No triangle for fewer than 3 corners: a failure unless the polygon is empty.
bool FewerThanThreeCorners(const std::vector<Vec3>& polygon, PolygonTriangulationResult& result)
{
  if (polygon.size() >= 3)
  {
    return false;
  }
  result.Failed = !polygon.empty();
  return true;
}

// Distances below this count as zero: 1e-9 of the projected polygon's extent.
double ProjectedTolerance(const std::vector<Vec2>& p)
{
  double extent = 0;
  for (size_t i = 0; i < p.size(); ++i)
  {
    extent = std::max({ extent, std::fabs(p[i][0] - p[0][0]), std::fabs(p[i][1] - p[0][1]) });
  }
  return 1e-9 * extent;
}

// Proper crossing of segments ab and cd (touching at shared endpoints does not count).
bool SegmentsCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d)
{
  const double d1 = Cross2(a, b, c), d2 = Cross2(a, b, d), d3 = Cross2(c, d, a), d4 = Cross2(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}
// Ear clipping of a polygon projected onto its plane: the ear of smallest angle first (a heap
// validated by per-corner versions), a rescan when the heap runs dry, and in fallback mode the
// most convex corner when no ear is left.
class EarClipper
{
public:
  EarClipper(const std::vector<Vec3>& polygon, const Vec3& normal, const PolygonTriangulationOptions& options,
    PolygonTriangulationResult& result)
    : Polygon(polygon)
    , Options(options)
    , Result(result)
    , P(ProjectOntoPlane(polygon, normal))
    , Size(polygon.size())
    , Prev(polygon.size())
    , Next(polygon.size())
    , Removed(polygon.size(), 0)
    , Remaining(polygon.size())
  {
    this->Ears.Reset(static_cast<Index>(polygon.size()));
    const size_t n = this->Size;
    // Doubly linked ring of remaining corners.
    for (size_t i = 0; i < n; ++i)
    {
      this->Prev[i] = (i + n - 1) % n;
      this->Next[i] = (i + 1) % n;
    }
    // Distances below this (relative to the polygon's size) count as zero in strict mode.
    this->Tolerance = ProjectedTolerance(this->P);
  }

  // Fills the result; false when strict mode fails.
  bool Run()
  {
    this->Rescan();
    bool rescanned = true;
    while (this->Remaining > 3)
    {
      size_t best = this->PopBestEar();
      if (best == this->Size)
      {
        if (!rescanned)
        {
          this->Rescan(); // far corners may have become ears since their last test
          rescanned = true;
          continue;
        }
        if (!this->Options.AllowFallback)
        {
          return false;
        }
        // Not simple in projection: clip the most convex corner anyway.
        this->Result.UsedFallback = true;
        best = this->MostConvexCorner();
      }
      const size_t a = this->Prev[best], c = this->Next[best];
      this->Clip(best);
      rescanned = false;
      this->Refresh(a);
      this->Refresh(c);
    }
    return this->AddLastTriangle();
  }

private:
  bool IsEar(size_t k) const
  {
    const std::vector<Vec2>& p = this->P;
    const size_t ia = this->Prev[k], ic = this->Next[k];
    const Vec2& a = p[ia];
    const Vec2& b = p[k];
    const Vec2& c = p[ic];
    if (Cross2(a, b, c) <= 0)
    {
      return false; // reflex or flat corner
    }
    const bool strict = !this->Options.AllowFallback;
    if (strict && IsDegenerate(this->Polygon[ia], this->Polygon[k], this->Polygon[ic]))
    {
      return false; // strict mode: no (numerically) zero-area triangle
    }
    for (size_t j = this->Next[ic]; j != ia; j = this->Next[j])
    {
      const Vec2& q = p[j];
      const bool repeated =
        (q[0] == a[0] && q[1] == a[1]) || (q[0] == b[0] && q[1] == b[1]) || (q[0] == c[0] && q[1] == c[1]);
      // A repeated point of the boundary does not block the ear. In strict mode a point (almost)
      // on the diagonal blocks it too: clipping there would leave a collinear, unclippable rest.
      if (!repeated && (InsideTriangle(q, a, b, c) || (strict && NearSegment(q, a, c, this->Tolerance))))
      {
        return false;
      }
      // The diagonal a-c must not cross an edge of the remaining polygon.
      if (SegmentsCross(a, c, q, p[this->Next[j]]))
      {
        return false;
      }
    }
    return !this->Options.AcceptEar ||
      this->Options.AcceptEar(static_cast<Index>(ia), static_cast<Index>(k), static_cast<Index>(ic));
  }

  double AngleOf(size_t k) const { return CornerAngle(this->P[this->Prev[k]], this->P[k], this->P[this->Next[k]]); }

  void Refresh(size_t k)
  {
    if (this->IsEar(k))
    {
      this->Ears.Set(static_cast<Index>(k), this->AngleOf(k));
    }
    else
    {
      this->Ears.Remove(static_cast<Index>(k));
    }
  }

  void Rescan()
  {
    this->Ears.Clear();
    size_t k = this->Start;
    for (size_t i = 0; i < this->Remaining; ++i, k = this->Next[k])
    {
      this->Refresh(k);
    }
  }

  // The valid ear of smallest angle (Size: none in the heap).
  size_t PopBestEar()
  {
    // Clipped corners are never in the heap: a corner is clipped only after it is popped.
    return this->Ears.Empty() ? this->Size : static_cast<size_t>(this->Ears.Pop());
  }

  // The corner of largest signed area.
  size_t MostConvexCorner() const
  {
    size_t best = this->Size;
    double bestArea = -std::numeric_limits<double>::infinity();
    size_t k = this->Start;
    for (size_t i = 0; i < this->Remaining; ++i, k = this->Next[k])
    {
      const double area = Cross2(this->P[this->Prev[k]], this->P[k], this->P[this->Next[k]]);
      if (area > bestArea)
      {
        bestArea = area;
        best = k;
      }
    }
    return best;
  }

  void Clip(size_t k)
  {
    this->Result.Triangles.push_back(
      { static_cast<Index>(this->Prev[k]), static_cast<Index>(k), static_cast<Index>(this->Next[k]) });
    this->Next[this->Prev[k]] = this->Next[k];
    this->Prev[this->Next[k]] = this->Prev[k];
    this->Removed[k] = 1;
    this->Start = this->Next[k];
    --this->Remaining;
  }

  // The last triangle adds no diagonal; in strict mode it must still be counter-clockwise.
  bool AddLastTriangle()
  {
    const size_t a = this->Start, b = this->Next[a], c = this->Next[b];
    if (!this->Options.AllowFallback &&
      (Cross2(this->P[a], this->P[b], this->P[c]) <= 0 ||
        IsDegenerate(this->Polygon[a], this->Polygon[b], this->Polygon[c])))
    {
      return false;
    }
    this->Result.Triangles.push_back({ static_cast<Index>(a), static_cast<Index>(b), static_cast<Index>(c) });
    return true;
  }

  const std::vector<Vec3>& Polygon;
  const PolygonTriangulationOptions& Options;
  PolygonTriangulationResult& Result;
  const std::vector<Vec2> P;
  const size_t Size;
  std::vector<size_t> Prev, Next;
  std::vector<char> Removed;
  size_t Remaining;
  size_t Start = 0; // some remaining corner
  double Tolerance = 0;
  IndexedHeap<double> Ears; // current ears by angle, ties by corner
};
} // namespace

PolygonTriangulationResult TriangulatePolygon(const std::vector<Vec3>& polygon, const Vec3& normal)
{
  return TriangulatePolygon(polygon, normal, PolygonTriangulationOptions());
}

PolygonTriangulationResult TriangulatePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal, const PolygonTriangulationOptions& options)
{
  PolygonTriangulationResult result;
  if (FewerThanThreeCorners(polygon, result))
  {
    return result;
  }
  EarClipper clipper(polygon, normal, options, result);
  result.Failed = !clipper.Run();
  return result;
}

namespace
{
// Diagonal validity and cost of a polygon, an n x n table (symmetric); polygon edges are valid with
// cost 0.
struct DiagonalTable
{
  size_t N;
  std::vector<char> Valid;
  std::vector<double> Cost;

  explicit DiagonalTable(size_t n)
    : N(n)
    , Valid(n * n, 0)
    , Cost(n * n, 0.0)
  {
  }
  size_t At(size_t i, size_t j) const { return i * this->N + j; }
};

// Whether the diagonal from corner i towards corner j starts inside the polygon (within the cone of
// its two edges at i).
bool InCone(const std::vector<Vec2>& p, size_t i, size_t j)
{
  const size_t n = p.size();
  const Vec2& a = p[(i + n - 1) % n];
  const Vec2& b = p[(i + 1) % n];
  if (Cross2(a, p[i], b) >= 0) // convex corner
  {
    return Cross2(p[i], p[j], a) > 0 && Cross2(p[j], p[i], b) > 0;
  }
  return !(Cross2(p[i], p[j], b) >= 0 && Cross2(p[j], p[i], a) >= 0);
}

// A diagonal is valid inside the polygon, passes near no other corner, crosses no edge and is
// accepted by the caller.
DiagonalTable ValidDiagonals(const std::vector<Vec2>& p, const MinimumCostTriangulationOptions& options)
{
  const size_t n = p.size();
  const double tolerance = ProjectedTolerance(p);
  DiagonalTable table(n);
  for (size_t i = 0; i < n; ++i)
  {
    table.Valid[table.At(i, (i + 1) % n)] = table.Valid[table.At((i + 1) % n, i)] = 1;
  }
  for (size_t i = 0; i + 2 < n; ++i)
  {
    for (size_t j = i + 2; j < n; ++j)
    {
      if (i == 0 && j == n - 1)
      {
        continue;
      }
      bool ok = InCone(p, i, j) && InCone(p, j, i);
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
        table.Valid[table.At(i, j)] = table.Valid[table.At(j, i)] = 1;
        table.Cost[table.At(i, j)] = table.Cost[table.At(j, i)] =
          options.DiagonalCost ? options.DiagonalCost(static_cast<Index>(i), static_cast<Index>(j)) : 0.0;
      }
    }
  }
  return table;
}

// 1 - sin of the smallest angle of triangle abc (sin = twice the area over the product of the two
// longest edges): 0 for an equilateral triangle, 1 for a flat one.
double Thinness(const std::vector<Vec3>& polygon, size_t a, size_t b, size_t c)
{
  const double area2 = Norm(Cross(polygon[b] - polygon[a], polygon[c] - polygon[a]));
  const double l0 = Norm(polygon[b] - polygon[a]), l1 = Norm(polygon[c] - polygon[b]), l2 = Norm(polygon[a] - polygon[c]);
  const double longest = std::max({ l0, l1, l2 });
  const double middle = l0 + l1 + l2 - longest - std::min({ l0, l1, l2 });
  return longest * middle > 0 ? 1.0 - area2 / (longest * middle) : 1.0;
}

// The extent along the unit `normal` of triangle abc when it is turned away from it by more than
// the angle of cosine foldedCosine (it stands across the polygon's plane), 0 otherwise.
double FoldedHeight(const std::vector<Vec3>& polygon, size_t a, size_t b, size_t c, const Vec3& normal,
  double foldedCosine)
{
  const Vec3 n = Cross(polygon[b] - polygon[a], polygon[c] - polygon[a]);
  if (Dot(n, normal) >= foldedCosine * Norm(n))
  {
    return 0.0;
  }
  const double ha = Dot(polygon[a], normal), hb = Dot(polygon[b], normal), hc = Dot(polygon[c], normal);
  return std::max({ ha, hb, hc }) - std::min({ ha, hb, hc });
}

// Dynamic programme over sub-polygons i, i+1, ..., j closed by the edge (i, j): the smallest
// maximum cost (diagonals, folded triangles' heights), then the smallest sum (costs plus weighted
// thinness). Returns the best apex k of every (i, j) (-1: none).
std::vector<Index> MinimumCostSplits(const std::vector<Vec3>& polygon, const std::vector<Vec2>& p,
  const DiagonalTable& table, const Vec3& normal, const MinimumCostTriangulationOptions& options)
{
  const double angleWeight = options.AngleWeight;
  const bool foldsCount = options.FoldedTriangleCosine > -1.0;
  const size_t n = p.size();
  auto at = [&table](size_t i, size_t j) { return table.At(i, j); };
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> bestMax(n * n, infinity), bestSum(n * n, infinity);
  std::vector<Index> split(n * n, -1);
  for (size_t i = 0; i + 1 < n; ++i)
  {
    bestMax[at(i, i + 1)] = bestSum[at(i, i + 1)] = 0;
  }
  for (size_t length = 2; length < n; ++length)
  {
    for (size_t i = 0; i + length < n; ++i)
    {
      const size_t j = i + length;
      if (!table.Valid[at(i, j)])
      {
        continue;
      }
      double& bm = bestMax[at(i, j)];
      double& bs = bestSum[at(i, j)];
      for (size_t k = i + 1; k < j; ++k)
      {
        if (!table.Valid[at(i, k)] || !table.Valid[at(k, j)] || bestMax[at(i, k)] == infinity ||
          bestMax[at(k, j)] == infinity)
        {
          continue;
        }
        if (Cross2(p[i], p[k], p[j]) <= 0 || IsDegenerate(polygon[i], polygon[k], polygon[j]))
        {
          continue;
        }
        const double cik = table.Cost[at(i, k)], ckj = table.Cost[at(k, j)];
        const double fold = foldsCount ? FoldedHeight(polygon, i, k, j, normal, options.FoldedTriangleCosine) : 0.0;
        const double m = std::max({ bestMax[at(i, k)], bestMax[at(k, j)], cik, ckj, fold });
        const double sum =
          bestSum[at(i, k)] + bestSum[at(k, j)] + cik + ckj + fold + angleWeight * Thinness(polygon, i, k, j);
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
  return split;
}
} // namespace

PolygonTriangulationResult TriangulatePolygonMinimumCost(
  const std::vector<Vec3>& polygon, const Vec3& normal, const MinimumCostTriangulationOptions& options)
{
  PolygonTriangulationResult result;
  if (FewerThanThreeCorners(polygon, result))
  {
    return result;
  }
  const size_t n = polygon.size();
  const std::vector<Vec2> p = ProjectOntoPlane(polygon, normal);
  const DiagonalTable table = ValidDiagonals(p, options);
  const std::vector<Index> split = MinimumCostSplits(polygon, p, table, Normalized(normal), options);
  if (split[table.At(0, n - 1)] < 0)
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
    const size_t k = static_cast<size_t>(split[table.At(i, j)]);
    result.Triangles.push_back({ static_cast<Index>(i), static_cast<Index>(k), static_cast<Index>(j) });
    stack.push_back({ i, k });
    stack.push_back({ k, j });
  }
  return result;
}
} // namespace slod
