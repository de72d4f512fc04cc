// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: the plain triangle mesh every algorithm works on.
//
// Flat arrays, no VTK types: points as xyz doubles, triangles as vertex-index triples.
// Algorithms in SurfaceLOD take and return this; VTK conversion lives in slodInputPreparation.
#ifndef slodTriangleMesh_h
#define slodTriangleMesh_h

#include "SurfaceLODFiltersModule.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

namespace slod
{
// 32-bit indices: meshes up to 2^31 elements, half the memory of vtkIdType in hot arrays.
using Index = std::int32_t;
constexpr Index InvalidIndex = -1;

constexpr double Pi = 3.14159265358979323846;
// Angles are given in degrees at the filters' interface and used in radians inside.
constexpr double Radians(double degrees) { return degrees * (Pi / 180.0); } // as vtkMath::RadiansFromDegrees

using Vec3 = std::array<double, 3>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return { a[0] + b[0], a[1] + b[1], a[2] + b[2] }; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return { a[0] - b[0], a[1] - b[1], a[2] - b[2] }; }
inline Vec3 operator*(double s, const Vec3& a) { return { s * a[0], s * a[1], s * a[2] }; }
inline double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 Cross(const Vec3& a, const Vec3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}
inline double Norm(const Vec3& a) { return std::sqrt(Dot(a, a)); }
inline Vec3 Normalized(const Vec3& a)
{
  const double n = Norm(a);
  return n > 0 ? (1.0 / n) * a : Vec3{ 0, 0, 0 };
}
// A unit vector orthogonal to the unit vector `axis` (a frame in the plane `axis` is normal to).
inline Vec3 AnyOrthogonal(const Vec3& axis)
{
  const Vec3 other = std::fabs(axis[0]) < 0.6 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  return Normalized(Cross(axis, other));
}

// The low 21 bits of x spread to every third bit: three of them interleaved (x | y << 1 | z << 2)
// make a 63-bit Morton (Z-order) code, the spatial order of the BVH and of the collapse's vertices.
inline std::uint64_t SpreadBits21(std::uint64_t x)
{
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// A Morton code and the id it belongs to; ordered by code, then id (a total order: the same
// sort for any thread count).
struct MortonEntry
{
  std::uint64_t Code;
  Index Id;
  bool operator<(const MortonEntry& o) const { return this->Code < o.Code || (this->Code == o.Code && this->Id < o.Id); }
};

// Below this many elements the builds that share work out over threads (MortonOrder, the
// TriangleBVH) run on the calling thread: a collapse's local mesh of a few hundred triangles is
// built for each try, and handing it to the SMP backend cost more than the work (a tenth of the
// greedy cuts' final collapses). Same result either way (loops per element, sorts of total orders).
constexpr Index SerialBelow = 2048;

// The positions `centres` (3 doubles each) in Morton order, each axis quantised to 21 bits over
// the box of the finite coordinates (a non-finite one counts as the box's low side): spatially
// coherent, and splitting a sorted range at its highest differing bit halves its cell (the linear
// BVH's build order; the distributed split's pieces).
SURFACELODFILTERS_EXPORT std::vector<MortonEntry> MortonOrder(const std::vector<double>& centres);
// The same order for `count` positions that `centre(id, xyz)` writes on demand (called twice per
// id, possibly from several threads): no array of positions is allocated (a fresh array of a
// large mesh costs more in page faults than computing its entries again).
SURFACELODFILTERS_EXPORT std::vector<MortonEntry> MortonOrder(
  Index count, const std::function<void(Index, double*)>& centre);

// One 64-bit key per undirected edge (smaller vertex id in the high half), for hash sets and sorts.
inline std::uint64_t EdgeKey(Index a, Index b)
{
  return (std::uint64_t(std::uint32_t(a < b ? a : b)) << 32) | std::uint32_t(a < b ? b : a);
}

// Renumbers the vertices that a set of triangles uses, in order of first use: outputs made of
// original vertices keep only those (Used[new] = old, NewIndexOf[old] = new or InvalidIndex).
struct FirstUseNumbering
{
  std::vector<Index> NewIndexOf;
  std::vector<Index> Used;

  explicit FirstUseNumbering(Index numberOfPoints)
    : NewIndexOf(static_cast<size_t>(numberOfPoints), InvalidIndex)
  {
  }
  Index operator()(Index v)
  {
    if (this->NewIndexOf[v] == InvalidIndex)
    {
      this->NewIndexOf[v] = static_cast<Index>(this->Used.size());
      this->Used.push_back(v);
    }
    return this->NewIndexOf[v];
  }
};

struct SURFACELODFILTERS_EXPORT TriangleMesh
{
  std::vector<double> Points;   // 3 per vertex
  std::vector<Index> Triangles; // 3 per triangle, counter-clockwise seen from outside

  Index NumberOfPoints() const { return static_cast<Index>(this->Points.size() / 3); }
  Index NumberOfTriangles() const { return static_cast<Index>(this->Triangles.size() / 3); }

  Vec3 Point(Index v) const
  {
    const double* p = &this->Points[3 * static_cast<size_t>(v)];
    return { p[0], p[1], p[2] };
  }
  void SetPoint(Index v, const Vec3& p)
  {
    double* q = &this->Points[3 * static_cast<size_t>(v)];
    q[0] = p[0];
    q[1] = p[1];
    q[2] = p[2];
  }
  const Index* Triangle(Index t) const { return &this->Triangles[3 * static_cast<size_t>(t)]; }
  Index AddPoint(const Vec3& p)
  {
    // Three push_backs, not a range insert: GCC 12 warns falsely (stringop-overflow) on the latter.
    this->Points.push_back(p[0]);
    this->Points.push_back(p[1]);
    this->Points.push_back(p[2]);
    return this->NumberOfPoints() - 1;
  }
  Index AddTriangle(Index a, Index b, Index c)
  {
    this->Triangles.push_back(a);
    this->Triangles.push_back(b);
    this->Triangles.push_back(c);
    return this->NumberOfTriangles() - 1;
  }

  // Unnormalised normal (twice the area times the unit normal).
  Vec3 TriangleAreaVector(Index t) const;
  double TriangleArea(Index t) const { return 0.5 * Norm(this->TriangleAreaVector(t)); }
  // Axis-aligned bounds as {xmin,xmax,ymin,ymax,zmin,zmax} of the used and unused points alike.
  std::array<double, 6> Bounds() const;
  double BoundingBoxDiagonal() const;
  double TotalArea() const;

  // Drops points no triangle uses and renumbers; newToOld (optional) gets the old index of each kept point.
  void RemoveUnusedPoints(std::vector<Index>* newToOld = nullptr);
};

// Geometry helpers on raw coordinates, shared by every algorithm.
SURFACELODFILTERS_EXPORT Vec3 TriangleNormal(const Vec3& a, const Vec3& b, const Vec3& c);
// Smallest interior angle in radians (0 for degenerate triangles).
SURFACELODFILTERS_EXPORT double MinimumAngle(const Vec3& a, const Vec3& b, const Vec3& c);
// True when the triangle has (numerically) zero area relative to its longest edge.
SURFACELODFILTERS_EXPORT bool IsDegenerate(const Vec3& a, const Vec3& b, const Vec3& c, double relativeTolerance = 1e-12);
// IsDegenerate for a caller that has the norm of Cross(b - a, c - a) already (twice the area):
// the same test, without a second cross product and square root.
inline bool IsDegenerateWithArea(
  const Vec3& a, const Vec3& b, const Vec3& c, double twiceArea, double relativeTolerance = 1e-12)
{
  const double l2 = std::max({ Dot(b - a, b - a), Dot(c - b, c - b), Dot(a - c, a - c) });
  return l2 == 0 || twiceArea <= relativeTolerance * l2;
}
} // namespace slod

#endif
