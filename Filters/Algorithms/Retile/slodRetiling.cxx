// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetiling.h"

#include "slodEditableMesh.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPointGrid.h"
#include "slodRetileCreases.h"
#include "slodRetileFeatures.h"
#include "slodRetileRepair.h"
#include "slodRetileRing.h"
#include "slodTriangleBVH.h"

#include "vtkLogger.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_map>

namespace slod
{
namespace
{
// Portable uniform random numbers: std distributions differ between standard libraries.
struct Random
{
  std::uint64_t State;
  explicit Random(std::uint64_t seed) : State(seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull) {}
  std::uint64_t Next() // splitmix64
  {
    std::uint64_t z = (this->State += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform() { return double(this->Next() >> 11) * (1.0 / 9007199254740992.0); } // [0,1)
};

// Barycentric coordinates of p (assumed in the plane) in triangle abc.
Vec3 Barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 e0 = b - a, e1 = c - a, d = p - a;
  const double d00 = Dot(e0, e0), d01 = Dot(e0, e1), d11 = Dot(e1, e1);
  const double d20 = Dot(d, e0), d21 = Dot(d, e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0))
  {
    return { 1.0 / 3, 1.0 / 3, 1.0 / 3 };
  }
  const double v = (d11 * d20 - d01 * d21) / den;
  const double w = (d00 * d21 - d01 * d20) / den;
  return { 1.0 - v - w, v, w };
}

void VertexNormals(const TriangleMesh& mesh, std::vector<Vec3>& normals)
{
  normals.assign(mesh.NumberOfPoints(), Vec3{ 0, 0, 0 });
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Vec3 n = mesh.TriangleAreaVector(t);
    for (int k = 0; k < 3; ++k)
    {
      normals[mesh.Triangle(t)[k]] = normals[mesh.Triangle(t)[k]] + n;
    }
  }
  for (Vec3& n : normals)
  {
    n = Normalized(n);
  }
}

// The vertex normals of triangle t interpolated with weights w (its face normal where they cancel).
Vec3 InterpolatedNormal(const TriangleMesh& mesh, const std::vector<Vec3>& vertexNormals, Index t, const double* w)
{
  const Index* tri = mesh.Triangle(t);
  Vec3 nrm{ 0, 0, 0 };
  for (int k = 0; k < 3; ++k)
  {
    nrm = nrm + w[k] * vertexNormals[tri[k]];
  }
  return Norm(nrm) > 0 ? Normalized(nrm) : Normalized(mesh.TriangleAreaVector(t));
}

double PointDensity(const TriangleMesh& mesh, const std::vector<double>& vertexDensity, const SurfacePoint& p)
{
  if (vertexDensity.empty() || p.Triangle == InvalidIndex)
  {
    return 1.0;
  }
  const Index* t = mesh.Triangle(p.Triangle);
  const Vec3 b = Barycentric(p.Position, mesh.Point(t[0]), mesh.Point(t[1]), mesh.Point(t[2]));
  double d = 0;
  for (int k = 0; k < 3; ++k)
  {
    d += std::max(0.0, b[k]) * vertexDensity[t[k]];
  }
  const double s = std::max(0.0, b[0]) + std::max(0.0, b[1]) + std::max(0.0, b[2]);
  return s > 0 ? d / s : 1.0;
}

double WeightedArea(const TriangleMesh& mesh, const std::vector<double>& vertexDensity, Index t)
{
  double a = mesh.TriangleArea(t);
  if (!vertexDensity.empty())
  {
    const Index* tri = mesh.Triangle(t);
    a *= (vertexDensity[tri[0]] + vertexDensity[tri[1]] + vertexDensity[tri[2]]) / 3.0;
  }
  return a;
}

// Incircle test in 2D: > 0 when d lies inside the circumcircle of the counter-clockwise abc.
double InCircle(const double* a, const double* b, const double* c, const double* d)
{
  const double adx = a[0] - d[0], ady = a[1] - d[1];
  const double bdx = b[0] - d[0], bdy = b[1] - d[1];
  const double cdx = c[0] - d[0], cdy = c[1] - d[1];
  const double ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
  return adx * (bdy * cd - bd * cdy) - ady * (bdx * cd - bd * cdx) + ad * (bdx * cdy - bdy * cdx);
}

double Orient2D(const double* a, const double* b, const double* c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Splits one original triangle at the candidate points inside it (section 4.2). Local vertices
// 0..2 are the corners; points have already been moved strictly inside. Output triangles are
// counter-clockwise in the triangle's own frame, so they keep the original orientation.
struct TriangleSplitter
{
  std::vector<double> UV;         // 2 per local vertex
  std::vector<Index> Local;       // 3 per local triangle
  std::vector<std::array<Index, 4>> EdgeRefs; // (min, max, triangle, corner opposite)

  void Run(const Vec3* corners, const Vec3* points, int count)
  {
    const Vec3 e1 = Normalized(corners[1] - corners[0]);
    const Vec3 n = Normalized(Cross(corners[1] - corners[0], corners[2] - corners[0]));
    const Vec3 e2 = Cross(n, e1);
    this->UV.clear();
    auto add = [&](const Vec3& p) {
      const Vec3 d = p - corners[0];
      this->UV.push_back(Dot(d, e1));
      this->UV.push_back(Dot(d, e2));
    };
    for (int k = 0; k < 3; ++k)
    {
      add(corners[k]);
    }
    this->Local.assign({ 0, 1, 2 });
    for (int i = 0; i < count; ++i)
    {
      add(points[i]);
      const Index v = static_cast<Index>(this->UV.size() / 2 - 1);
      this->Insert(v);
    }
    this->Delaunay();
  }

  const double* P(Index v) const { return &this->UV[2 * size_t(v)]; }

  void Insert(Index v)
  {
    double* p = &this->UV[2 * size_t(v)];
    size_t best = 0;
    double bestMin = -std::numeric_limits<double>::max();
    for (size_t t = 0; t < this->Local.size() / 3; ++t)
    {
      const Index* tri = &this->Local[3 * t];
      const double area = Orient2D(this->P(tri[0]), this->P(tri[1]), this->P(tri[2]));
      const double b0 = Orient2D(p, this->P(tri[1]), this->P(tri[2])) / area;
      const double b1 = Orient2D(this->P(tri[0]), p, this->P(tri[2])) / area;
      const double b2 = 1.0 - b0 - b1;
      const double m = std::min(b0, std::min(b1, b2));
      if (m > bestMin)
      {
        bestMin = m;
        best = t;
      }
    }
    Index* tri = &this->Local[3 * best];
    if (bestMin < 1e-7)
    {
      // On an edge or a vertex of the local triangulation (coincident or collinear candidate
      // points): nudge into the triangle so every split triangle has a positive area.
      for (int k = 0; k < 2; ++k)
      {
        const double centre = (this->P(tri[0])[k] + this->P(tri[1])[k] + this->P(tri[2])[k]) / 3.0;
        p[k] += 1e-5 * (centre - p[k]);
      }
    }
    const Index a = tri[0], b = tri[1], c = tri[2];
    tri[2] = v;                                    // (a, b, v)
    this->Local.insert(this->Local.end(), { b, c, v });
    this->Local.insert(this->Local.end(), { c, a, v });
  }

  // Lawson flips toward the Delaunay triangulation; the triangle's own edges are never flipped
  // (they are the constraints: only corner pairs, which never form an interior edge).
  void Delaunay()
  {
    const size_t nt = this->Local.size() / 3;
    if (nt < 2)
    {
      return;
    }
    std::vector<unsigned char> touched(nt);
    for (int pass = 0; pass < 64; ++pass)
    {
      this->EdgeRefs.clear();
      for (size_t t = 0; t < nt; ++t)
      {
        for (int k = 0; k < 3; ++k)
        {
          const Index u = this->Local[3 * t + (k + 1) % 3], w = this->Local[3 * t + (k + 2) % 3];
          this->EdgeRefs.push_back({ std::min(u, w), std::max(u, w), Index(t), Index(k) });
        }
      }
      std::sort(this->EdgeRefs.begin(), this->EdgeRefs.end());
      std::fill(touched.begin(), touched.end(), 0);
      int flips = 0;
      for (size_t i = 0; i + 1 < this->EdgeRefs.size(); ++i)
      {
        const auto& r0 = this->EdgeRefs[i];
        const auto& r1 = this->EdgeRefs[i + 1];
        if (r0[0] != r1[0] || r0[1] != r1[1] || touched[r0[2]] || touched[r1[2]])
        {
          continue;
        }
        Index* t0 = &this->Local[3 * size_t(r0[2])];
        Index* t1 = &this->Local[3 * size_t(r1[2])];
        // t0 = (q, x, y) with q opposite; t1 holds (y, x, z).
        const Index q = t0[r0[3]], x = t0[(r0[3] + 1) % 3], y = t0[(r0[3] + 2) % 3];
        const Index z = t1[r1[3]];
        const double scale = std::abs(Orient2D(this->P(q), this->P(x), this->P(y))) +
          std::abs(Orient2D(this->P(z), this->P(y), this->P(x)));
        if (InCircle(this->P(q), this->P(x), this->P(y), this->P(z)) <= 1e-12 * scale * scale)
        {
          continue;
        }
        // The quad must be strictly convex for the flip to keep both triangles positive.
        if (Orient2D(this->P(q), this->P(x), this->P(z)) <= 0 || Orient2D(this->P(z), this->P(y), this->P(q)) <= 0)
        {
          continue;
        }
        t0[0] = q;
        t0[1] = x;
        t0[2] = z;
        t1[0] = z;
        t1[1] = y;
        t1[2] = q;
        touched[r0[2]] = touched[r1[2]] = 1;
        ++flips;
      }
      if (flips == 0)
      {
        break;
      }
    }
  }
};

double MinAngleOf(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return MinimumAngle(a, b, c);
}
} // namespace

namespace
{
// Turk's minimum radius of curvature per vertex (section 5.1), before any smoothing.
std::vector<double> RawCurvatureRadius(const TriangleMesh& mesh, const MeshTopology& topology)
{
  const Index n = mesh.NumberOfPoints();
  std::vector<Vec3> normals;
  VertexNormals(mesh, normals);
  const double large = std::max(mesh.BoundingBoxDiagonal(), 1e-300);
  std::vector<double> raw(n, large);
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    const Index u = topology.EdgeVertex(e, 0), w = topology.EdgeVertex(e, 1);
    for (int side = 0; side < 2; ++side)
    {
      const Index p = side ? w : u, q = side ? u : w;
      const Vec3 d = mesh.Point(q) - mesh.Point(p);
      const double len = Norm(d);
      if (len <= 0)
      {
        continue;
      }
      // theta = angle between the normal and the edge; r = |tan(theta)| |PQ| / 2.
      const double c = std::min(1.0, std::abs(Dot(normals[p], d)) / len);
      const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
      const double r = c > 0 ? 0.5 * len * s / c : large;
      raw[p] = std::min(raw[p], std::min(r, large));
    }
  }
  return raw;
}

// The mean of `value` over each vertex and its neighbours, leaving out the flagged vertices
// (`skipped` may be empty); a vertex with nothing left keeps `fallback`.
std::vector<double> NeighbourhoodMean(const MeshTopology& topology, const std::vector<double>& value,
  const std::vector<unsigned char>& skipped, double fallback)
{
  const size_t n = value.size();
  auto counts = [&](size_t v) { return skipped.empty() || !skipped[v]; };
  std::vector<double> sum(n, 0.0);
  std::vector<int> count(n, 0);
  for (size_t v = 0; v < n; ++v)
  {
    if (counts(v))
    {
      sum[v] = value[v];
      count[v] = 1;
    }
  }
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    const Index u = topology.EdgeVertex(e, 0), w = topology.EdgeVertex(e, 1);
    if (counts(size_t(w)))
    {
      sum[u] += value[w];
      ++count[u];
    }
    if (counts(size_t(u)))
    {
      sum[w] += value[u];
      ++count[w];
    }
  }
  for (size_t v = 0; v < n; ++v)
  {
    sum[v] = count[v] > 0 ? sum[v] / count[v] : fallback;
  }
  return sum;
}
} // namespace

void EstimateCurvatureRadius(const TriangleMesh& mesh, std::vector<double>& radius)
{
  const MeshTopology topology(mesh);
  // One smoothing step: the mean over the vertex and its neighbours (the estimate is noisy).
  radius = NeighbourhoodMean(topology, RawCurvatureRadius(mesh, topology), {}, 0.0);
}

void EstimateFilletCurvature(
  const TriangleMesh& mesh, const std::vector<unsigned char>& skipped, std::vector<double>& curvature)
{
  const MeshTopology topology(mesh);
  std::vector<double> raw = RawCurvatureRadius(mesh, topology);
  for (double& r : raw)
  {
    r = 1.0 / std::max(r, 1e-300);
  }
  // Averaged as curvature: a mean of radii is held up by one flat neighbour (radius = the
  // diagonal), which thins out the edges of a fillet's band.
  curvature = NeighbourhoodMean(topology, raw, skipped, 1.0 / std::max(mesh.BoundingBoxDiagonal(), 1e-300));
}

void CurvatureDensity(const TriangleMesh& mesh, double curvatureWeight, std::vector<double>& vertexDensity,
  const std::vector<unsigned char>* skipped)
{
  vertexDensity.clear();
  if (!(curvatureWeight > 0) || mesh.NumberOfPoints() == 0)
  {
    return;
  }
  std::vector<double> curvature;
  if (skipped)
  {
    EstimateFilletCurvature(mesh, *skipped, curvature);
  }
  else
  {
    std::vector<double> radius;
    EstimateCurvatureRadius(mesh, radius);
    curvature.resize(radius.size());
    for (size_t i = 0; i < radius.size(); ++i)
    {
      curvature[i] = 1.0 / std::max(radius[i], 1e-300);
    }
  }
  std::vector<double> sorted = curvature;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = std::max(sorted[sorted.size() / 2], 1e-300);
  vertexDensity.resize(curvature.size());
  for (size_t i = 0; i < curvature.size(); ++i)
  {
    // Capped so a few spikes cannot take all points (and the repulsion radii stay comparable).
    vertexDensity[i] = 1.0 + curvatureWeight * std::min(curvature[i] / median, 8.0);
  }
}

void DistributePoints(const TriangleMesh& mesh, const std::vector<double>& vertexDensity, Index count,
  std::uint64_t seed, std::vector<SurfacePoint>& points)
{
  points.clear();
  const Index nt = mesh.NumberOfTriangles();
  if (nt == 0 || count <= 0)
  {
    return;
  }
  std::vector<double> cumulative(nt);
  double total = 0;
  for (Index t = 0; t < nt; ++t)
  {
    total += WeightedArea(mesh, vertexDensity, t);
    cumulative[t] = total;
  }
  Random random(seed);
  std::vector<SurfacePoint> drawn(count);
  std::vector<Index> perTriangle(size_t(nt) + 1, 0);
  for (Index i = 0; i < count; ++i)
  {
    const double x = random.Uniform() * total;
    Index t = static_cast<Index>(std::upper_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
    t = std::min(t, nt - 1);
    // Uniform point in the triangle (square-root parametrisation).
    const double r1 = std::sqrt(random.Uniform()), r2 = random.Uniform();
    const Index* tri = mesh.Triangle(t);
    const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
    drawn[i].Position = (1 - r1) * a + (r1 * (1 - r2)) * b + (r1 * r2) * c;
    drawn[i].Triangle = t;
    ++perTriangle[t + 1];
  }
  // The points in their triangles' order (a stable counting sort), not in drawing order: the
  // candidates then lie in memory as the input's triangles and vertices do, so the later stages,
  // which walk the input in its order and read each old vertex's neighbouring candidates, read
  // nearby memory (in drawing order every candidate read was a cache miss, and the 4M-triangle
  // scan took more than 4 times the 1M one's time).
  for (Index t = 0; t < nt; ++t)
  {
    perTriangle[t + 1] += perTriangle[t];
  }
  points.resize(count);
  for (const SurfacePoint& point : drawn)
  {
    points[perTriangle[point.Triangle]++] = point;
  }
}

// The repulsion's sheet rule: a neighbour whose face turns from a point's by more than this
// (about 107 degrees) lies on another sheet and does not push it.
constexpr double OtherSheetCosine = -0.3;
// A kept line's gap point (FeatureLines::GapPoints) pushes with this share of its radius (a pair
// repels within the mean of both radii). Measured over three seeds on the 29 CGAL meshes it
// changes (session 44): 1 and 0.75 remove as many needles (-30% at 50% of the vertices), 0.5
// fewer (-24%); 1 adds flipped tiles (76 -> 85), 0.75 does not (76 -> 78).
constexpr double GapPusherRadiusShare = 0.75;

// What a repulsion step reads of a point, copied in the grid's cell order: neighbours are then
// contiguous in memory (on a 1M-triangle scan, reading them by point id through the triangles'
// normals made each visit several times slower than on a 250k one).
struct RepulsionSlot
{
  Vec3 Position;
  Vec3 Normal;
  double Radius;
  Index Id;
};

std::vector<RepulsionSlot> RepulsionSlots(const std::vector<SurfacePoint>& points, const std::vector<double>& radius,
  const PointGrid& grid, const std::vector<Vec3>& faceNormal)
{
  const std::vector<Index>& order = grid.CellOrder();
  std::vector<RepulsionSlot> slots(order.size());
  for (size_t s = 0; s < order.size(); ++s)
  {
    const Index i = order[s];
    slots[s] = { points[i].Position, faceNormal[points[i].Triangle], radius[i], i };
  }
  return slots;
}

// One repulsion step per point (Jacobi: from the positions of the previous iteration): the
// force of the neighbours within the mean of both radii, in the tangent plane, capped.
// (The pair rule is a template parameter: a test per pair costs 5% of this loop's instructions.)
template <bool SmallerPairRadius>
void RepulsionMoves(const std::vector<SurfacePoint>& points, const std::vector<double>& radius, double maxRadius,
  const PointGrid& grid, const std::vector<Vec3>& faceNormal, std::vector<Vec3>& move)
{
  const std::vector<RepulsionSlot> slots = RepulsionSlots(points, radius, grid, faceNormal);
  vtkSMPTools::For(0, static_cast<vtkIdType>(slots.size()), [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType s = begin; s < end; ++s)
    {
      const RepulsionSlot& self = slots[s];
      const Vec3& p = self.Position;
      const Vec3& normal = self.Normal;
      Vec3 force{ 0, 0, 0 };
      grid.ForEachSlotNear(p.data(), maxRadius, [&](Index t) {
        const RepulsionSlot& other = slots[t];
        if (other.Id == self.Id)
        {
          return;
        }
        // A neighbour facing the other way lies on another sheet (the far side of a thin
        // part): it must not push, or thin parts are emptied of points.
        if (Dot(other.Normal, normal) < OtherSheetCosine)
        {
          return;
        }
        const double r =
          SmallerPairRadius ? std::min(self.Radius, other.Radius) : 0.5 * (self.Radius + other.Radius);
        // The neighbour is folded into the tangent plane: pushed along its offset's tangent
        // part, by its distance in space. (Measured by the tangent part alone, every neighbour
        // across a convex edge within reach looked as close as the edge, and the repulsion
        // emptied the strip along creases and fillets: rotor_small's rounded lip.)
        Vec3 d = p - other.Position;
        const double len = Norm(d);
        if (len >= r)
        {
          return;
        }
        d = d - Dot(d, normal) * normal;
        const double tangent = Norm(d);
        if (tangent <= 1e-12 * r)
        {
          // Coincident points: push apart along a deterministic tangent direction.
          Vec3 axis = std::abs(normal[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
          axis = Normalized(Cross(normal, axis));
          force = force + ((self.Id < other.Id ? 1.0 : -1.0) * 0.5) * axis;
          return;
        }
        force = force + ((r - len) / (r * tangent)) * d; // linear fall-off, zero at r
      });
      // Step: a fraction of the radius per unit force, capped (stable for any neighbour count).
      Vec3 step = (0.2 * self.Radius) * force;
      const double length = Norm(step);
      const double cap = 0.25 * self.Radius;
      if (length > cap)
      {
        step = (cap / length) * step;
      }
      move[self.Id] = step;
    }
  });
}

// Each moved point (not the first fixedCount) goes to the closest point of the surface to its
// moved position, never onto a sheet facing the other way. Points are taken in `order` (the
// grid's cell order: nearby queries walk the same part of the tree); each one is independent.
void ProjectMoves(const TriangleBVH& bvh, const std::vector<Vec3>& faceNormal, const std::vector<Vec3>& move,
  Index fixedCount, const std::vector<Index>& order, std::vector<SurfacePoint>& points)
{
  vtkSMPTools::For(0, static_cast<vtkIdType>(order.size()), [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType slot = begin; slot < end; ++slot)
    {
      const Index i = order[slot];
      const double s = Norm(move[i]);
      if (!(s > 0) || i < fixedCount)
      {
        continue;
      }
      const Vec3 q = points[i].Position + move[i];
      // The closest surface point to q lies within |move| of q (points[i] is on the surface).
      ClosestPointResult c = bvh.ClosestPoint(q, s * s * 1.0001 + 1e-300);
      if (c.Triangle == InvalidIndex)
      {
        c = bvh.ClosestPoint(q);
      }
      // Never jump to a sheet facing the other way (thin parts folded back on themselves).
      if (c.Triangle == InvalidIndex || Dot(faceNormal[c.Triangle], faceNormal[points[i].Triangle]) < -0.5)
      {
        continue;
      }
      points[i].Position = c.Point;
      points[i].Triangle = c.Triangle;
    }
  });
}

bool RelaxPoints(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<double>& vertexDensity,
  int iterations, std::vector<SurfacePoint>& points, const std::function<bool(double)>& progress, Index fixedCount,
  bool smallerPairRadius, Index pushers)
{
  const size_t n = points.size();
  if (n < 2 || iterations <= 0)
  {
    return true;
  }
  const double counted = double(n - size_t(pushers)); // the vertices the radius is for
  // Turk 1991: radius 2 sqrt(A / n) for a uniform density; with a density, points repel within
  // 2 sqrt(A_w / (n d)) where A_w is the density-weighted area (more points where d is larger).
  double weightedArea = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    weightedArea += WeightedArea(mesh, vertexDensity, t);
  }
  std::vector<double> radius(n), xyz(3 * n);
  std::vector<Vec3> move(n);
  std::vector<Vec3> faceNormal(mesh.NumberOfTriangles());
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    faceNormal[t] = Normalized(mesh.TriangleAreaVector(t));
  }
  PointGrid grid;
  for (int it = 0; it < iterations; ++it)
  {
    double maxRadius = 0;
    for (size_t i = 0; i < n; ++i)
    {
      radius[i] = 2.0 * std::sqrt(weightedArea / (counted * PointDensity(mesh, vertexDensity, points[i])));
      if (i >= size_t(fixedCount - pushers) && i < size_t(fixedCount))
      {
        radius[i] *= GapPusherRadiusShare;
      }
      maxRadius = std::max(maxRadius, radius[i]);
      std::copy(points[i].Position.begin(), points[i].Position.end(), &xyz[3 * i]);
    }
    grid.Build(xyz, maxRadius);
    if (smallerPairRadius)
    {
      RepulsionMoves<true>(points, radius, maxRadius, grid, faceNormal, move);
    }
    else
    {
      RepulsionMoves<false>(points, radius, maxRadius, grid, faceNormal, move);
    }
    ProjectMoves(bvh, faceNormal, move, fixedCount, grid.CellOrder(), points);
    if (progress && !progress(double(it + 1) / iterations))
    {
      return false;
    }
  }
  return true;
}

void NearestNeighborSpacing(const std::vector<double>& xyz, double& minimum, double& mean, std::vector<double>* perPoint)
{
  const size_t n = xyz.size() / 3;
  minimum = mean = 0;
  if (n < 2)
  {
    return;
  }
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k)
  {
    lo[k] = hi[k] = xyz[k];
  }
  for (size_t i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], xyz[3 * i + k]);
      hi[k] = std::max(hi[k], xyz[3 * i + k]);
    }
  }
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  std::vector<double> nearest(n, std::numeric_limits<double>::max());
  PointGrid grid;
  // Start with a cell suited to a surface sample, widen for points that find nothing.
  double cell = std::max(diag / std::sqrt(double(n)), 1e-300);
  grid.Build(xyz, cell);
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      double r = grid.CellSize();
      for (;;)
      {
        double best2 = std::numeric_limits<double>::max();
        grid.ForEachNear(&xyz[3 * i], r, [&](Index j) {
          if (j == Index(i))
          {
            return;
          }
          double d2 = 0;
          for (int k = 0; k < 3; ++k)
          {
            d2 += (xyz[3 * i + k] - xyz[3 * size_t(j) + k]) * (xyz[3 * i + k] - xyz[3 * size_t(j) + k]);
          }
          best2 = std::min(best2, d2);
        });
        if (best2 <= r * r || r > 2 * diag)
        {
          nearest[i] = std::sqrt(best2);
          break;
        }
        r *= 2;
      }
    }
  });
  minimum = *std::min_element(nearest.begin(), nearest.end());
  mean = std::accumulate(nearest.begin(), nearest.end(), 0.0) / double(n);
  if (perPoint)
  {
    *perPoint = std::move(nearest);
  }
}

namespace
{
std::vector<double> PointCoordinates(const std::vector<SurfacePoint>& points)
{
  std::vector<double> xyz(3 * points.size());
  for (size_t i = 0; i < points.size(); ++i)
  {
    std::copy(points[i].Position.begin(), points[i].Position.end(), &xyz[3 * i]);
  }
  return xyz;
}

// Points closer to another point than this share of the mean spacing are crowded: repulsion keeps
// relaxed points near the mean spacing, so only an artefact of the projection comes this close.
constexpr double CrowdedSpacingShare = 0.02;

// Repulsion projects every move to the closest point of the surface, which at a pinched vertex
// or a sharp concave fold maps points from both sides onto the same spot: they would make needle
// or zero-area tiles. A crowded point (not one of the first fixedCount) goes back to where it was
// placed at random; one still crowded there is dropped. Returns the number dropped.
Index SeparateCrowdedPoints(std::vector<SurfacePoint>& points, const std::vector<SurfacePoint>& placed, Index fixedCount)
{
  double minimum = 0, mean = 0;
  std::vector<double> nearest;
  NearestNeighborSpacing(PointCoordinates(points), minimum, mean, &nearest);
  if (!(minimum < CrowdedSpacingShare * mean))
  {
    return 0;
  }
  const double limit = CrowdedSpacingShare * mean;
  for (size_t i = size_t(fixedCount); i < points.size(); ++i)
  {
    if (nearest[i] < limit)
    {
      points[i] = placed[i];
    }
  }
  NearestNeighborSpacing(PointCoordinates(points), minimum, mean, &nearest);
  Index kept = fixedCount;
  for (size_t i = size_t(fixedCount); i < points.size(); ++i)
  {
    if (!(nearest[i] < limit))
    {
      points[size_t(kept++)] = points[i];
    }
  }
  const Index dropped = static_cast<Index>(points.size()) - kept;
  points.resize(size_t(kept));
  return dropped;
}

// Triangles with two or more non-manifold vertices (those on a non-manifold edge, a sheet and its
// mirror image) are kept as they are: a candidate inside would split the triangles of one edge
// differently on each sheet and add non-manifold edges. Candidates there (not one of the first
// fixedCount) are dropped; returns how many.
Index DropPointsOnNonManifoldTriangles(const TriangleMesh& mesh, const std::vector<unsigned char>& nonManifoldVertices,
  std::vector<SurfacePoint>& points, Index fixedCount)
{
  if (std::find(nonManifoldVertices.begin(), nonManifoldVertices.end(), 1) == nonManifoldVertices.end())
  {
    return 0;
  }
  Index kept = fixedCount;
  for (size_t i = size_t(fixedCount); i < points.size(); ++i)
  {
    const Index* tri = mesh.Triangle(points[i].Triangle);
    if (nonManifoldVertices[tri[0]] + nonManifoldVertices[tri[1]] + nonManifoldVertices[tri[2]] < 2)
    {
      points[size_t(kept++)] = points[i];
    }
  }
  const Index dropped = static_cast<Index>(points.size()) - kept;
  points.resize(size_t(kept));
  return dropped;
}
} // namespace

namespace
{
// The vertices of a coarser nested level, which a finer level must keep exactly (section 6.1).
struct CoarserLevel
{
  // Points [0, FixedCount) keep their given positions (no nudge inside their triangle).
  Index FixedCount = 0;
  // Per point (empty: none): the input vertex it stands for, which is then kept as it is instead
  // of inserting the point (a vertex a coarser level retained or moved a candidate onto).
  std::vector<Index> PinnedTo;
  // Feature lines (PreserveCreases; null: none): per input vertex, its neighbours along a line.
  const std::vector<std::vector<Index>>* Lines = nullptr;
  // The creases candidates slide along in the repair (SlideAlongCreases; null: none).
  const CreasePolylines* Creases = nullptr;

  bool IsPinned(Index i) const { return !this->PinnedTo.empty() && this->PinnedTo[i] != InvalidIndex; }
};

void TileWithPoints(const TriangleMesh& mesh, const TriangleBVH& bvh, std::vector<SurfacePoint>& points,
  const RetilingOptions& options, const CoarserLevel& coarser, RetilingResult& result);
}

namespace
{
// 1 for the vertices of the kept feature lines (none when no line is kept).
std::vector<unsigned char> LineVertexFlags(const FeatureLines& features)
{
  std::vector<unsigned char> flags(features.LineNeighbors.size(), 0);
  for (size_t v = 0; v < flags.size(); ++v)
  {
    flags[v] = features.LineNeighbors[v].empty() ? 0 : 1;
  }
  return flags;
}

// PreserveCreases: the corners and samples of the feature lines as the first points, pinned to
// their input vertex (kept as they are, like a coarser level's vertices), at the spacing the free
// points will have. Lines needing half the vertices or more are finer than the re-tiling can
// follow: then none are kept (FeaturesIgnored); nor when most of their vertices are corners. With
// SlideAlongCreases the lines not kept are returned as the crease polylines the repair slides
// candidates along, built from the topology the lines were found with (one build of the input's
// adjacency, held only here; session 39 built a second one).
std::unique_ptr<CreasePolylines> FeaturePoints(const TriangleMesh& mesh, const RetilingOptions& options,
  FeatureLines& features, std::vector<SurfacePoint>& points, CoarserLevel& fixedPoints, RetilingResult& result)
{
  double area = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    area += mesh.TriangleArea(t);
  }
  const double spacing = EvenSpacing(area, options.NumberOfPoints);
  std::unique_ptr<MeshTopology> topology;
  if (options.SlideAlongCreases)
  {
    topology.reset(new MeshTopology(mesh));
    DetectFeatureLines(mesh, *topology, options.FeatureAngle, spacing, features);
  }
  else
  {
    DetectFeatureLines(mesh, options.FeatureAngle, spacing, features);
  }
  // Lines made mostly of corners are shorter than the spacing: detail (scan noise, the facets of
  // an organic shape, an isosurface's steps) finer than the re-tiling can follow. Kept, they held
  // original vertices and left needles (triceratops, mannequin-devil, the MRI: 83-100% corners;
  // CAD creases 0-12%), so none are kept, silently: it is the default.
  const bool tooFine = 2 * static_cast<Index>(features.Kept.size()) >= options.NumberOfPoints;
  if (tooFine || 2 * features.Corners > static_cast<Index>(features.Kept.size()))
  {
    result.FeaturesIgnored = tooFine && !features.Kept.empty();
    std::unique_ptr<CreasePolylines> creases;
    if (topology)
    {
      creases.reset(new CreasePolylines(mesh, *topology, features.LineNeighbors));
    }
    features = FeatureLines(); // not held otherwise: the MRI's lines are 52 MB
    return creases;
  }
  std::vector<Index> firstTriangle(size_t(mesh.NumberOfPoints()), InvalidIndex);
  for (Index t = mesh.NumberOfTriangles() - 1; t >= 0; --t)
  {
    for (int k = 0; k < 3; ++k)
    {
      firstTriangle[mesh.Triangle(t)[k]] = t;
    }
  }
  for (Index v : features.Kept)
  {
    points.push_back(SurfacePoint{ mesh.Point(v), firstTriangle[v] });
    fixedPoints.PinnedTo.push_back(v);
  }
  fixedPoints.FixedCount = static_cast<Index>(points.size());
  fixedPoints.Lines = &features.LineNeighbors;
  result.FeatureVertices = fixedPoints.FixedCount;
  result.Corners = features.Corners;
  return nullptr;
}

// The kept lines' gap points (FeatureLines::GapPoints) as fixed points of the repulsion, inserted
// after the `fixed` samples; returns how many. On a convex crease the projection holds a free
// point pushed across it on the crease, and the samples around a gap push it only along the line:
// it stayed between them, and the removal, joining the samples along the line, left it the
// obtuse corner of a cap (session 43: 212 of the 550 needles at 50% of the vertices). A pusher
// stands on one of its edge's faces; where the other face turns away beyond the repulsion's
// sheet rule (a knife edge: blade's), the other face gets a pusher of its own.
Index InsertGapPushers(const TriangleMesh& mesh, const std::vector<LinePoint>& gaps, Index fixed,
  std::vector<SurfacePoint>& points)
{
  if (gaps.empty())
  {
    return 0;
  }
  std::vector<SurfacePoint> pushers;
  pushers.reserve(2 * gaps.size());
  for (size_t i = 0; i < gaps.size(); ++i)
  {
    const LinePoint& g = gaps[i];
    const Vec3 a = mesh.Point(g.From);
    const Vec3 p = a + g.T * (mesh.Point(g.To) - a);
    const Index t0 = g.Faces[0], t1 = g.Faces[1];
    if (t0 == InvalidIndex)
    {
      continue;
    }
    pushers.push_back(SurfacePoint{ p, t0 });
    if (t1 != InvalidIndex &&
      Dot(Normalized(mesh.TriangleAreaVector(t0)), Normalized(mesh.TriangleAreaVector(t1))) < OtherSheetCosine)
    {
      pushers.push_back(SurfacePoint{ p, t1 });
    }
  }
  points.insert(points.begin() + fixed, pushers.begin(), pushers.end());
  return static_cast<Index>(pushers.size());
}
} // namespace


void Retile(const TriangleMesh& mesh, const RetilingOptions& options, RetilingResult& result)
{
  result = RetilingResult();
  const Index n0 = mesh.NumberOfPoints();
  const Index nt = mesh.NumberOfTriangles();
  if (nt == 0 || options.NumberOfPoints < 3)
  {
    return;
  }
  auto report = [&](double f) { return !options.Progress || options.Progress(f); };
  auto abort = [&]() {
    result = RetilingResult();
    result.Aborted = true;
  };

  // 1-3: candidate points, after the fixed ones on feature lines (which push but do not move).
  std::vector<SurfacePoint> points, added;
  FeatureLines features;
  CoarserLevel fixedPoints;
  std::unique_ptr<CreasePolylines> creases;
  if (options.PreserveCreases)
  {
    creases = FeaturePoints(mesh, options, features, points, fixedPoints, result);
    fixedPoints.Creases = creases.get();
  }
  std::vector<double> density;
  if (options.FilletDensity)
  {
    const std::vector<unsigned char> lineVertices = LineVertexFlags(features);
    CurvatureDensity(mesh, options.CurvatureWeight, density, &lineVertices);
  }
  else
  {
    CurvatureDensity(mesh, options.CurvatureWeight, density);
  }
  const Index fixed = static_cast<Index>(points.size());
  DistributePoints(mesh, density, options.NumberOfPoints - fixed, options.RandomSeed, added);
  points.insert(points.end(), added.begin(), added.end());
  NearestNeighborSpacing(PointCoordinates(points), result.MinSpacingBefore, result.MeanSpacingBefore);
  TriangleBVH bvh(mesh);
  const std::vector<SurfacePoint> placed = points;
  vtkLogF(TRACE, "retile: %lld candidate points on %lld triangles", static_cast<long long>(points.size()),
    static_cast<long long>(nt));
  vtkLogStartScopeF(TRACE, "retile-relax", "retile: repulsion");
  const Index pushers = options.RepelFromLineGaps ? InsertGapPushers(mesh, features.GapPoints, fixed, points) : 0;
  const bool relaxed = RelaxPoints(mesh, bvh, density, options.RepulsionIterations, points,
    [&](double f) { return report(0.6 * f); }, fixed + pushers, options.FilletDensity, pushers);
  points.erase(points.begin() + fixed, points.begin() + fixed + pushers);
  vtkLogEndScope("retile-relax");
  if (!relaxed)
  {
    abort();
    return;
  }
  RetilingOptions withFlags = options;
  const std::vector<unsigned char> computedFlags =
    options.NonManifoldVertices ? std::vector<unsigned char>() : NonManifoldVertexFlags(mesh);
  withFlags.NonManifoldVertices = options.NonManifoldVertices ? options.NonManifoldVertices : &computedFlags;
  const Index dropped = SeparateCrowdedPoints(points, placed, fixed) +
    DropPointsOnNonManifoldTriangles(mesh, *withFlags.NonManifoldVertices, points, fixed);
  NearestNeighborSpacing(PointCoordinates(points), result.MinSpacingAfter, result.MeanSpacingAfter);
  result.DroppedCandidates = dropped;
  fixedPoints.PinnedTo.resize(points.size(), InvalidIndex);
  TileWithPoints(mesh, bvh, points, withFlags, fixedPoints, result);
}

namespace
{
bool ReportProgress(const RetilingOptions& options, double fraction)
{
  return !options.Progress || options.Progress(fraction);
}

void AbortResult(RetilingResult& result)
{
  result = RetilingResult();
  result.Aborted = true;
}

// The candidates of each input triangle: order[start[t]] .. order[start[t + 1] - 1] (counting sort).
struct CandidatesByTriangle
{
  std::vector<Index> Start, Order;
};

CandidatesByTriangle BucketCandidates(
  const std::vector<SurfacePoint>& points, Index numberOfTriangles, const CoarserLevel& coarser)
{
  const Index np = static_cast<Index>(points.size());
  CandidatesByTriangle buckets;
  buckets.Start.assign(size_t(numberOfTriangles) + 1, 0);
  buckets.Order.resize(np);
  for (Index i = 0; i < np; ++i)
  {
    if (!coarser.IsPinned(i))
    {
      ++buckets.Start[points[i].Triangle + 1];
    }
  }
  for (Index t = 0; t < numberOfTriangles; ++t)
  {
    buckets.Start[t + 1] += buckets.Start[t];
  }
  std::vector<Index> fill(buckets.Start.begin(), buckets.Start.end() - 1);
  for (Index i = 0; i < np; ++i)
  {
    if (!coarser.IsPinned(i))
    {
      buckets.Order[fill[points[i].Triangle]++] = i;
    }
  }
  buckets.Order.resize(buckets.Start[numberOfTriangles]);
  return buckets;
}

// Candidate points go strictly inside their triangle so that no original edge is split (the
// original edges stay the constraints of the mutual tessellation). A coarser level's points are
// inside already and stay where they are.
void MoveCandidatesInside(const TriangleMesh& mesh, std::vector<SurfacePoint>& points, const CoarserLevel& coarser)
{
  for (Index i = coarser.FixedCount; i < static_cast<Index>(points.size()); ++i)
  {
    SurfacePoint& point = points[i];
    const Index* tri = mesh.Triangle(point.Triangle);
    const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
    Vec3 w = Barycentric(point.Position, a, b, c);
    const double eps = 1e-4;
    double sum = 0;
    for (double& x : w)
    {
      x = std::max(x, eps);
      sum += x;
    }
    w = (1.0 / sum) * w;
    point.Position = w[0] * a + w[1] * b + w[2] * c;
  }
}

// Step 4 (section 4.2): the mutual tessellation. Vertices: the old ones, then candidate i at
// n0 + i; every old triangle holding candidates is split around them. Fills the candidates'
// barycentric coordinates in their triangle (after the splitter's nudges). A coarser level's
// points keep their exact position (a nudge only moves them in the splitter's plane coordinates);
// pinned points are left out (isolated vertices, dropped by the extraction).
void MutualTessellation(const TriangleMesh& mesh, std::vector<SurfacePoint>& points, const CandidatesByTriangle& buckets,
  Index fixedCount, TriangleMesh& mutual, std::vector<double>& bary)
{
  const Index n0 = mesh.NumberOfPoints();
  const Index nt = mesh.NumberOfTriangles();
  const Index np = static_cast<Index>(points.size());
  bary.assign(3 * size_t(np), 0.0);
  mutual.Points = mesh.Points;
  mutual.Points.reserve(mesh.Points.size() + 3 * size_t(np));
  for (const SurfacePoint& point : points)
  {
    mutual.AddPoint(point.Position);
  }
  mutual.Triangles.reserve(mesh.Triangles.size() + 6 * size_t(np));
  TriangleSplitter splitter;
  std::vector<Vec3> local;
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const Index first = buckets.Start[t];
    const Index k = buckets.Start[t + 1] - first;
    if (k == 0)
    {
      mutual.AddTriangle(tri[0], tri[1], tri[2]);
      continue;
    }
    const Vec3 corners[3] = { mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]) };
    local.clear();
    for (Index j = first; j < first + k; ++j)
    {
      local.push_back(points[buckets.Order[j]].Position);
    }
    splitter.Run(corners, local.data(), k);
    // Points nudged by the splitter: update their 3D position from the plane coordinates.
    const Vec3 e1 = Normalized(corners[1] - corners[0]);
    const Vec3 e2 = Cross(Normalized(Cross(corners[1] - corners[0], corners[2] - corners[0])), e1);
    for (Index j = 0; j < k; ++j)
    {
      const Index id = buckets.Order[first + j];
      const double* uv = splitter.P(3 + j);
      const Vec3 p = id < fixedCount ? points[id].Position : corners[0] + uv[0] * e1 + uv[1] * e2;
      points[id].Position = p;
      mutual.SetPoint(n0 + id, p);
      const Vec3 w = Barycentric(p, corners[0], corners[1], corners[2]);
      std::copy(w.begin(), w.end(), &bary[3 * size_t(id)]);
    }
    auto global = [&](Index v) { return v < 3 ? tri[v] : n0 + buckets.Order[first + v - 3]; };
    for (size_t s = 0; s < splitter.Local.size(); s += 3)
    {
      mutual.AddTriangle(global(splitter.Local[s]), global(splitter.Local[s + 1]), global(splitter.Local[s + 2]));
    }
  }
}

// What the original surface faces at each vertex of the mutual tessellation: old vertices their
// normal, candidates the interpolated normal at their position.
std::vector<Vec3> ReferenceNormals(
  const TriangleMesh& mesh, const std::vector<SurfacePoint>& points, const std::vector<double>& bary)
{
  const Index n0 = mesh.NumberOfPoints();
  const Index np = static_cast<Index>(points.size());
  std::vector<Vec3> vertexNormals, reference(size_t(n0) + np);
  VertexNormals(mesh, vertexNormals);
  for (Index v = 0; v < n0; ++v)
  {
    reference[v] = vertexNormals[v];
  }
  for (Index i = 0; i < np; ++i)
  {
    reference[n0 + i] = InterpolatedNormal(mesh, vertexNormals, points[i].Triangle, &bary[3 * size_t(i)]);
  }
  return reference;
}

// Smallest angle (3 degrees) a collapse of the first round may leave: a vertex whose collapses
// all leave a needle waits for a later phase, as long as the waits stay within this many per old
// vertex (fandisk waits 0.15 per vertex) and the vertex has at most MaximumDeferredValence
// neighbours (a cone's valence-5000 apex would be re-checked at 5000 squared cost every pass).
constexpr double NeedleFloor = Radians(3.0);
constexpr double NeedleDeferralBudget = 1.0;
constexpr size_t MaximumDeferredValence = 32;
// A ring re-triangulated by flips (RemoveByRingFlips) with a smaller angle is taken only when
// every other is too: the repair stage's needle angle.
constexpr double RingNeedleAngle = Radians(2.0);

// Step 5 (section 4.3): removal of the old vertices by collapses onto neighbours.
struct OldVertexRemoval
{
  EditableMesh& Edit;
  std::vector<Vec3>& Reference;
  Index OldVertices;
  // Candidates moved onto an old vertex's position by phase 2 (InvalidIndex: not moved).
  std::vector<Index> MovedTo;
  // Per old vertex: the coarser level's point it stands for (kept as it is), else InvalidIndex.
  std::vector<Index> KeptFor;
  // Candidates [0, FixedCount) belong to a coarser level: phase 2 never moves them.
  Index FixedCount = 0;
  CollapseOptions Collapse;
  // Border flags of every vertex, kept exact through the collapses (a merged vertex is on the
  // border when one of the pair was): IsBoundaryVertex walks a whole fan twice per check.
  std::vector<unsigned char> OnBorder;
  // Per vertex of the mutual tessellation: 1 for the input's non-manifold vertices, which no
  // collapse may touch (candidates lie strictly inside triangles, so they are all manifold).
  std::vector<unsigned char> Locked;
  // Feature lines (empty: none): per vertex of the mutual tessellation, its neighbours along a
  // line. A vertex on a line is removed only by collapsing along it (or replaced in place by a
  // candidate), so the line's edges end up joining its kept vertices.
  std::vector<std::vector<Index>> Lines;
  double MinimumFacing = 0.0;
  double MinimumAngleFloor = 0.0;
  // PreserveCreases: the facing test is enforced for every target, and the angle floor applies.
  bool Strict = false;
  double DeferredChecks = 0.0; // waits of vertices whose collapses all left needles or faced wrong
  bool LastStep = false;       // the last phase: EnforceFacing takes its fallback targets
  bool EnforceFacing = false;  // RetilingOptions::EnforceFacing (without PreserveCreases)
  bool RetriangulateRings = false; // RetilingOptions::RetriangulateRings
  // Optional: every collapse performed, as pairs (removed, target) in this mesh's ids.
  std::vector<Index>* Record = nullptr;
  // The targets of the last ChooseTarget whose collapse keeps the mesh valid, with the smallest
  // angle of their fan (-1: a tile of the fan faces against the original surface).
  struct TargetAngle
  {
    Index Target;
    double Angle;
  };
  std::vector<TargetAngle> Valid;
  // Scratch of RemoveByRingSearch (reused by every old vertex).
  RingTriangulationSearch Search{ this->Edit, this->Reference };
  // The input surface (optional): where a ring has no triangulation facing its corners' reference
  // normals and one is taken all the same, the search prefers one whose tiles face the input
  // under them (RingTriangulationSearch::InputSurface).
  const TriangleBVH* InputSurface = nullptr;
  std::vector<std::pair<Index, Index>> SearchFlips;
  // A border vertex may only go onto a border neighbour (section 4.6: the border keeps its place),
  // and not when it has a single triangle. Set for the nested levels, whose records the fragment
  // tracking replays: a border vertex collapsed onto an inner vertex, or a lone border triangle
  // removed, takes a piece of the surface away, which no fragment can follow.
  bool BorderAlongBorder = false;
  // Set for the coarser nested levels, whose removals keep the fans (RemoveByRingSearch): in the
  // last step, a vertex no collapse can remove is removed by the ring search all the same
  // (RemoveHeldByRingSearch) rather than kept in the level.
  bool HeldRingSearch = false;

  OldVertexRemoval(EditableMesh& edit, std::vector<Vec3>& reference, Index oldVertices, Index candidates,
    const CoarserLevel& coarser, const std::vector<unsigned char>& nonManifoldVertices)
    : Edit(edit)
    , Reference(reference)
    , OldVertices(oldVertices)
    , MovedTo(candidates, InvalidIndex)
    , KeptFor(oldVertices, InvalidIndex)
    , FixedCount(coarser.FixedCount)
  {
    this->Collapse.MinimumNormalDot = 0.0;
    this->Locked.assign(size_t(edit.NumberOfPoints()), 0);
    std::copy_n(nonManifoldVertices.begin(), std::min(nonManifoldVertices.size(), this->Locked.size()), this->Locked.begin());
    this->Collapse.LockedVertices = this->Locked.data();
    // Most candidates of a high-valence old vertex fold its fan: reject those at the first
    // folding triangle instead of after a walk of the whole link.
    this->Collapse.GeometryFirst = true;
    this->OnBorder.resize(edit.NumberOfPoints());
    for (Index v = 0; v < edit.NumberOfPoints(); ++v)
    {
      this->OnBorder[v] = edit.IsVertexAlive(v) && edit.IsBoundaryVertex(v) ? 1 : 0;
    }
    this->Collapse.BoundaryVertices = this->OnBorder.data();
    for (Index i = 0; i < candidates; ++i)
    {
      if (coarser.IsPinned(i))
      {
        this->KeptFor[coarser.PinnedTo[i]] = i;
      }
    }
    if (coarser.Lines)
    {
      this->Lines = *coarser.Lines;
      this->Lines.resize(size_t(edit.NumberOfPoints()));
    }
  }

  bool IsLineEdge(Index u, Index w) const
  {
    return !this->Lines.empty() && std::find(this->Lines[u].begin(), this->Lines[u].end(), w) != this->Lines[u].end();
  }

  // The lines after r went onto target: r's other line neighbours join the target (along a line
  // the target was one of them; replaced in place by a candidate, phase 2, it had none).
  void UpdateLines(Index r, Index target)
  {
    if (this->Lines.empty() || this->Lines[r].empty())
    {
      return;
    }
    std::vector<Index> around = std::move(this->Lines[r]);
    this->Lines[r].clear();
    auto& joined = this->Lines[target];
    joined.erase(std::remove(joined.begin(), joined.end(), r), joined.end());
    for (Index w : around)
    {
      if (w == target)
      {
        continue;
      }
      auto& other = this->Lines[w];
      std::replace(other.begin(), other.end(), r, target);
      std::sort(other.begin(), other.end()); // a short line closed into a loop: no duplicates
      other.erase(std::unique(other.begin(), other.end()), other.end());
      if (std::find(joined.begin(), joined.end(), w) == joined.end())
      {
        joined.push_back(w);
      }
    }
  }

  // Facing test of the triangles a collapse keeps; returns their smallest angle or -1 when one
  // would face against the original surface or degenerate.
  double Evaluate(const Index* pair, const Vec3& position) const
  {
    double worst = std::numeric_limits<double>::max();
    bool ok = true;
    this->Edit.ForEachSurvivingTriangle(pair, 2, [&](Index t, int corner) {
      if (!ok)
      {
        return;
      }
      const Index* tri = this->Edit.Triangle(t);
      Vec3 p[3];
      Index ids[3];
      for (int k = 0; k < 3; ++k)
      {
        ids[k] = k == corner ? pair[1] : tri[k];
        p[k] = k == corner ? position : this->Edit.Point(tri[k]);
      }
      const Vec3 nrm = TriangleNormal(p[0], p[1], p[2]);
      if (Norm(nrm) == 0 || IsDegenerate(p[0], p[1], p[2]))
      {
        ok = false;
        return;
      }
      for (int k = 0; k < 3; ++k)
      {
        if (Dot(nrm, this->Reference[ids[k]]) <= this->MinimumFacing)
        {
          ok = false;
          return;
        }
      }
      worst = std::min(worst, MinAngleOf(p[0], p[1], p[2]));
    });
    return ok ? worst : -1.0;
  }

  // The best neighbour of old vertex r to collapse with in this phase (InvalidIndex: none).
  Index ChooseTarget(Index r, int phase, std::vector<Index>& neighbors)
  {
    const Index n0 = this->OldVertices;
    this->Edit.Neighbors(r, neighbors);
    this->Valid.clear();
    if (this->BorderAlongBorder && this->OnBorder[r] && neighbors.size() < 3)
    {
      return InvalidIndex;
    }
    // bestNeedle: ignoring the angle floor (PreserveCreases); bestLoose: ignoring the facing test
    // for candidate targets (the default's rule before the facing test was enforced there).
    Index best = InvalidIndex, bestNeedle = InvalidIndex, bestLoose = InvalidIndex;
    double bestScore = -1, bestNeedleScore = -1, bestLooseScore = -1;
    for (Index c : neighbors)
    {
      if (c < n0 && phase == 0)
      {
        continue;
      }
      if (phase == 2 && (c < n0 || c - n0 < this->FixedCount || this->MovedTo[c - n0] != InvalidIndex))
      {
        continue;
      }
      if (phase != 2 && !this->Lines.empty() && !this->Lines[r].empty() && !this->IsLineEdge(r, c))
      {
        continue; // a line vertex goes along its line only
      }
      if (this->BorderAlongBorder && this->OnBorder[r] && !this->OnBorder[c])
      {
        continue;
      }
      const Index pair[2] = { r, c };
      const Vec3 position = this->Edit.Point(phase == 2 ? r : c);
      if (this->Edit.CheckCollapse(pair, 2, position, this->Collapse) != CollapseStatus::Ok)
      {
        continue;
      }
      const double angle = this->Evaluate(pair, position);
      const double score = angle + (c >= n0 ? 10.0 : 0.0);
      this->Valid.push_back(TargetAngle{ c, angle });
      // Without PreserveCreases or EnforceFacing a candidate target passes even when Evaluate
      // refused it (-1 + 10): the facing test only ranks those (enforcing it without a bound made
      // the corpus's valence-5000 cone 14 times slower: vertices stayed pending pass after pass).
      // EnforceFacing: such a target is the fallback below, within the waiting budget.
      const bool allowed = this->Strict ? angle >= this->MinimumAngleFloor : (this->EnforceFacing ? angle >= 0 : score >= 0);
      if (this->EnforceFacing && score >= 0 && score > bestLooseScore)
      {
        bestLooseScore = score;
        bestLoose = c;
      }
      if (allowed && score > bestScore)
      {
        bestScore = score;
        best = c;
      }
      if (angle >= 0 && score > bestNeedleScore)
      {
        bestNeedleScore = score;
        bestNeedle = c;
      }
    }
    // Only needles (PreserveCreases) or only targets facing against the surface (EnforceFacing):
    // wait for a later phase, within a budget of waits, and only for vertices cheap to check again
    // (a valence-5000 apex costs 5000 squared triangle visits per check); the last step takes them.
    const Index fallback = this->Strict ? bestNeedle : bestLoose;
    if (best == InvalidIndex && fallback != InvalidIndex)
    {
      if (this->DeferredChecks >= NeedleDeferralBudget * double(n0) || neighbors.size() > MaximumDeferredValence ||
        (this->EnforceFacing && this->LastStep))
      {
        return fallback;
      }
      this->DeferredChecks += 1.0;
    }
    return best;
  }

  void Perform(Index r, Index target, int phase)
  {
    const Index pair[2] = { r, target };
    if (this->Record)
    {
      this->Record->push_back(r);
      this->Record->push_back(target);
    }
    if (phase == 2)
    {
      this->MovedTo[target - this->OldVertices] = r;
      this->Reference[target] = this->Reference[r];
    }
    this->OnBorder[target] = this->OnBorder[target] | this->OnBorder[r];
    this->UpdateLines(r, target);
    this->Edit.Collapse(pair, 2, target, this->Edit.Point(phase == 2 ? r : target));
  }

  // Whether the chosen target's fan faces against the original surface somewhere.
  bool FanFacesWrong(Index target) const
  {
    for (const TargetAngle& tried : this->Valid)
    {
      if (tried.Target == target)
      {
        return tried.Angle < 0;
      }
    }
    return false;
  }

  // Turk's removal (section 4.3) where the fans from r's valid targets all face against the
  // surface somewhere: the ring re-triangulated by flips after the collapse (slodRetileRing.h).
  // Among the targets that give a ring facing the surface's way, one without needles (smallest
  // angle RingNeedleAngle) whose ring passes closest to r (the surface moves least); when all have
  // needles, the largest smallest angle. False (nothing done) when none does. The flips are recorded as step 6's are (the nested levels' tracking replays them).
  bool RemoveByRingFlips(Index r, int phase)
  {
    RingRetriangulation ring(this->Edit, this->Reference);
    ring.MinimumFacing = this->MinimumFacing;
    ring.IsFixedEdge = [&](Index x, Index y) { return this->IsLineEdge(x, y); };
    Index best = InvalidIndex;
    double bestAngle = -1, bestDistance = std::numeric_limits<double>::max();
    std::vector<std::pair<Index, Index>> flips, bestFlips;
    for (const TargetAngle& tried : this->Valid)
    {
      if (tried.Angle >= 0)
      {
        continue; // its fan faces the surface's way: ChooseTarget's rules decide on it
      }
      const Index c = tried.Target;
      const Vec3 position = this->Edit.Point(phase == 2 ? r : c);
      double angle = 0;
      double distance = 0;
      if (!ring.Try(r, c, position, this->Reference[phase == 2 ? r : c], flips, angle, distance) ||
        (this->Strict && angle < this->MinimumAngleFloor))
      {
        continue;
      }
      // A ring without needles first; among those, the closest to r.
      const bool needle = angle < RingNeedleAngle, bestNeedle = bestAngle < RingNeedleAngle;
      if (best == InvalidIndex || (bestNeedle && !needle) ||
        (needle == bestNeedle && (needle ? angle > bestAngle : distance < bestDistance)))
      {
        bestDistance = distance;
        best = c;
        bestAngle = angle;
        bestFlips = flips;
      }
    }
    if (best == InvalidIndex)
    {
      return false;
    }
    this->PerformWithFlips(r, best, phase, bestFlips);
    return true;
  }

  // The collapse of r onto target, then the flips of its new ring (recorded as step 6's are: the
  // nested levels' tracking replays them). A flip the mesh refuses is left out (not expected: the
  // ring searches only make edges the mesh does not have).
  void PerformWithFlips(Index r, Index target, int phase, const std::vector<std::pair<Index, Index>>& flips)
  {
    this->Perform(r, target, phase);
    for (const auto& edge : flips)
    {
      if (this->Edit.FlipEdge(edge.first, edge.second) && this->Record)
      {
        this->Record->push_back(-1 - edge.first);
        this->Record->push_back(edge.second);
      }
    }
  }

  // Turk's removal where the fans from r's valid targets all face against the surface somewhere
  // (the default's last-resort fans made the pleats of flipped tiles, Documentation/Retile.md,
  // Session 16): the triangulation of r's whole ring facing the surface's way with the largest
  // smallest angle (RingTriangulationSearch, every triangulation of the ring), made as the collapse
  // onto the valid target that is a corner of most of its tiles, then flips. Where no
  // triangulation faces the surface's way and a fan facing against it would be taken anyway
  // (`wrongFanTaken`), the triangulation whose worst tile turns least (never worse than that fan),
  // unless it has a needle.
  // False (nothing done) when the ring is not closed, is on a line, or has no such triangulation.
  // Not in phase 2 (the old vertex's position stays there).
  bool RemoveByRingSearch(Index r, int phase, bool wrongFanTaken)
  {
    // Not for the nested levels' recorded removals: each search's flips cut the fragments of the
    // level interpolation again (elephant's morph had 6,692 fragments with fans, 41,588 with it).
    if (phase == 2 || this->Record || (!this->Lines.empty() && !this->Lines[r].empty()))
    {
      return false;
    }
    this->Search.MinimumFacing = this->MinimumFacing;
    this->Search.MinimumAngle = this->Strict ? this->MinimumAngleFloor : 0.0;
    // The fallback's ranking by the input costs a closest-point query per tile: only when the
    // fallback may be taken.
    this->Search.InputSurface = wrongFanTaken ? this->InputSurface : nullptr;
    bool valid = false;
    double worst = 0, smallest = 0;
    // Not valid: taken instead of the fan only without a needle (the repair cannot mend a needle
    // at a vertex kept for the topology: femur at 0.9 had a 0.6 degree tile there).
    if (!this->Search.Find(r, valid, worst, smallest) ||
      (!valid && (!wrongFanTaken || smallest < RingNeedleAngle)))
    {
      return false;
    }
    Index best = InvalidIndex;
    int bestTiles = 0;
    for (const TargetAngle& tried : this->Valid)
    {
      const int tiles = this->Search.TilesAt(tried.Target);
      if (tiles > bestTiles)
      {
        bestTiles = tiles;
        best = tried.Target;
      }
    }
    if (best == InvalidIndex || !this->Search.FlipsFromFan(best, this->SearchFlips))
    {
      return false;
    }
    this->PerformWithFlips(r, best, phase, this->SearchFlips);
    return true;
  }

  // The coarser nested levels' last step (HeldRingSearch): r is left with no collapse that keeps
  // the surface unfolded (or facing its way), so the level would keep it and every such vertex adds
  // two triangles: on the noisy scan scan-48 (reduction 0.8) the coarsest level asked for 169
  // vertices kept 446 of the finer level's, 296 of them held by folds. Turk's removal of r (section
  // 4.3): its whole ring re-triangulated by the search, taken only when every tile faces the
  // surface's way without a needle, made as the collapse onto the ring vertex that is a corner of
  // most of its tiles among those whose collapse keeps the topology (its fan may fold: the flips
  // that follow unfold it, and the level interpolation's tracking lays a folding fan's ring out on
  // a circle), then the flips, recorded. Only here: each search's flips cut the level
  // interpolation's fragments again (RemoveByRingSearch), and these vertices are few.
  bool RemoveHeldByRingSearch(Index r, const std::vector<Index>& neighbors)
  {
    if (!this->HeldRingSearch || !this->LastStep || neighbors.size() > MaximumDeferredValence ||
      (!this->Lines.empty() && !this->Lines[r].empty()))
    {
      return false;
    }
    this->Search.MinimumFacing = 0.0;
    this->Search.MinimumAngle = RingNeedleAngle;
    this->Search.InputSurface = nullptr; // only a valid triangulation is taken here
    bool valid = false;
    double worst = 0, smallest = 0;
    if (!this->Search.Find(r, valid, worst, smallest) || smallest < RingNeedleAngle || !valid)
    {
      return false;
    }
    // The surface moves at most as the repair lets it (MovedShare of the tiles' longest edge).
    double distance = 0, longestEdge = 0;
    this->Search.Deviation(this->Edit.Point(r), distance, longestEdge);
    if (distance > MovedShare * longestEdge)
    {
      return false;
    }
    CollapseOptions topologyOnly = this->Collapse;
    topologyOnly.MinimumNormalDot = -1.0; // only degenerate tiles of the fan are refused
    Index best = InvalidIndex;
    int bestTiles = 0;
    for (Index c : neighbors)
    {
      const Index pair[2] = { r, c };
      const int tiles = this->Search.TilesAt(c);
      if (tiles > bestTiles &&
        this->Edit.CheckCollapse(pair, 2, this->Edit.Point(c), topologyOnly) == CollapseStatus::Ok)
      {
        bestTiles = tiles;
        best = c;
      }
    }
    if (best == InvalidIndex || !this->Search.FlipsFromFan(best, this->SearchFlips))
    {
      return false;
    }
    // A collapse onto c where c is (phase 0's kind: the last step's phase 2 would move c onto r).
    this->PerformWithFlips(r, best, 0, this->SearchFlips);
    return true;
  }

  // Step 5's last step once more after step 6's shape flips, when feature lines are kept (the
  // strict removal: facing enforced, a line vertex only collapses along its line): the flips change
  // the tiles a collapse would leave, so a vertex every collapse of which turned a tile over may
  // now have one that does not. Fandisk at 700 points kept a crease vertex whose two collapses
  // along its line each turned a tile over, and missed its count by one; anchor_dense kept one at
  // 7 of 20 settings, now at 1. Not without kept lines: on a noisy scan the retry removed 43 of
  // 1,900 vertices held by folds, which changed the count attempts and cost one more (20% CPU).
  // Only collapses whose fan faces the surface's way. Bounded: one walk over the old vertices per
  // phase. Returns the number removed.
  Index RetryRemovalAfterFlips()
  {
    if (this->Lines.empty())
    {
      return 0;
    }
    std::vector<Index> neighbors;
    this->LastStep = true;
    this->MinimumFacing = -0.5;
    this->MinimumAngleFloor = 0.0;
    Index removed = 0;
    for (int phase = 0; phase < 3; ++phase)
    {
      for (Index r = 0; r < this->OldVertices; ++r)
      {
        if (this->Edit.IsVertexAlive(r) && !this->Locked[r] && this->KeptFor[r] == InvalidIndex)
        {
          const Index best = this->ChooseTarget(r, phase, neighbors);
          if (best != InvalidIndex && !this->FanFacesWrong(best))
          {
            this->Perform(r, best, phase);
            ++removed;
          }
        }
      }
    }
    return removed;
  }

  // After the flips that follow the removal (step 6's and the repair's): they change the rings,
  // so a kept vertex may now have one the search can re-triangulate (HeldRingSearch). Bounded:
  // 32 passes over the old vertices, while one goes.
  void RemoveHeldAfterFlips()
  {
    std::vector<Index> neighbors;
    this->LastStep = true;
    bool progressed = true;
    for (int pass = 0; pass < 32 && progressed; ++pass)
    {
      progressed = false;
      for (Index r = 0; r < this->OldVertices; ++r)
      {
        if (this->Edit.IsVertexAlive(r) && !this->Locked[r] && this->KeptFor[r] == InvalidIndex)
        {
          this->Edit.Neighbors(r, neighbors);
          progressed = this->RemoveHeldByRingSearch(r, neighbors) || progressed;
        }
      }
    }
  }

  // Phase 0: collapse onto candidate vertices only; phase 1 (for old vertices walled in by
  // other old vertices): onto any neighbour, the target being removed later in turn; phase 2
  // (last resort, keeps the vertex count exact): a neighbouring candidate moves onto the old
  // vertex (still a point of the surface) and takes its place.
  // Phases 3-5 repeat 0-2 for the few old vertices left where the surface curves strongly
  // between candidates (thin parts): a new triangle may then face up to 60 degrees past
  // perpendicular to the original normal at one of its vertices (never flip against the mesh
  // it replaces: CheckCollapse still rejects turns beyond 90 degrees).
  // Returns false when aborted.
  bool Run(const RetilingOptions& options)
  {
    const Index n0 = this->OldVertices;
    // The strict removal comes with kept feature lines only: where none are kept (ignored as too
    // dense: noisy scans, isosurfaces, coarse meshes) it held more original vertices, cost twice
    // the time and left degenerate tiles on noisy scans (Documentation/Retile.md, Session 15).
    this->Strict = options.PreserveCreases && !this->Lines.empty();
    this->EnforceFacing = options.EnforceFacing && !this->Strict;
    this->RetriangulateRings = options.RetriangulateRings;
    std::vector<Index> neighbors, pending;
    pending.reserve(n0);
    for (Index v = 0; v < n0; ++v)
    {
      if (this->KeptFor[v] == InvalidIndex && !this->Locked[v])
      {
        pending.push_back(v);
      }
    }
    for (int step = 0; step < 6 && !pending.empty(); ++step)
    {
      vtkLogF(TRACE, "retile removal step %d: %zu old vertices pending", step, pending.size());
      this->LastStep = step == 5;
      const int phase = step % 3;
      this->MinimumFacing = step < 3 ? 0.0 : -0.5;
      // With PreserveCreases, the first round leaves no needle: such a collapse waits for a
      // later phase's better option.
      this->MinimumAngleFloor = step < 3 && this->Strict ? NeedleFloor : 0.0;
      for (int pass = 0; pass < 32 && !pending.empty(); ++pass)
      {
        std::vector<Index> next;
        for (size_t i = 0; i < pending.size(); ++i)
        {
          const Index r = pending[i];
          if ((i & 1023) == 0 &&
            !ReportProgress(options, 0.65 + 0.25 * (1.0 - double(pending.size() - i) / std::max<Index>(n0, 1))))
          {
            return false;
          }
          if (!this->Edit.IsVertexAlive(r))
          {
            continue;
          }
          const Index best = this->ChooseTarget(r, phase, neighbors);
          const bool fanFacesWrong = best == InvalidIndex || this->FanFacesWrong(best);
          if (fanFacesWrong && !this->Valid.empty() && neighbors.size() <= MaximumDeferredValence &&
            (this->RemoveByRingSearch(r, phase, best != InvalidIndex) || (this->RetriangulateRings && this->RemoveByRingFlips(r, phase))))
          {
            continue;
          }
          if (best == InvalidIndex && this->RemoveHeldByRingSearch(r, neighbors))
          {
            continue;
          }
          if (best == InvalidIndex)
          {
            next.push_back(r);
            continue;
          }
          this->Perform(r, best, phase);
        }
        const bool progressed = next.size() < pending.size();
        pending.swap(next);
        if (!progressed)
        {
          break;
        }
      }
    }
    if (vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE)
    {
      this->LogWhyRetained(pending);
    }
    return true;
  }

  // TRACE: why the old vertices left could not go: every collapse onto a neighbour breaks the
  // topology (link condition, boundary, too small: small handles and thin parts), or some
  // collapse would only fold the surface.
  void LogWhyRetained(const std::vector<Index>& pending) const
  {
    CollapseOptions topologyFirst = this->Collapse;
    topologyFirst.GeometryFirst = false;
    long long topology = 0, geometry = 0;
    std::vector<Index> neighbors;
    for (Index r : pending)
    {
      if (!this->Edit.IsVertexAlive(r))
      {
        continue;
      }
      this->Edit.Neighbors(r, neighbors);
      bool anyTopologicallyValid = false;
      for (Index c : neighbors)
      {
        const Index pair[2] = { r, c };
        const CollapseStatus status = this->Edit.CheckCollapse(pair, 2, this->Edit.Point(c), topologyFirst);
        anyTopologicallyValid = anyTopologicallyValid ||
          (status != CollapseStatus::NonManifold && status != CollapseStatus::BoundaryChange &&
            status != CollapseStatus::TooSmall && status != CollapseStatus::IsolatedVertex);
      }
      ++(anyTopologicallyValid ? geometry : topology);
    }
    vtkLogF(TRACE, "retile removal: %lld old vertices left held by the topology (every collapse), %lld by folds",
      topology, geometry);
  }
};

// Whether flipping edge (x, y) of triangle (x, y, q) to (q, z) improves the triangle shapes
// without folding a nearly planar quad or turning against the original surface.
bool FlipImprovesShape(const EditableMesh& edit, const std::vector<Vec3>& reference, Index x, Index y, Index q, Index z)
{
  const Vec3 X = edit.Point(x), Y = edit.Point(y), Q = edit.Point(q), Z = edit.Point(z);
  const double before = std::min(MinimumAngle(X, Y, Q), MinimumAngle(Y, X, Z));
  const double after = std::min(MinimumAngle(X, Z, Q), MinimumAngle(Z, Y, Q));
  if (!(after > before + 1e-3))
  {
    return false;
  }
  const Vec3 n0o = TriangleNormal(X, Y, Q), n1o = TriangleNormal(Y, X, Z);
  const Vec3 m0 = TriangleNormal(X, Z, Q), m1 = TriangleNormal(Z, Y, Q);
  // Nearly planar quads only, and no turn against the original surface.
  const double dihedralBefore = Dot(n0o, n1o), dihedralAfter = Dot(m0, m1);
  if (dihedralAfter < std::min(dihedralBefore, 0.985) || Dot(m0, n0o + n1o) <= 0 || Dot(m1, n0o + n1o) <= 0)
  {
    return false;
  }
  const Index tri0[3] = { x, z, q }, tri1[3] = { z, y, q };
  bool facing = true;
  for (int j = 0; j < 3; ++j)
  {
    facing = facing && Dot(m0, reference[tri0[j]]) > 0 && Dot(m1, reference[tri1[j]]) > 0;
  }
  return facing;
}

// The apex z of the triangle across plain manifold edge (x, y) from triangle t (InvalidIndex when
// the edge has another number of triangles or they are inconsistently oriented).
Index OppositeApex(const EditableMesh& edit, Index t, Index x, Index y)
{
  Index z = InvalidIndex;
  int count = 0;
  edit.ForEachTriangle(x, [&](Index u) {
    if (u == t)
    {
      return;
    }
    const Index* o = edit.Triangle(u);
    for (int j = 0; j < 3; ++j)
    {
      if (o[j] == y && o[(j + 1) % 3] == x)
      {
        z = o[(j + 2) % 3];
        ++count;
      }
      else if (o[j] == x && o[(j + 1) % 3] == y)
      {
        count += 2; // same orientation or more triangles: not a plain manifold edge
      }
    }
  });
  return count == 1 ? z : InvalidIndex;
}

// Step 6 (section 4.5): shape improvement by edge flips. Returns the number of flips. record
// (optional): each flip of edge (x, y) as the pair (-1 - x, y).
Index ImproveShapeByFlips(EditableMesh& edit, const std::vector<Vec3>& reference, int passes,
  const OldVertexRemoval& removal, std::vector<Index>* record = nullptr)
{
  Index flips = 0;
  for (int pass = 0; pass < passes; ++pass)
  {
    Index passFlips = 0;
    for (Index t = 0; t < edit.NumberOfTriangles(); ++t)
    {
      for (int k = 0; k < 3 && edit.IsTriangleAlive(t); ++k)
      {
        const Index* tri = edit.Triangle(t);
        const Index x = tri[k], y = tri[(k + 1) % 3], q = tri[(k + 2) % 3];
        if (x > y)
        {
          continue; // each edge once (the other triangle sees (y, x))
        }
        const Index z = OppositeApex(edit, t, x, y);
        if (z == InvalidIndex || z == q || removal.IsLineEdge(x, y) || !FlipImprovesShape(edit, reference, x, y, q, z) ||
          !edit.FlipEdge(x, y))
        {
          continue;
        }
        if (record)
        {
          record->push_back(-1 - x);
          record->push_back(y);
        }
        ++passFlips;
      }
    }
    flips += passFlips;
    if (passFlips == 0)
    {
      break;
    }
  }
  return flips;
}

// Smallest angle and shortest edge (share of the input's diagonal) of a tile RepairTiles accepts:
// below them a tile is a needle. At 2 degrees (until session 34) the repair never worked on the
// tiles of 2-5 degrees, most of the needles left (138 CGAL meshes at 50% of their vertices:
// 1,538 under 5 degrees, 555 with 5).
constexpr double RepairNeedleAngle = Radians(5.0);
constexpr double RepairShortestEdge = 1e-5;
constexpr int RepairPasses = 8;
// Rounds of the final stage on the flipped tiles (RetilingOptions::RepairFlippedTiles), and of
// the needle stage after it (RetilingOptions::RepairNeedleTiles).
constexpr int FlippedRepairRounds = 4;
constexpr int NeedleRepairRounds = 4;
int NeedleRounds(const RetilingOptions& options)
{
  return options.RepairFlippedTiles && options.RepairNeedleTiles ? NeedleRepairRounds : 0;
}

// The last check (slodRetileRepair.h) after step 6: tiles facing against the input or needles
// are repaired by flips (recorded in `record` when given) and moves of the `movable` vertices
// (`moved` says where each went); then, with `flippedRounds`, the final stage on the tiles still
// facing against the input under their centroids (TileRepair::RunFlipped), and with
// `needleRounds` the needle stage after it (TileRepair::RunNeedles). Returns the number of flips.
Index RepairTiles(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<Vec3>& inputNormals,
  const OldVertexRemoval& removal, const std::vector<unsigned char>& movable, EditableMesh& edit,
  std::vector<Vec3>& reference, std::vector<Index>* record,
  const std::function<void(Index, const Vec3&, Index)>& moved, int flippedRounds = 0, int needleRounds = 0,
  const decltype(TileRepair::AlongCrease)& alongCrease = nullptr, std::vector<Index> movableInFinalStage = {})
{
  TileRepair repair(edit, reference, mesh, bvh, movable);
  repair.AlongCrease = alongCrease;
  repair.MovableInFinalStage = std::move(movableInFinalStage);
  repair.IsFixedEdge = [&](Index x, Index y) { return removal.IsLineEdge(x, y); };
  repair.NormalAt = [&](const Vec3& position, Index t) {
    const Index* tri = mesh.Triangle(t);
    const Vec3 w = Barycentric(position, mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]));
    return InterpolatedNormal(mesh, inputNormals, t, w.data());
  };
  repair.Moved = moved;
  repair.Record = record;
  repair.LastResort = record == nullptr; // not on the coarser nested levels (slodRetileRepair.h)
  repair.NeedleAngle = RepairNeedleAngle;
  repair.ShortestEdge = RepairShortestEdge * mesh.BoundingBoxDiagonal();
  repair.Run(RepairPasses);
  if (flippedRounds > 0)
  {
    repair.RunFlipped(flippedRounds);
    if (needleRounds > 0)
    {
      // After the flipped stage: its changes may leave needles, and the needle stage may not
      // add a flipped tile back.
      repair.RunNeedles(needleRounds);
    }
  }
  return repair.Flips;
}

// Renumbers the vertices of `output` in increasing key order; `ids` (one per vertex) follows.
template <typename Key>
void SortVerticesByKey(TriangleMesh& output, std::vector<Index>& ids, Key key)
{
  const size_t count = ids.size();
  std::vector<Index> perm(count), rank(count);
  std::iota(perm.begin(), perm.end(), 0);
  std::sort(perm.begin(), perm.end(), [&](Index a, Index b) { return key(a) < key(b); });
  std::vector<double> sortedPoints(3 * count);
  std::vector<Index> sortedIds(count);
  for (size_t i = 0; i < count; ++i)
  {
    rank[perm[i]] = static_cast<Index>(i);
    std::copy(&output.Points[3 * size_t(perm[i])], &output.Points[3 * size_t(perm[i])] + 3, &sortedPoints[3 * i]);
    sortedIds[i] = ids[perm[i]];
  }
  for (Index& v : output.Triangles)
  {
    v = rank[v];
  }
  output.Points.swap(sortedPoints);
  ids.swap(sortedIds);
}

// Candidate order first (output vertex i = candidate i; a pinned candidate's slot holds the old
// vertex it stands for), retained old vertices last: stable ids across seeds' levels and the
// nested levels' subset property. newToOld: mutual-tessellation id of every output vertex.
void SortCandidatesFirst(
  Index n0, Index np, const std::vector<Index>& keptFor, TriangleMesh& output, std::vector<Index>& newToOld)
{
  const std::vector<Index> ids = newToOld;
  SortVerticesByKey(output, newToOld, [&](Index v) {
    const Index id = ids[v];
    return id >= n0 ? id - n0 : (keptFor[id] != InvalidIndex ? keptFor[id] : np + id);
  });
}

// Where every output vertex lies on the input (host triangle and barycentric coordinates), for
// interpolating point attributes.
void RecordHostLocations(const TriangleMesh& mesh, const std::vector<SurfacePoint>& points,
  const std::vector<double>& bary, const OldVertexRemoval& removal, const std::vector<Index>& newToOld,
  const std::unordered_map<Index, SurfacePoint>& movedRetained, RetilingResult& result)
{
  const std::vector<Index>& movedTo = removal.MovedTo;
  const Index n0 = mesh.NumberOfPoints();
  const Index nt = mesh.NumberOfTriangles();
  std::vector<Index> firstTriangle(n0, InvalidIndex);
  for (Index t = nt - 1; t >= 0; --t)
  {
    for (int k = 0; k < 3; ++k)
    {
      firstTriangle[mesh.Triangle(t)[k]] = t;
    }
  }
  // An old vertex's location: a corner of its first triangle.
  auto atOldVertex = [&](size_t v, Index old) {
    result.InputVertex[v] = old;
    const Index t = firstTriangle[old];
    result.HostTriangle[v] = t;
    for (int k = 0; k < 3; ++k)
    {
      result.Barycentric[3 * v + k] = mesh.Triangle(t)[k] == old ? 1.0 : 0.0;
    }
  };
  const size_t nv = newToOld.size();
  result.HostTriangle.resize(nv);
  result.Barycentric.assign(3 * nv, 0.0);
  result.InputVertex.assign(nv, InvalidIndex);
  result.Candidate.assign(nv, InvalidIndex);
  result.CandidatePoints = static_cast<Index>(points.size());
  for (size_t v = 0; v < nv; ++v)
  {
    const Index id = newToOld[v];
    result.Candidate[v] = id >= n0 ? id - n0 : removal.KeptFor[id];
    if (id >= n0 && movedTo[id - n0] != InvalidIndex)
    {
      atOldVertex(v, movedTo[id - n0]);
    }
    else if (id >= n0)
    {
      result.HostTriangle[v] = points[id - n0].Triangle;
      std::copy(&bary[3 * size_t(id - n0)], &bary[3 * size_t(id - n0)] + 3, &result.Barycentric[3 * v]);
    }
    else
    {
      result.RetainedOldVertices += removal.KeptFor[id] == InvalidIndex ? 1 : 0;
      const auto moved = movedRetained.find(id);
      if (moved == movedRetained.end())
      {
        atOldVertex(v, id);
        continue;
      }
      // Moved by the final stage: it stands where it went, no longer at its input vertex.
      const Index t = moved->second.Triangle;
      const Index* tri = mesh.Triangle(t);
      const Vec3 w = Barycentric(moved->second.Position, mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]));
      result.HostTriangle[v] = t;
      std::copy(w.begin(), w.end(), &result.Barycentric[3 * v]);
    }
  }
}

// The retained original vertices the final stage may move (MoveRetainedVertices): alive after the
// removal, standing for no candidate, not locked (non-manifold), on a border or a kept line.
std::vector<Index> MovableRetainedVertices(const EditableMesh& edit, const OldVertexRemoval& removal, Index n0)
{
  std::vector<Index> retained;
  for (Index v = 0; v < n0; ++v)
  {
    const bool onLine = !removal.Lines.empty() && !removal.Lines[v].empty();
    if (edit.IsVertexAlive(v) && removal.KeptFor[v] == InvalidIndex && !removal.Locked[v] && !removal.OnBorder[v] &&
      !onLine)
    {
      retained.push_back(v);
    }
  }
  return retained;
}

// Candidates nudged inside their triangle (MoveCandidatesInside) stand this far from a side they
// were on (a barycentric coordinate).
constexpr double NudgedOnCreaseTolerance = 1.5e-4;

// The repair's AlongCrease for candidate v (v - n0 in `points`, its host): slides along the
// crease it stands on; none without creases.
decltype(TileRepair::AlongCrease) AlongCreaseOf(
  const CreasePolylines* creases, const std::vector<SurfacePoint>& points, Index n0)
{
  if (!creases)
  {
    return nullptr;
  }
  return [creases, &points, n0](
           Index v, const Vec3& start, const Vec3& target, const Vec3& reference, ClosestPointResult& c) {
    if (v < n0 || v - n0 >= static_cast<Index>(points.size()))
    {
      return false;
    }
    const Index host = points[v - n0].Triangle;
    const Index s = creases->SegmentAt(host, start, NudgedOnCreaseTolerance);
    if (s == InvalidIndex)
    {
      return false;
    }
    c = creases->Slide(s, start, target - start, reference);
    return true;
  };
}

// Steps 4-6 on given candidate points (their positions may be adjusted: moved strictly inside
// their triangle). Keeps the spacing figures already in result.
void TileWithPoints(const TriangleMesh& mesh, const TriangleBVH& bvh, std::vector<SurfacePoint>& points,
  const RetilingOptions& options, const CoarserLevel& coarser, RetilingResult& result)
{
  const Index n0 = mesh.NumberOfPoints();
  const Index np = static_cast<Index>(points.size());
  const CandidatesByTriangle buckets = BucketCandidates(points, mesh.NumberOfTriangles(), coarser);
  MoveCandidatesInside(mesh, points, coarser);
  TriangleMesh mutual;
  std::vector<double> bary;
  vtkLogStartScopeF(TRACE, "retile-mutual", "retile: mutual tessellation");
  MutualTessellation(mesh, points, buckets, coarser.FixedCount, mutual, bary);
  vtkLogEndScope("retile-mutual");
  if (!ReportProgress(options, 0.65))
  {
    AbortResult(result);
    return;
  }
  std::vector<Vec3> reference = ReferenceNormals(mesh, points, bary);
  EditableMesh edit(mutual);
  std::vector<unsigned char> computedFlags;
  if (!options.NonManifoldVertices)
  {
    computedFlags = NonManifoldVertexFlags(mesh);
  }
  OldVertexRemoval removal(
    edit, reference, n0, np, coarser, options.NonManifoldVertices ? *options.NonManifoldVertices : computedFlags);
  removal.InputSurface = options.RingSearchFacesInput ? &bvh : nullptr;
  vtkLogStartScopeF(TRACE, "retile-removal", "retile: old-vertex removal");
  const bool removed = removal.Run(options);
  vtkLogEndScope("retile-removal");
  if (!removed)
  {
    AbortResult(result);
    return;
  }
  vtkLogStartScopeF(TRACE, "retile-flips", "retile: shape flips");
  result.Flips = ImproveShapeByFlips(edit, reference, options.ShapeImprovementPasses, removal);
  if (removal.RetryRemovalAfterFlips() > 0)
  {
    result.Flips += ImproveShapeByFlips(edit, reference, options.ShapeImprovementPasses, removal);
  }
  vtkLogEndScope("retile-flips");
  if (options.ContinueWithCounts)
  {
    edit.Extract(result.Mesh);
    if (!options.ContinueWithCounts(result.Mesh.NumberOfPoints(), result.Mesh.NumberOfTriangles()))
    {
      result.Stopped = true;
      return;
    }
  }
  // The free candidates may move (on the input surface): not a coarser level's, nor one on a
  // border or a feature line. One standing on an old vertex (phase 2) no longer does once moved.
  std::vector<unsigned char> movable(size_t(edit.NumberOfPoints()), 0);
  for (Index i = coarser.FixedCount; i < np; ++i)
  {
    const bool onLine = !removal.Lines.empty() && !removal.Lines[n0 + i].empty();
    movable[n0 + i] = !removal.OnBorder[n0 + i] && !removal.Locked[n0 + i] && !onLine;
  }
  std::vector<Vec3> vertexNormals;
  VertexNormals(mesh, vertexNormals);
  vtkLogStartScopeF(TRACE, "retile-repair", "retile: repair");
  std::unordered_map<Index, SurfacePoint> movedRetained; // retained old vertices the final stage moved
  result.Flips += RepairTiles(mesh, bvh, vertexNormals, removal, movable, edit, reference, nullptr,
    [&](Index v, const Vec3& position, Index triangle) {
      if (v < n0)
      {
        movedRetained[v] = SurfacePoint{ position, triangle };
        return;
      }
      removal.MovedTo[v - n0] = InvalidIndex;
      points[v - n0] = SurfacePoint{ position, triangle };
      const Index* tri = mesh.Triangle(triangle);
      const Vec3 w = Barycentric(position, mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]));
      std::copy(w.begin(), w.end(), &bary[3 * size_t(v - n0)]);
    },
    options.RepairFlippedTiles ? FlippedRepairRounds : 0, NeedleRounds(options),
    AlongCreaseOf(coarser.Creases, points, n0),
    options.RepairFlippedTiles && options.MoveRetainedVertices
      ? MovableRetainedVertices(edit, removal, n0)
      : std::vector<Index>());
  vtkLogEndScope("retile-repair");
  if (!ReportProgress(options, 0.97))
  {
    AbortResult(result);
    return;
  }
  std::vector<Index> newToOld;
  edit.Extract(result.Mesh, &newToOld);
  SortCandidatesFirst(n0, np, removal.KeptFor, result.Mesh, newToOld);
  RecordHostLocations(mesh, points, bary, removal, newToOld, movedRetained, result);
  ReportProgress(options, 1.0);
}
} // namespace

namespace
{
// What the input surface faces at each vertex of a re-tiling: its vertex normals interpolated at
// the vertex's host location.
std::vector<Vec3> HostNormals(const TriangleMesh& mesh, const std::vector<Vec3>& inputNormals, const RetilingResult& level)
{
  std::vector<Vec3> normals(size_t(level.Mesh.NumberOfPoints()));
  for (size_t v = 0; v < normals.size(); ++v)
  {
    normals[v] = InterpolatedNormal(mesh, inputNormals, level.HostTriangle[v], &level.Barycentric[3 * v]);
  }
  return normals;
}

// Section 6.2's removal: every vertex of `fine` not flagged in `keep` is removed by the
// re-tiling's own step 5 (phases 0-1 and their relaxed repeat, facing tested against the input's
// normals; phase 2 never applies since every kept vertex is fixed), then step 6's flips; each
// collapse and flip is recorded (coarse.Removals, in the finer level's ids). The survivors keep the
// finer level's order; those not kept (no collapse allowed) count in coarse.RetainedOldVertices.
// `flippedRounds` > 0: the repair's final stage (and `needleRounds` > 0 its needle stage) too
// (RepairTiles; their flips are recorded with the others: only for a result no level
// interpolation replays, the exact count's trim). Returns false when aborted.
bool RemoveUnkeptVertices(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<Vec3>& inputNormals,
  const RetilingResult& fine, const std::vector<unsigned char>& keep, const RetilingOptions& options,
  RetilingResult& coarse, std::vector<Index>& survivors, int flippedRounds = 0, int needleRounds = 0)
{
  const Index n = fine.Mesh.NumberOfPoints();
  auto kept = [&](Index v) { return keep[v] != 0; };
  // The removal's layout: the vertices to remove first ("old"), then the kept ones.
  std::vector<Index> order, rank(static_cast<size_t>(n));
  order.reserve(size_t(n));
  for (int pass = 0; pass < 2; ++pass)
  {
    for (Index v = 0; v < n; ++v)
    {
      if (kept(v) == (pass == 1))
      {
        rank[v] = static_cast<Index>(order.size());
        order.push_back(v);
      }
    }
  }
  const Index removable = n - static_cast<Index>(std::count_if(order.begin(), order.end(), kept));
  TriangleMesh layout;
  for (Index v : order)
  {
    layout.AddPoint(fine.Mesh.Point(v));
  }
  layout.Triangles = fine.Mesh.Triangles;
  for (Index& v : layout.Triangles)
  {
    v = rank[v];
  }
  const std::vector<Vec3> hostNormals = HostNormals(mesh, inputNormals, fine);
  std::vector<Vec3> reference(static_cast<size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    reference[i] = hostNormals[order[i]];
  }
  EditableMesh edit(layout);
  CoarserLevel allFixed;
  allFixed.FixedCount = n - removable;
  // The finer level's non-manifold vertices (kept from a non-manifold input) stay, as in step 5.
  const std::vector<unsigned char> locked = NonManifoldVertexFlags(layout);
  OldVertexRemoval removal(edit, reference, removable, n - removable, allFixed, locked);
  std::vector<Index> record;
  removal.Record = &record;
  removal.BorderAlongBorder = true;
  removal.HeldRingSearch = true;
  RetilingOptions removalOptions = options;
  removalOptions.PreserveCreases = false;
  if (!removal.Run(removalOptions))
  {
    return false;
  }
  coarse.Flips = ImproveShapeByFlips(edit, reference, options.ShapeImprovementPasses, removal, &record);
  // Every vertex is the finer level's: the repair only flips (recorded with the others).
  const std::vector<unsigned char> fixedVertices(size_t(n), 0);
  coarse.Flips += RepairTiles(
    mesh, bvh, inputNormals, removal, fixedVertices, edit, reference, &record, nullptr, flippedRounds, needleRounds);
  removal.RemoveHeldAfterFlips();
  edit.Extract(coarse.Mesh, &survivors);
  for (Index& id : survivors)
  {
    id = order[id];
  }
  const std::vector<Index> fineIds = survivors;
  SortVerticesByKey(coarse.Mesh, survivors, [&](Index v) { return fineIds[v]; });
  coarse.Removals.resize(record.size());
  std::transform(record.begin(), record.end(), coarse.Removals.begin(),
    [&](Index id) { return id >= 0 ? order[id] : -1 - order[-1 - id]; });
  const size_t nv = survivors.size();
  coarse.HostTriangle.resize(nv);
  coarse.Barycentric.resize(3 * nv);
  coarse.InputVertex.resize(nv);
  coarse.Candidate.resize(nv);
  for (size_t v = 0; v < nv; ++v)
  {
    const Index f = survivors[v];
    coarse.HostTriangle[v] = fine.HostTriangle[f];
    std::copy_n(&fine.Barycentric[3 * size_t(f)], 3, &coarse.Barycentric[3 * v]);
    coarse.InputVertex[v] = fine.InputVertex[f];
    coarse.Candidate[v] = fine.Candidate[f];
    coarse.RetainedOldVertices += kept(f) ? 0 : 1;
  }
  return true;
}

// Section 6.2: a coarser nested level from the next finer one, keeping the first `keep`
// candidates (so the first vertices are the kept candidates in candidate order).
bool DeriveCoarserLevel(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<Vec3>& inputNormals,
  const RetilingResult& fine, Index keep, const RetilingOptions& options, RetilingResult& coarse,
  std::vector<Index>& survivors)
{
  std::vector<unsigned char> kept(size_t(fine.Mesh.NumberOfPoints()), 0);
  for (size_t v = 0; v < kept.size(); ++v)
  {
    kept[v] = fine.Candidate[v] != InvalidIndex && fine.Candidate[v] < keep;
  }
  coarse.CandidatePoints = keep;
  return RemoveUnkeptVertices(mesh, bvh, inputNormals, fine, kept, options, coarse, survivors);
}

// The free candidates of a re-tiling (not on a kept line, nor in `avoid`: sorted candidate ids, nor next
// to a retained old vertex: those sit in the thin parts and small handles where the topology holds
// them, nor of valence 3: a tetrahedral component's), most crowded first (shortest edge), none
// next to another one chosen: up to `count`.
std::vector<Index> CrowdedCandidates(const RetilingResult& result, Index count, const std::vector<Index>& avoid)
{
  const TriangleMesh& m = result.Mesh;
  const size_t nv = size_t(m.NumberOfPoints());
  const MeshTopology topology(m);
  // Calls visit(w) for every neighbour w of v (twice for an inner edge: once per triangle).
  const auto forNeighbors = [&](Index v, auto&& visit) {
    for (const Index* t = topology.VertexTrianglesBegin(v); t != topology.VertexTrianglesEnd(v); ++t)
    {
      const Index* tri = m.Triangle(*t);
      for (int k = 0; k < 3; ++k)
      {
        if (tri[k] != v)
        {
          visit(tri[k]);
        }
      }
    }
  };
  std::vector<double> shortest(nv, std::numeric_limits<double>::infinity());
  std::vector<Index> order;
  for (size_t v = 0; v < nv; ++v)
  {
    forNeighbors(Index(v), [&](Index w) { shortest[v] = std::min(shortest[v], Norm(m.Point(Index(v)) - m.Point(w))); });
    // More than three triangles: an inner vertex of valence 3 (a tetrahedral component's) stays.
    const auto triangles = topology.VertexTrianglesEnd(Index(v)) - topology.VertexTrianglesBegin(Index(v));
    if (result.Candidate[v] != InvalidIndex && result.Candidate[v] >= result.FeatureVertices && triangles > 3 &&
      !std::binary_search(avoid.begin(), avoid.end(), result.Candidate[v]))
    {
      order.push_back(Index(v));
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return shortest[a] < shortest[b]; });
  std::vector<unsigned char> blocked(nv, 0);
  const auto block = [&](Index w) { blocked[w] = 1; };
  for (size_t v = 0; v < nv; ++v)
  {
    if (result.Candidate[v] == InvalidIndex)
    {
      forNeighbors(Index(v), block);
    }
  }
  std::vector<Index> chosen;
  for (size_t i = 0; i < order.size() && Index(chosen.size()) < count; ++i)
  {
    if (!blocked[order[i]])
    {
      chosen.push_back(order[i]);
      forNeighbors(order[i], block);
    }
  }
  return chosen;
}
} // namespace

namespace
{
// One round of RemoveCandidates: up to `count` crowded candidates out; those that stay go to
// `stayed`. False when aborted.
bool RemoveCandidatesOnce(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<Vec3>& inputNormals,
  const RetilingOptions& options, Index count, RetilingResult& result, std::vector<Index>& stayed)
{
  const std::vector<Index> chosen = CrowdedCandidates(result, count, stayed);
  if (chosen.empty())
  {
    return true;
  }
  std::vector<unsigned char> kept(size_t(result.Mesh.NumberOfPoints()), 1);
  for (Index v : chosen)
  {
    kept[v] = 0;
  }
  RetilingResult fewer;
  std::vector<Index> survivors;
  // The trimmed re-tiling is the output, not a level the interpolation replays: its removals
  // leave flipped tiles as the re-tiling's did, so the final stage runs on it too (flips only:
  // every vertex stays where the re-tiling put it).
  const int flippedRounds = options.RepairFlippedTiles ? FlippedRepairRounds : 0;
  if (!RemoveUnkeptVertices(
        mesh, bvh, inputNormals, result, kept, options, fewer, survivors, flippedRounds, NeedleRounds(options)))
  {
    return false;
  }
  result.Mesh = std::move(fewer.Mesh);
  result.HostTriangle = std::move(fewer.HostTriangle);
  result.Barycentric = std::move(fewer.Barycentric);
  result.InputVertex = std::move(fewer.InputVertex);
  result.Candidate = std::move(fewer.Candidate);
  result.Flips += fewer.Flips;
  for (size_t v = 0; v < survivors.size(); ++v)
  {
    if (!kept[survivors[v]])
    {
      stayed.push_back(result.Candidate[v]);
    }
  }
  std::sort(stayed.begin(), stayed.end());
  return true;
}
} // namespace

bool RemoveCandidates(const TriangleMesh& mesh, const RetilingOptions& options, Index wanted, int maximumRounds,
  RetilingResult& result)
{
  if (result.Mesh.NumberOfPoints() <= wanted)
  {
    return true;
  }
  // The input's search structures, built once for every round.
  const TriangleBVH bvh(mesh);
  std::vector<Vec3> inputNormals;
  VertexNormals(mesh, inputNormals);
  std::vector<Index> stayed;
  for (int round = 0; round < maximumRounds && result.Mesh.NumberOfPoints() > wanted; ++round)
  {
    const Index before = result.Mesh.NumberOfPoints();
    if (!RemoveCandidatesOnce(mesh, bvh, inputNormals, options, before - wanted, result, stayed))
    {
      return false;
    }
    vtkLogF(TRACE, "retile exact count: %lld -> %lld vertices (%lld asked)", static_cast<long long>(before),
      static_cast<long long>(result.Mesh.NumberOfPoints()), static_cast<long long>(wanted));
  }
  return true;
}

namespace
{

// Renumbers the vertices of a level (newToOld: old id of every new id) with everything stored per vertex.
void RenumberLevel(RetilingResult& level, const std::vector<Index>& newToOld, const std::vector<Index>& oldToNew)
{
  const size_t nv = newToOld.size();
  RetilingResult old;
  old.Mesh.Points.swap(level.Mesh.Points);
  old.HostTriangle.swap(level.HostTriangle);
  old.Barycentric.swap(level.Barycentric);
  old.InputVertex.swap(level.InputVertex);
  old.Candidate.swap(level.Candidate);
  level.Mesh.Points.resize(3 * nv);
  level.HostTriangle.resize(nv);
  level.Barycentric.resize(3 * nv);
  level.InputVertex.resize(nv);
  level.Candidate.resize(nv);
  for (size_t v = 0; v < nv; ++v)
  {
    const size_t o = size_t(newToOld[v]);
    std::copy_n(&old.Mesh.Points[3 * o], 3, &level.Mesh.Points[3 * v]);
    std::copy_n(&old.Barycentric[3 * o], 3, &level.Barycentric[3 * v]);
    level.HostTriangle[v] = old.HostTriangle[o];
    level.InputVertex[v] = old.InputVertex[o];
    level.Candidate[v] = old.Candidate[o];
  }
  for (Index& v : level.Mesh.Triangles)
  {
    v = oldToNew[v];
  }
}

// The subset property by id (section 6.1): every vertex of a level is the vertex of the same id
// in every finer level. A coarser level keeps the finer level's order, so only the finer vertices
// a collapse could not remove (after the level's own) break it: each finer level is renumbered to
// start with the coarser level's vertices in their order. finer[k]: per vertex of level k, its id
// in level k + 1 (kept up to date, as the removal records).
void NestedOrder(std::vector<RetilingResult>& levels, std::vector<std::vector<Index>>& finer)
{
  for (size_t k = 1; k < levels.size(); ++k)
  {
    const size_t nv = size_t(levels[k].Mesh.NumberOfPoints());
    std::vector<Index> newToOld(finer[k - 1]), oldToNew(nv, InvalidIndex);
    std::vector<char> taken(nv, 0);
    for (Index v : newToOld)
    {
      taken[v] = 1;
    }
    for (size_t v = 0; v < nv; ++v)
    {
      if (!taken[v])
      {
        newToOld.push_back(static_cast<Index>(v));
      }
    }
    for (size_t v = 0; v < nv; ++v)
    {
      oldToNew[newToOld[v]] = static_cast<Index>(v);
    }
    RenumberLevel(levels[k], newToOld, oldToNew);
    for (Index& v : finer[k - 1])
    {
      v = oldToNew[v];
    }
    for (Index& v : levels[k - 1].Removals)
    {
      v = v >= 0 ? oldToNew[v] : -1 - oldToNew[-1 - v]; // (-1 - x, y): a flip of edge (x, y)
    }
    if (k < finer.size())
    {
      std::vector<Index> permuted(nv);
      for (size_t v = 0; v < nv; ++v)
      {
        permuted[v] = finer[k][newToOld[v]];
      }
      finer[k].swap(permuted);
    }
  }
}

// Section 6.1: the points of every level, coarse to fine: each level's points stay where they are
// (and keep pushing) while the next level's are placed and relaxed. sizes[k]: the number of
// points of level k (the first sizes[k] points). Returns false when aborted.
bool PlaceNestedPoints(const TriangleMesh& mesh, const TriangleBVH& bvh, const std::vector<double>& density,
  const std::vector<Index>& counts, const RetilingOptions& options, const std::vector<unsigned char>& nonManifold,
  std::vector<SurfacePoint>& points, std::vector<Index>& sizes, Index& dropped)
{
  std::vector<SurfacePoint> added;
  const double share = 0.6 / double(counts.size());
  for (size_t k = 0; k < counts.size(); ++k)
  {
    const Index fixed = static_cast<Index>(points.size());
    DistributePoints(mesh, density, counts[k] - fixed, options.RandomSeed + k, added);
    points.insert(points.end(), added.begin(), added.end());
    auto progress = [&](double f) { return !options.Progress || options.Progress(share * (k + f)); };
    const std::vector<SurfacePoint> placed = points;
    if (!RelaxPoints(mesh, bvh, density, options.RepulsionIterations, points, progress, fixed, options.FilletDensity))
    {
      return false;
    }
    dropped += SeparateCrowdedPoints(points, placed, fixed) + DropPointsOnNonManifoldTriangles(mesh, nonManifold, points, fixed);
    // Strictly inside their triangle before they are fixed (the mutual tessellation keeps the
    // original edges unsplit).
    CoarserLevel added;
    added.FixedCount = fixed;
    MoveCandidatesInside(mesh, points, added);
    sizes.push_back(static_cast<Index>(points.size()));
  }
  return true;
}
} // namespace

void RetileNested(const TriangleMesh& mesh, std::vector<Index> counts, const RetilingOptions& options,
  std::vector<RetilingResult>& levels)
{
  levels.clear();
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  counts.erase(std::remove_if(counts.begin(), counts.end(), [](Index c) { return c < 3; }), counts.end());
  if (mesh.NumberOfTriangles() == 0 || counts.empty())
  {
    return;
  }
  // The nested levels keep no line: FilletDensity skips no vertex there.
  const std::vector<unsigned char> noLines;
  std::vector<double> density;
  CurvatureDensity(mesh, options.CurvatureWeight, density, options.FilletDensity ? &noLines : nullptr);
  const TriangleBVH bvh(mesh);
  const std::vector<unsigned char> computedFlags =
    options.NonManifoldVertices ? std::vector<unsigned char>() : NonManifoldVertexFlags(mesh);
  const std::vector<unsigned char>& nonManifold = options.NonManifoldVertices ? *options.NonManifoldVertices : computedFlags;
  std::vector<SurfacePoint> points;
  std::vector<Index> sizes;
  Index dropped = 0;
  auto aborted = [&levels]() {
    levels.assign(1, RetilingResult());
    levels[0].Aborted = true;
  };
  if (!PlaceNestedPoints(mesh, bvh, density, counts, options, nonManifold, points, sizes, dropped))
  {
    return aborted();
  }
  // The finest level from the original surface; the coarser levels' points are fixed there.
  const size_t n = sizes.size();
  levels.resize(n);
  CoarserLevel coarser;
  coarser.FixedCount = n > 1 ? sizes[n - 2] : 0;
  RetilingOptions levelOptions = options;
  levelOptions.NonManifoldVertices = &nonManifold;
  levelOptions.Progress = [&](double f) { return !options.Progress || options.Progress(0.6 + 0.25 * f); };
  TileWithPoints(mesh, bvh, points, levelOptions, coarser, levels[n - 1]);
  if (levels[n - 1].Aborted)
  {
    return aborted();
  }
  levels[n - 1].DroppedCandidates = dropped;
  // Each coarser level from the next finer one (section 6.2).
  std::vector<Vec3> inputNormals;
  VertexNormals(mesh, inputNormals);
  std::vector<std::vector<Index>> finer(n - 1);
  for (size_t k = n - 1; k-- > 0;)
  {
    levelOptions.Progress = [&](double f) {
      return !options.Progress || options.Progress(0.85 + 0.15 * (double(n - 1 - k) - 1 + f) / double(n - 1));
    };
    levels[k].DroppedCandidates = dropped;
    if (!DeriveCoarserLevel(mesh, bvh, inputNormals, levels[k + 1], sizes[k], levelOptions, levels[k], finer[k]))
    {
      return aborted();
    }
  }
  NestedOrder(levels, finer);
}

double ExtentPerMedianEdge(const TriangleMesh& mesh)
{
  std::vector<double> lengths;
  lengths.reserve(3 * size_t(mesh.NumberOfTriangles()));
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      lengths.push_back(Norm(mesh.Point(tri[(k + 1) % 3]) - mesh.Point(tri[k])));
    }
  }
  if (lengths.empty())
  {
    return 0;
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double median = lengths[lengths.size() / 2];
  return median > 0 ? mesh.BoundingBoxDiagonal() / median : std::numeric_limits<double>::infinity();
}
} // namespace slod
