// SPDX-License-Identifier: BSD-3-Clause
#include "slodGreedyCuts.h"

#include "slodChainSimplification.h"
#include "slodInputPreparation.h" // NonManifoldVertexFlags
#include "slodProvedCollapses.h"
#include "slodStageClock.h"

#include "vtkMath.h"

#include <algorithm>
#include <numeric>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_map>
#include <unordered_set>

namespace slod
{
namespace
{
// Candidate triangles at more than about 75 degrees to the patch normal or to the surface at their
// centroid are rejected: thin "standing" triangles can be within epsilon yet shade wrongly.
constexpr double MinimumNormalCosine = 0.25;
constexpr double MinimumTerrainCosine = 0.05;
// Runs repeated after splitting the patches that fell back to their original triangles.
constexpr int MaximumSplitRounds = 6;

struct P2
{
  double x, y;
};

// An axis-aligned box, for the local verification of a split round (which input triangles can
// have lost their nearest output, which output a proof needs).
struct Box3
{
  Vec3 Lo{ { 1e300, 1e300, 1e300 } }, Hi{ { -1e300, -1e300, -1e300 } };
  void Add(const Vec3& p)
  {
    for (int k = 0; k < 3; ++k)
    {
      this->Lo[k] = std::min(this->Lo[k], p[k]);
      this->Hi[k] = std::max(this->Hi[k], p[k]);
    }
  }
  void Add(const Box3& b)
  {
    this->Add(b.Lo);
    this->Add(b.Hi);
  }
  Box3 Grown(double d) const
  {
    Box3 b = *this;
    for (int k = 0; k < 3; ++k)
    {
      b.Lo[k] -= d;
      b.Hi[k] += d;
    }
    return b;
  }
  bool Meets(const Box3& b) const
  {
    for (int k = 0; k < 3; ++k)
    {
      if (b.Lo[k] > this->Hi[k] || b.Hi[k] < this->Lo[k])
      {
        return false;
      }
    }
    return true;
  }
};
Box3 TriangleBox(const TriangleMesh& mesh, const Index* tri)
{
  Box3 b;
  for (int k = 0; k < 3; ++k)
  {
    b.Add(mesh.Point(tri[k]));
  }
  return b;
}
inline double Orient(const P2& a, const P2& b, const P2& c)
{
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Buckets of a patch's inner vertices in its plane, so that a bite's candidates near a front
// edge are found without scanning every inner vertex for every edge at every step (that scan made
// the greedy cuts cubic in a patch's size: 42% of the time on a 3,000-triangle plate with holes).
// Items are the indices into the patch's inner list, bucket by bucket, increasing in a bucket.
struct InnerBuckets
{
  double X0 = 0, Y0 = 0, Cell = 1;
  long long NX = 0, NY = 0;
  std::vector<Index> Start, Items;

  void Build(const std::vector<P2>& coord, const std::vector<Index>& inner)
  {
    this->NX = this->NY = 0;
    this->Start.clear();
    this->Items.clear();
    if (inner.empty())
    {
      return;
    }
    double x1 = coord[inner[0]].x, y1 = coord[inner[0]].y;
    this->X0 = x1;
    this->Y0 = y1;
    for (Index v : inner)
    {
      this->X0 = std::min(this->X0, coord[v].x);
      this->Y0 = std::min(this->Y0, coord[v].y);
      x1 = std::max(x1, coord[v].x);
      y1 = std::max(y1, coord[v].y);
    }
    // About two vertices per bucket; at most 4 n + 16 buckets whatever the shape.
    const double n = double(inner.size());
    this->Cell = std::max(std::sqrt(std::max((x1 - this->X0) * (y1 - this->Y0), 0.0) * 2.0 / n), 1e-300);
    this->Cell = std::max({ this->Cell, (x1 - this->X0) / (4 * n + 16), (y1 - this->Y0) / (4 * n + 16) });
    this->NX = static_cast<long long>((x1 - this->X0) / this->Cell) + 1;
    this->NY = static_cast<long long>((y1 - this->Y0) / this->Cell) + 1;
    while (double(this->NX) * double(this->NY) > 4 * n + 16)
    {
      this->Cell *= 1.5;
      this->NX = static_cast<long long>((x1 - this->X0) / this->Cell) + 1;
      this->NY = static_cast<long long>((y1 - this->Y0) / this->Cell) + 1;
    }
    this->Start.assign(size_t(this->NX * this->NY + 1), 0);
    std::vector<size_t> bucket(inner.size());
    for (size_t k = 0; k < inner.size(); ++k)
    {
      bucket[k] = this->BucketOf(coord[inner[k]]);
      ++this->Start[bucket[k] + 1];
    }
    for (size_t b = 0; b + 1 < this->Start.size(); ++b)
    {
      this->Start[b + 1] += this->Start[b];
    }
    this->Items.resize(inner.size());
    std::vector<Index> fill(this->Start.begin(), this->Start.end() - 1);
    for (size_t k = 0; k < inner.size(); ++k)
    {
      this->Items[size_t(fill[bucket[k]]++)] = static_cast<Index>(k);
    }
  }
  // f(k) for every inner index k in the buckets that the square of half-width r around c touches.
  template <typename F>
  void ForEachNear(const P2& c, double r, F&& f) const
  {
    if (this->NX == 0)
    {
      return;
    }
    const long long x0 = this->Clamp((c.x - r - this->X0) / this->Cell, this->NX);
    const long long x1 = this->Clamp((c.x + r - this->X0) / this->Cell, this->NX);
    const long long y0 = this->Clamp((c.y - r - this->Y0) / this->Cell, this->NY);
    const long long y1 = this->Clamp((c.y + r - this->Y0) / this->Cell, this->NY);
    for (long long y = y0; y <= y1; ++y)
    {
      for (long long x = x0; x <= x1; ++x)
      {
        const size_t b = size_t(y * this->NX + x);
        for (Index q = this->Start[b]; q < this->Start[b + 1]; ++q)
        {
          f(this->Items[size_t(q)]);
        }
      }
    }
  }

private:
  static long long Clamp(double cell, long long n)
  {
    return cell <= 0 ? 0 : (cell >= double(n - 1) ? n - 1 : static_cast<long long>(cell));
  }
  size_t BucketOf(const P2& p) const
  {
    return size_t(this->Clamp((p.y - this->Y0) / this->Cell, this->NY) * this->NX +
      this->Clamp((p.x - this->X0) / this->Cell, this->NX));
  }
};

struct TripleKey
{
  Index v[3];
  bool operator==(const TripleKey& o) const { return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2]; }
};
struct TripleHash
{
  size_t operator()(const TripleKey& k) const
  {
    std::uint64_t h = std::uint32_t(k.v[0]);
    h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.v[1]);
    h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.v[2]);
    return size_t(h ^ (h >> 29));
  }
};
TripleKey MakeTriple(Index a, Index b, Index c)
{
  TripleKey k{ { a, b, c } };
  std::sort(k.v, k.v + 3);
  return k;
}
// Closed triangle test with a tolerance relative to the triangle's size.
inline bool InClosedTriangle(const P2& p, const P2& a, const P2& b, const P2& c, double tol)
{
  return Orient(a, b, p) >= -tol && Orient(b, c, p) >= -tol && Orient(c, a, p) >= -tol;
}
// Whether segment c-d properly crosses segment a-b, given o1 = Orient(a, b, c) and
// o2 = Orient(a, b, d): a walk along a chain c, d, ... passes each vertex's side on to the next
// segment instead of computing it twice.
inline bool ProperCrossGivenSides(double o1, double o2, const P2& a, const P2& b, const P2& c, const P2& d)
{
  if (!((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)))
  {
    return false;
  }
  const double o3 = Orient(c, d, a), o4 = Orient(c, d, b);
  return (o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0);
}
inline bool ProperCross(const P2& a, const P2& b, const P2& c, const P2& d)
{
  return ProperCrossGivenSides(Orient(a, b, c), Orient(a, b, d), a, b, c, d);
}
struct ClipVertex
{
  P2 p;
  Vec3 x;
};
// Sutherland-Hodgman: keeps the part of `poly` left of the directed line a->b (3D carried along:
// the projection is affine on a planar face, so interpolation is exact).
void ClipHalfPlane(const std::vector<ClipVertex>& in, const P2& a, const P2& b, std::vector<ClipVertex>& out)
{
  out.clear();
  const size_t n = in.size();
  for (size_t i = 0; i < n; ++i)
  {
    const ClipVertex& s = in[i];
    const ClipVertex& e = in[(i + 1) % n];
    const double ds = Orient(a, b, s.p), de = Orient(a, b, e.p);
    if (ds >= 0)
    {
      out.push_back(s);
    }
    if ((ds >= 0) != (de >= 0))
    {
      const double t = ds / (ds - de);
      out.push_back({ { s.p.x + t * (e.p.x - s.p.x), s.p.y + t * (e.p.y - s.p.y) }, s.x + t * (e.x - s.x) });
    }
  }
}
double PolygonArea2(const std::vector<ClipVertex>& poly)
{
  double a = 0;
  for (size_t i = 0, n = poly.size(); i < n; ++i)
  {
    const P2& p = poly[i].p;
    const P2& q = poly[(i + 1) % n].p;
    a += p.x * q.y - p.y * q.x;
  }
  return a;
}
} // namespace

namespace
{
// Pieces one distance proof may examine: past it the triangle counts as not proved (the callers
// then keep finer triangles), so a proof costs at most this many closest-point queries.
constexpr int MaximumDistancePieces = 4096;
// Work bound of a target search (RunForTarget): distance-proof pieces per input triangle. A whole
// 10-step search takes about 45 on a CAD mesh (fandisk at 10 %); a flat valence-5,000 fan took
// about 100 per step, each piece near its centre costing a scan of all its triangles.
constexpr long long MaximumProofPiecesPerTriangle = 200;
// Work bound of a nested run over the tolerance ladder (RunMonotone) and of the collapsed target
// search's runs, and again of its final collapses: distance-proof pieces per input triangle, the
// cuts' and the collapses' together. Past it no further level, fresh run, collapse or flip is
// started (a deterministic point of the same work sequence, so the nesting stays monotone).
constexpr long long MaximumLadderPiecesPerTriangle = 2000;
// New triangles' answers carried between final collapses (CarryProofs): past this many they are
// dropped and gathered again (a flat table of 16-byte slots, a quarter to half full: at most 128 MB).
constexpr size_t MaximumCarriedProofs = size_t(1) << 21;

// Sets a flag for the scope of a call and restores it on every way out.
class ScopedFlag
{
public:
  explicit ScopedFlag(bool& flag, bool value = true)
    : Flag(flag)
    , Before(flag)
  {
    flag = value;
  }
  ~ScopedFlag() { this->Flag = this->Before; }
  ScopedFlag(const ScopedFlag&) = delete;
  ScopedFlag& operator=(const ScopedFlag&) = delete;

private:
  bool& Flag;
  const bool Before;
};
// Tolerances (doubling up to the level found) at which a target's final collapses run when their
// start is finer than half that level (the input below the ladder's bottom).
constexpr int CollapseStages = 5;
// A target search's top level over the target goes down the ladder only when it removed at least
// 1/this of the input's triangles (below, it moved the surface too little to have stalled).
constexpr Index DescentMinimumRemoved = 100;

enum class PieceDistance
{
  Within,  // proved: every point of the piece within epsilon
  Outside, // a point of the piece (its centroid or a corner) farther than epsilon
  Unknown  // neither: split it
};

// Original triangles one flat-neighbourhood proof may gather (beyond: no proof, split the piece).
constexpr size_t MaximumFlatNeighbourhood = 8192;

// Whether segment u-w (in the plane of triangle p) enters the open triangle p[0..2] (counter-
// clockwise seen along n): the segment clipped to the three open half-planes keeps a length.
bool SegmentEntersTriangle(const Vec3& u, const Vec3& w, const Vec3* p, const Vec3& n, double tolerance)
{
  double enter = 0, leave = 1;
  for (int k = 0; k < 3; ++k)
  {
    const Vec3 inward = Cross(n, p[(k + 1) % 3] - p[k]);
    const double scale = Norm(inward);
    const double su = Dot(u - p[k], inward) / scale - tolerance, sw = Dot(w - p[k], inward) / scale - tolerance;
    if (su <= 0 && sw <= 0)
    {
      return false;
    }
    if (su < 0 || sw < 0)
    {
      const double t = su / (su - sw);
      (su < 0 ? enter : leave) = su < 0 ? std::max(enter, t) : std::min(leave, t);
    }
  }
  return enter < leave;
}

// Net use of the edges of a set of triangles (u < w counts +1 as u->w, -1 as w->u), gathered per
// triangle and summed once sorted (no hashing per piece): an edge with a net use is where the
// set's covering of a plane may end (its border, a fold, a non-manifold edge).
class EdgeUses
{
public:
  void Clear() { this->Uses.clear(); }
  void Add(const Index* v)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index u = v[k], w = v[(k + 1) % 3];
      this->Uses.emplace_back(u < w ? Key(u, w) : Key(w, u), u < w ? 1 : -1);
    }
  }
  // Whether `enters(u, w)` holds for an edge u-w of nonzero net use.
  template <typename Enters>
  bool AnyUnmatched(Enters&& enters)
  {
    std::sort(this->Uses.begin(), this->Uses.end());
    for (size_t i = 0, j = 0; i < this->Uses.size(); i = j)
    {
      int use = 0;
      for (j = i; j < this->Uses.size() && this->Uses[j].first == this->Uses[i].first; ++j)
      {
        use += this->Uses[j].second;
      }
      const std::uint64_t edge = this->Uses[i].first;
      if (use != 0 && enters(Index(edge >> 32), Index(edge & 0xffffffffu)))
      {
        return true;
      }
    }
    return false;
  }

private:
  static std::uint64_t Key(Index u, Index w) { return (std::uint64_t(std::uint32_t(u)) << 32) | std::uint32_t(w); }
  std::vector<std::pair<std::uint64_t, int>> Uses;
};

// The original triangles near a piece (within `radius` of `center`, at most `limit`) for a covering
// proof, or nullptr when the covered point `seedFoot` is not inside the piece (seen along n) or there
// are more. Per-thread scratch: a proof examines many pieces, none allocates once it has grown.
const std::vector<Index>* SeededNeighbourhood(const TriangleBVH& bvh, const Vec3& seedFoot, const Vec3* piece,
  const Vec3& n, double tolerance, const Vec3& center, double radius, size_t limit)
{
  thread_local std::vector<Index> near;
  near.clear();
  if (!SegmentEntersTriangle(seedFoot, seedFoot, piece, n, tolerance) || !bvh.TrianglesNear(center, radius, limit, near))
  {
    return nullptr;
  }
  return &near;
}

// A piece lying in the plane of a flat neighbourhood, proved at once instead of subdivided down to
// the size of epsilon. The plane P is that of the original triangle `seed` closest to the piece's
// centroid. The original triangles within delta of P facing P's side project onto P as a covering
// whose count is constant away from their unmatched edges (an edge a->b without b->a); when no
// unmatched edge enters the projected piece and the seed's closest point lies inside it, the whole
// projected piece is covered: a point x of the piece is within |x - P| + delta of the surface, at
// most epsilon when the corners are within epsilon - delta of P (the distance to a plane is convex).
bool FlatNeighbourhoodProof(const TriangleMesh& mesh, const TriangleBVH& bvh, Index seed, const Vec3& seedPoint,
  const Vec3* corner, const Vec3& g, double epsilon)
{
  const Index* t = mesh.Triangle(seed);
  const Vec3 origin = mesh.Point(t[0]);
  const Vec3 n = Normalized(mesh.TriangleAreaVector(seed));
  const double delta = 0.25 * epsilon;
  auto height = [&](const Vec3& x) { return Dot(x - origin, n); };
  auto project = [&](const Vec3& x) { return x - height(x) * n; };
  const Vec3 piece[3] = { project(corner[0]), project(corner[1]), project(corner[2]) };
  const Vec3 pieceNormal = Cross(piece[1] - piece[0], piece[2] - piece[0]);
  if (Dot(n, n) == 0 || Dot(pieceNormal, n) <= 0)
  {
    return false;
  }
  const Vec3 center = project(g);
  double radius2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    const Vec3 d = piece[k] - center;
    radius2 = std::max(radius2, Dot(d, d));
  }
  // Unmatched edges within `tolerance` of the piece's border (a border edge of the surface under
  // a piece edge) do not count: the corners' margin in height pays for that sliver.
  const double tolerance = 1e-9 * std::sqrt(radius2);
  for (int k = 0; k < 3; ++k)
  {
    if (std::fabs(height(corner[k])) > epsilon - delta - tolerance)
    {
      return false;
    }
  }
  const std::vector<Index>* near =
    SeededNeighbourhood(bvh, project(seedPoint), piece, n, tolerance, center, std::sqrt(radius2) + delta, MaximumFlatNeighbourhood);
  if (!near)
  {
    return false;
  }
  // The triangles lying flat in P and facing its side.
  thread_local EdgeUses uses; // per-thread scratch, as `near`
  uses.Clear();
  for (Index q : *near)
  {
    const Index* v = mesh.Triangle(q);
    if (std::fabs(height(mesh.Point(v[0]))) <= delta && std::fabs(height(mesh.Point(v[1]))) <= delta &&
      std::fabs(height(mesh.Point(v[2]))) <= delta && Dot(mesh.TriangleAreaVector(q), n) > 0)
    {
      uses.Add(v);
    }
  }
  if (uses.AnyUnmatched([&](Index u, Index w) {
        return SegmentEntersTriangle(project(mesh.Point(u)), project(mesh.Point(w)), piece, n, tolerance);
      }))
  {
    return false; // the covering may end inside the piece
  }
  return true;
}

// Whether every point of x within epsilon of triangle t (the distance to a triangle is convex,
// so a convex polygon's corners decide).
bool CornersWithin(const TriangleMesh& mesh, Index t, const Vec3* x, size_t n, double epsilon)
{
  const Index* v = mesh.Triangle(t);
  const Vec3 p0 = mesh.Point(v[0]), p1 = mesh.Point(v[1]), p2 = mesh.Point(v[2]);
  for (size_t k = 0; k < n; ++k)
  {
    const Vec3 e = x[k] - ClosestPointOnTriangle(x[k], p0, p1, p2);
    if (Dot(e, e) > epsilon * epsilon)
    {
      return false;
    }
  }
  return true;
}

// A piece across the edge shared by `near` (the original triangle closest to its centroid) and
// `other` (the one closest to a corner that `near` does not cover): the plane through the edge that
// bisects their dihedral angle cuts the piece into two convex polygons, each proved against its own
// triangle by its corners (any cutting plane would be sound: the distance to one triangle is convex
// and the two parts cover the piece; this one puts each part on its triangle's side). Without it a
// piece straddling an edge of a curved input was split until its radius fell under epsilon along
// the whole edge (most of the final collapses' proof pieces at small tolerances).
bool SharedEdgeProof(const TriangleMesh& mesh, Index near, Index other, const Vec3* corner, double epsilon)
{
  const Index* t1 = mesh.Triangle(near);
  const Index* t2 = mesh.Triangle(other);
  Index shared[2] = { InvalidIndex, InvalidIndex }, apex1 = InvalidIndex, apex2 = InvalidIndex;
  int found = 0;
  for (int i = 0; i < 3; ++i)
  {
    const bool inOther = t1[i] == t2[0] || t1[i] == t2[1] || t1[i] == t2[2];
    (inOther ? shared[std::min(found++, 1)] : apex1) = t1[i];
    if (t2[i] != t1[0] && t2[i] != t1[1] && t2[i] != t1[2])
    {
      apex2 = t2[i];
    }
  }
  if (found != 2 || apex1 == InvalidIndex || apex2 == InvalidIndex)
  {
    return false;
  }
  const Vec3 s = mesh.Point(shared[0]);
  const Vec3 along = Normalized(mesh.Point(shared[1]) - s);
  auto across = [&](Index apex) {
    const Vec3 d = mesh.Point(apex) - s;
    return Normalized(d - Dot(d, along) * along);
  };
  const Vec3 m = across(apex1) - across(apex2); // the bisecting plane's normal, toward `near`
  if (!(Dot(m, m) > 1e-12))
  {
    return false; // the two triangles folded onto each other: no side to tell
  }
  Vec3 part[2][4];
  size_t size[2] = { 0, 0 };
  double side[3];
  for (int k = 0; k < 3; ++k)
  {
    side[k] = Dot(corner[k] - s, m);
  }
  for (int k = 0; k < 3; ++k)
  {
    const int l = (k + 1) % 3;
    if (side[k] >= 0)
    {
      part[0][size[0]++] = corner[k];
    }
    if (side[k] <= 0)
    {
      part[1][size[1]++] = corner[k];
    }
    if ((side[k] > 0 && side[l] < 0) || (side[k] < 0 && side[l] > 0))
    {
      const Vec3 x = corner[k] + (side[k] / (side[k] - side[l])) * (corner[l] - corner[k]);
      part[0][size[0]++] = x;
      part[1][size[1]++] = x;
    }
  }
  return CornersWithin(mesh, near, part[0], size[0], epsilon) && CornersWithin(mesh, other, part[1], size[1], epsilon);
}

// Original triangles one projected-cover proof may gather (beyond: no proof, split the piece). The
// proof pays off on pieces over a few original triangles; a larger gathering costs more when it
// fails (bull to 10 %: 47 s of CPU with 256, 15.5 s with 32, 15.0 s without the proof).
constexpr size_t MaximumCoverTriangles = 32;

// A piece over a curved part of the surface, proved at once: the original triangles near it that
// face its side, projected along its normal n, cover it (as in FlatNeighbourhoodProof: their count
// over the piece changes only across an unmatched edge, none enters the piece, and the seed's
// closest point lies inside it), and each part of the piece over one of them (the piece clipped to
// that triangle's prism along n, a convex polygon) has its corners within epsilon of that triangle
// (the distance to a triangle is convex). So every point of the piece is within epsilon of the
// triangle over which it lies. A piece spanning a few original triangles of a curved input used to
// be split until each part lay on one or two of them (tens of pieces per new triangle of the final
// collapses); unlike FlatNeighbourhoodProof no plane is assumed, the corners decide.
bool ProjectedCoverProof(const TriangleMesh& mesh, const TriangleBVH& bvh, Index seed, const Vec3& seedPoint,
  const Vec3* corner, const Vec3& g, double epsilon)
{
  const Vec3 area = Cross(corner[1] - corner[0], corner[2] - corner[0]);
  if (!(Dot(area, area) > 0) || !(Dot(mesh.TriangleAreaVector(seed), area) > 0))
  {
    return false;
  }
  const Vec3 n = Normalized(area);
  double radius2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    radius2 = std::max(radius2, Dot(corner[k] - g, corner[k] - g));
  }
  // Unmatched edges within `tolerance` of the piece's border do not count (a border of the input
  // under a border of the output). The part they may leave uncovered lies within tolerance /
  // sin(alpha / 2) of the covered inner piece (alpha its smallest angle), and the clipped polygons'
  // rounding gaps are far thinner: the corners are held to epsilon less that, which pays for both.
  const double tolerance = 1e-9 * std::sqrt(radius2);
  const double reach = epsilon - 2 * tolerance / std::max(1e-6, std::sin(0.5 * MinimumAngle(corner[0], corner[1], corner[2])));
  if (!(reach > 0))
  {
    return false;
  }
  // The seed's foot need not be projected: the test measures across n only.
  const std::vector<Index>* near =
    SeededNeighbourhood(bvh, seedPoint, corner, n, tolerance, g, std::sqrt(radius2) + epsilon, MaximumCoverTriangles);
  if (!near)
  {
    return false;
  }
  thread_local EdgeUses uses;
  uses.Clear();
  thread_local std::vector<Vec3> part, clipped;
  for (Index q : *near)
  {
    if (!(Dot(mesh.TriangleAreaVector(q), n) > 0))
    {
      continue;
    }
    const Index* v = mesh.Triangle(q);
    const Vec3 p[3] = { mesh.Point(v[0]), mesh.Point(v[1]), mesh.Point(v[2]) };
    part.assign(corner, corner + 3);
    for (int k = 0; k < 3 && !part.empty(); ++k) // the piece clipped to q's prism along n
    {
      const Vec3 inward = Cross(n, p[(k + 1) % 3] - p[k]);
      clipped.clear();
      for (size_t i = 0, m = part.size(); i < m; ++i)
      {
        const Vec3& x = part[i];
        const Vec3& y = part[(i + 1) % m];
        const double dx = Dot(x - p[k], inward), dy = Dot(y - p[k], inward);
        if (dx >= 0)
        {
          clipped.push_back(x);
        }
        if ((dx > 0 && dy < 0) || (dx < 0 && dy > 0))
        {
          clipped.push_back(x + (dx / (dx - dy)) * (y - x));
        }
      }
      part.swap(clipped);
    }
    for (const Vec3& x : part)
    {
      const Vec3 e = x - ClosestPointOnTriangle(x, p[0], p[1], p[2]);
      if (Dot(e, e) > reach * reach)
      {
        return false;
      }
    }
    uses.Add(v);
  }
  return !uses.AnyUnmatched(
    [&](Index u, Index w) { return SegmentEntersTriangle(mesh.Point(u), mesh.Point(w), corner, n, tolerance); });
}

// `examined` is charged one more piece for each further closest-point query or gathering the
// proofs after the first make (the work bounds count pieces as queries: a run that ends at its work
// bound would otherwise spend more CPU per piece).
PieceDistance ClassifyPiece(
  const TriangleBVH& bvh, const Vec3& a, const Vec3& b, const Vec3& c, double epsilon, int& examined)
{
  const Vec3 g = (1.0 / 3.0) * (a + b + c);
  const double r2 = std::max({ Dot(g - a, g - a), Dot(g - b, g - b), Dot(g - c, g - c) });
  const ClosestPointResult hit = bvh.ClosestPoint(g, epsilon * epsilon);
  if (hit.Triangle == InvalidIndex)
  {
    return PieceDistance::Outside;
  }
  if (std::sqrt(hit.Distance2) + std::sqrt(r2) <= epsilon)
  {
    return PieceDistance::Within; // every point of the piece is within R of g (1-Lipschitz distance)
  }
  // The distance to one triangle of the surface is convex (distance to a convex set), so over
  // the piece it is largest at a corner: corners within epsilon of the triangle closest to g prove
  // the whole piece. Without this, a piece lying on the surface (a flat region) was subdivided
  // until its radius fell below epsilon.
  if (const TriangleMesh* mesh = bvh.GetMesh())
  {
    const Index* t = &mesh->Triangles[3 * size_t(hit.Triangle)];
    const Vec3 p0 = mesh->Point(t[0]), p1 = mesh->Point(t[1]), p2 = mesh->Point(t[2]);
    auto within = [&](const Vec3& x) {
      const Vec3 e = x - ClosestPointOnTriangle(x, p0, p1, p2);
      return Dot(e, e) <= epsilon * epsilon;
    };
    const Vec3 corners[3] = { a, b, c };
    const int uncovered = !within(a) ? 0 : !within(b) ? 1 : !within(c) ? 2 : -1;
    if (uncovered < 0)
    {
      return PieceDistance::Within;
    }
    ++examined;
    const ClosestPointResult other = bvh.ClosestPoint(corners[uncovered], epsilon * epsilon);
    if (other.Triangle == InvalidIndex)
    {
      return PieceDistance::Outside; // that corner is farther than epsilon from the input
    }
    if (SharedEdgeProof(*mesh, hit.Triangle, other.Triangle, corners, epsilon))
    {
      return PieceDistance::Within;
    }
    ++examined;
    if (ProjectedCoverProof(*mesh, bvh, hit.Triangle, hit.Point, corners, g, epsilon) ||
      FlatNeighbourhoodProof(*mesh, bvh, hit.Triangle, hit.Point, corners, g, epsilon))
    {
      return PieceDistance::Within;
    }
  }
  return PieceDistance::Unknown;
}
} // namespace

namespace
{
// A piece of a distance proof: a triangle and the subdivisions it may still have.
struct Piece
{
  Vec3 Corner[3];
  int Generations;
};

// Unproved pieces are split in four (midpoint subdivision) down to their generations; `examined`
// counts on from its value (the pieces a proof already examined).
bool ProvePieces(const TriangleBVH& bvh, double epsilon, std::vector<Piece>& pending, int& examined)
{
  for (; !pending.empty(); ++examined)
  {
    if (examined >= MaximumDistancePieces)
    {
      return false;
    }
    const Piece piece = pending.back();
    pending.pop_back();
    const Vec3* x = piece.Corner;
    const PieceDistance d = ClassifyPiece(bvh, x[0], x[1], x[2], epsilon, examined);
    if (d == PieceDistance::Outside || (d == PieceDistance::Unknown && piece.Generations <= 0))
    {
      return false;
    }
    if (d == PieceDistance::Unknown)
    {
      const Vec3 ab = 0.5 * (x[0] + x[1]), bc = 0.5 * (x[1] + x[2]), ca = 0.5 * (x[2] + x[0]);
      const int g = piece.Generations - 1;
      pending.push_back({ { ca, bc, x[2] }, g });
      pending.push_back({ { ab, x[1], bc }, g });
      pending.push_back({ { x[0], ab, ca }, g });
      pending.push_back({ { ab, bc, ca }, g });
    }
  }
  return true;
}

bool ProveWithinDistance(
  const TriangleBVH& bvh, const Vec3& a, const Vec3& b, const Vec3& c, double epsilon, int depth, int& examined)
{
  thread_local std::vector<Piece> pending; // per-thread scratch: no allocation per proof
  pending.assign(1, Piece{ { a, b, c }, depth });
  examined = 0;
  return ProvePieces(bvh, epsilon, pending, examined);
}
} // namespace

bool TriangleWithinDistance(const TriangleBVH& bvh, const Vec3& a, const Vec3& b, const Vec3& c, double epsilon,
  int depth, long long* examinedPieces)
{
  int examined = 0;
  const bool within = ProveWithinDistance(bvh, a, b, c, epsilon, depth, examined);
  if (examinedPieces)
  {
    *examinedPieces += examined + 1;
  }
  return within;
}

bool TrianglesWithinDistance(const TriangleBVH& bvh, const std::vector<Vec3>& corners, double epsilon, int depth,
  long long* examinedPieces, size_t* refused)
{
  thread_local std::vector<std::pair<size_t, int>> undecided; // a triangle's first corner, pieces examined
  undecided.clear();
  auto charge = [examinedPieces](int examined) {
    if (examinedPieces)
    {
      *examinedPieces += examined + 1; // as TriangleWithinDistance charges each triangle's proof
    }
  };
  // A refusal: the undecided proofs not taken further were charged nothing yet but their first piece.
  auto refuse = [&](size_t from) {
    for (size_t k = from; k < undecided.size(); ++k)
    {
      charge(undecided[k].second - 1);
    }
    return false;
  };
  // Every triangle's first piece (the whole triangle), the undecided ones kept with their count.
  for (size_t i = 0; i + 2 < corners.size(); i += 3)
  {
    int examined = 0;
    const PieceDistance d = ClassifyPiece(bvh, corners[i], corners[i + 1], corners[i + 2], epsilon, examined);
    if (d == PieceDistance::Outside || (d == PieceDistance::Unknown && depth <= 0))
    {
      charge(examined); // counted as ProvePieces counts a refused piece
      if (refused)
      {
        *refused = i / 3;
      }
      return refuse(0);
    }
    ++examined;
    if (d == PieceDistance::Unknown)
    {
      undecided.emplace_back(i, examined);
      continue;
    }
    charge(examined);
  }
  // Then their subdivisions, each proof going on from its first piece (the same pieces, in the
  // same order, as TriangleWithinDistance's).
  thread_local std::vector<Piece> pending;
  for (size_t k = 0; k < undecided.size(); ++k)
  {
    const Vec3* x = &corners[undecided[k].first];
    int examined = undecided[k].second;
    const Vec3 ab = 0.5 * (x[0] + x[1]), bc = 0.5 * (x[1] + x[2]), ca = 0.5 * (x[2] + x[0]);
    pending.assign({ Piece{ { ca, bc, x[2] }, depth - 1 }, Piece{ { ab, x[1], bc }, depth - 1 },
      Piece{ { x[0], ab, ca }, depth - 1 }, Piece{ { ab, bc, ca }, depth - 1 } });
    const bool within = ProvePieces(bvh, epsilon, pending, examined);
    charge(examined);
    if (!within)
    {
      if (refused)
      {
        *refused = undecided[k].first / 3;
      }
      return refuse(k + 1);
    }
  }
  return true;
}

GreedyCuts::GreedyCuts() = default;
GreedyCuts::~GreedyCuts() = default;

void GreedyCuts::Initialize(const TriangleMesh& mesh, const PatchificationParameters& parameters,
  const ProgressFunction& progress, const TerrainPatchificationParameters* terrain)
{
  this->Mesh = &mesh;
  this->WasAborted = false;
  this->CarriedProofs.Clear();
  this->CarriedEpsilon = 0;
  this->Terrain = terrain != nullptr;
  this->Topology.Build(mesh);
  const ProgressFunction stage =
    progress ? ProgressFunction([&](double f) { return progress(0.8 * f); }) : ProgressFunction();
  if (terrain)
  {
    TerrainPatches labels;
    if (!BuildTerrainPatches(mesh, this->Topology, *terrain, labels, stage))
    {
      this->WasAborted = true;
      return;
    }
    this->Patches.BuildFromLabels(mesh, this->Topology, labels.TrianglePatch, labels.NumberOfPatches);
    this->HeightDirection = std::move(labels.HeightDirection);
  }
  else
  {
    this->Patches.Build(mesh, this->Topology, parameters, stage);
    if (this->Patches.Aborted())
    {
      this->WasAborted = true;
      return;
    }
    this->HeightDirection.resize(size_t(this->Patches.NumberOfPatches()));
    for (Index p = 0; p < this->Patches.NumberOfPatches(); ++p)
    {
      this->HeightDirection[p] = this->Patches.PatchNormal(p);
    }
  }
  this->Bvh.Build(mesh);
  this->AbsorbPatchesWithoutNormal();
  this->BuildPatchData();
  this->IsolateSeamTriangles();
  this->InitialLabels = this->Patches.TrianglePatches();
  this->InitialHeights = this->HeightDirection;
  if (progress && !progress(1.0))
  {
    this->WasAborted = true;
  }
}

// A patch of zero-area input triangles only (collinear corners: a polygon's fan over collinear
// vertices, CGAL's degtri_sliding) has no normal, so it cannot be projected and would fall back to
// its original triangles in every run. Each of its triangles joins the patch across its longest
// edge instead (its third corner lies on that edge: the neighbour's boundary only gains a vertex
// on a straight segment), when that patch has a normal and does not hold the third corner yet (the
// union stays a disk). Repeated while a triangle moves (a strip of them joins one by one), at most
// once per triangle; a mesh without such a patch is untouched.
void GreedyCuts::AbsorbPatchesWithoutNormal()
{
  const TriangleMesh& mesh = *this->Mesh;
  const Index np = this->Patches.NumberOfPatches();
  std::vector<unsigned char> normalless(size_t(np), 0);
  bool any = false;
  for (Index p = 0; p < np; ++p)
  {
    normalless[p] = Norm(this->HeightDirection[p]) == 0;
    any = any || normalless[p];
  }
  if (!any)
  {
    return;
  }
  std::vector<Index> label = this->Patches.TrianglePatches();
  const auto holds = [&](Index q, Index v) {
    for (const Index* t = this->Topology.VertexTrianglesBegin(v); t != this->Topology.VertexTrianglesEnd(v); ++t)
    {
      if (label[*t] == q)
      {
        return true;
      }
    }
    return false;
  };
  // Only the triangles of normalless patches are walked again (a round moves at least one of them
  // or ends, so at most as many rounds as they are).
  std::vector<Index> waiting;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (normalless[label[t]])
    {
      waiting.push_back(t);
    }
  }
  for (bool moved = true; moved;)
  {
    moved = false;
    for (const Index t : waiting)
    {
      if (!normalless[label[t]])
      {
        continue;
      }
      const Index* v = mesh.Triangle(t);
      int longest = 0;
      for (int k = 1; k < 3; ++k)
      {
        if (Norm(mesh.Point(v[(k + 1) % 3]) - mesh.Point(v[k])) >
          Norm(mesh.Point(v[(longest + 1) % 3]) - mesh.Point(v[longest])))
        {
          longest = k;
        }
      }
      const Index n = this->Topology.EdgeNeighbor(t, longest);
      if (n != InvalidIndex && !normalless[label[n]] && !holds(label[n], v[(longest + 2) % 3]))
      {
        label[t] = label[n];
        moved = true;
      }
    }
  }
  // Patches left empty are dropped (the others renumbered in order).
  std::vector<Index> renumber(size_t(np), InvalidIndex);
  for (Index l : label)
  {
    renumber[l] = 0;
  }
  Index kept = 0;
  std::vector<Vec3> heights;
  for (Index p = 0; p < np; ++p)
  {
    if (renumber[p] != InvalidIndex)
    {
      renumber[p] = kept++;
      heights.push_back(this->HeightDirection[p]);
    }
  }
  for (Index& l : label)
  {
    l = renumber[l];
  }
  this->Patches.BuildFromLabels(mesh, this->Topology, label, kept);
  this->HeightDirection = std::move(heights);
}

// Per patch: its triangles (grouped), its inner vertices (on no chain), its boundary loop.
void GreedyCuts::BuildPatchData()
{
  const TriangleMesh& mesh = *this->Mesh;
  const Index np = this->Patches.NumberOfPatches();
  const Index nt = mesh.NumberOfTriangles();
  const std::vector<Index>& patchOf = this->Patches.TrianglePatches();
  // Triangles grouped by patch (counting sort: deterministic order).
  this->PatchTriangleOffsets.assign(size_t(np) + 1, 0);
  for (Index t = 0; t < nt; ++t)
  {
    ++this->PatchTriangleOffsets[size_t(patchOf[t]) + 1];
  }
  for (Index p = 0; p < np; ++p)
  {
    this->PatchTriangleOffsets[p + 1] += this->PatchTriangleOffsets[p];
  }
  this->PatchTriangleList.resize(size_t(nt));
  {
    std::vector<Index> fill(this->PatchTriangleOffsets.begin(), this->PatchTriangleOffsets.end() - 1);
    for (Index t = 0; t < nt; ++t)
    {
      this->PatchTriangleList[fill[patchOf[t]]++] = t;
    }
  }
  // Inner vertices: on no chain (a chain vertex is shared with the neighbouring patch, so biting
  // it could pinch the surface).
  std::vector<unsigned char> onChain(size_t(mesh.NumberOfPoints()), 0);
  for (Index c = 0; c < this->Patches.NumberOfChains(); ++c)
  {
    const Index* v = this->Patches.ChainVerticesBegin(c);
    for (Index i = 0; i < this->Patches.ChainSize(c); ++i)
    {
      onChain[v[i]] = 1;
    }
  }
  std::vector<Index> stamp(size_t(mesh.NumberOfPoints()), InvalidIndex);
  this->PatchInnerOffsets.assign(1, 0);
  this->PatchInnerList.clear();
  this->PatchLoops.assign(size_t(np), {});
  this->LoopValid.assign(size_t(np), 0);
  for (Index p = 0; p < np; ++p)
  {
    for (Index i = this->PatchTriangleOffsets[p]; i < this->PatchTriangleOffsets[p + 1]; ++i)
    {
      const Index* tri = mesh.Triangle(this->PatchTriangleList[i]);
      for (int k = 0; k < 3; ++k)
      {
        if (!onChain[tri[k]] && stamp[tri[k]] != p)
        {
          stamp[tri[k]] = p;
          this->PatchInnerList.push_back(tri[k]);
        }
      }
    }
    this->PatchInnerOffsets.push_back(static_cast<Index>(this->PatchInnerList.size()));
    this->LoopValid[p] = this->Patches.PatchBoundaryLoop(p, this->PatchLoops[p]) ? 1 : 0;
  }
}

// Non-manifold input (Initialize): each triangle at a non-manifold vertex becomes its own patch,
// kept as it is, and the rest of every patch is cut into its edge-connected pieces. A piece that is
// not a disk (it surrounds seam triangles) is split as a fallback patch is, at most
// MaximumSplitRounds times; a piece still not a disk then is a fallback patch of every run.
void GreedyCuts::IsolateSeamTriangles()
{
  const TriangleMesh& mesh = *this->Mesh;
  const Index nt = mesh.NumberOfTriangles();
  this->SeamVertex = NonManifoldVertexFlags(mesh);
  std::vector<unsigned char> seam(size_t(nt), 0);
  this->SeamTriangles = 0;
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    seam[t] = this->SeamVertex[tri[0]] || this->SeamVertex[tri[1]] || this->SeamVertex[tri[2]];
    this->SeamTriangles += seam[t];
  }
  if (this->SeamTriangles == 0)
  {
    this->SeamVertex.clear();
    this->SeamPatch.clear();
    return;
  }
  const std::vector<Index> old = this->Patches.TrianglePatches();
  std::vector<Index> label(size_t(nt), InvalidIndex), queue;
  std::vector<Vec3> heights;
  for (Index seed = 0; seed < nt; ++seed)
  {
    if (label[seed] != InvalidIndex)
    {
      continue;
    }
    const Index piece = Index(heights.size());
    label[seed] = piece;
    const Index* tri = mesh.Triangle(seed);
    heights.push_back(seam[seed] ? TriangleNormal(mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]))
                                 : this->HeightDirection[old[seed]]);
    queue.assign(seam[seed] ? 0 : 1, seed);
    for (size_t head = 0; head < queue.size(); ++head)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index n = this->Topology.EdgeNeighbor(queue[head], k);
        if (n != InvalidIndex && !seam[n] && label[n] == InvalidIndex && old[n] == old[seed])
        {
          label[n] = piece;
          queue.push_back(n);
        }
      }
    }
  }
  this->SeamPatch.assign(heights.size(), 0);
  for (Index t = 0; t < nt; ++t)
  {
    this->SeamPatch[label[t]] = seam[t];
  }
  this->Patches.BuildFromLabels(mesh, this->Topology, label, Index(heights.size()));
  this->HeightDirection = std::move(heights);
  std::vector<Index> notDisks(this->HeightDirection.size()); // first every piece, for its normal
  std::iota(notDisks.begin(), notDisks.end(), Index(0));
  this->UseOwnNormals(notDisks);
  this->BuildPatchData();
  for (int round = 0; round < MaximumSplitRounds; ++round)
  {
    notDisks.clear();
    for (Index p = 0; p < this->Patches.NumberOfPatches(); ++p)
    {
      if (!this->LoopValid[p] && !this->SeamPatch[p])
      {
        notDisks.push_back(p);
      }
    }
    if (notDisks.empty() || !this->SplitPatches(notDisks))
    {
      break;
    }
  }
}

// Chapter 4's patches are triangulated along their mean normal, so a piece cut from one gets its
// own: the parent's may be far from a small piece's (a triangle joins a patch at up to
// TwoEdgePatchAngle, 90 degrees, from its normal), and a piece projected along it could not be
// triangulated (lion-head: two pieces of 1 and 6 triangles fell back to their originals at every
// tolerance). A part of a chapter 3 height field is one along the parent's direction: kept.
void GreedyCuts::UseOwnNormals(const std::vector<Index>& pieces)
{
  for (Index q : pieces)
  {
    const Vec3 own = this->Patches.PatchNormalSum(q);
    this->HeightDirection[q] = this->Terrain || !(Norm(own) > 0) ? this->HeightDirection[q] : Normalized(own);
  }
}

// The corner angle of triangle t at its vertex v, projected along the unit direction d.
double ProjectedCorner(const TriangleMesh& mesh, Index t, Index v, const Vec3& d)
{
  const Index* tri = mesh.Triangle(t);
  const int i = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
  Vec3 a = mesh.Point(tri[(i + 1) % 3]) - mesh.Point(v);
  Vec3 b = mesh.Point(tri[(i + 2) % 3]) - mesh.Point(v);
  a = a - Dot(a, d) * d;
  b = b - Dot(b, d) * d;
  return std::atan2(Norm(Cross(a, b)), Dot(a, b));
}

// Session 26: a vertex of patch p whose triangles' corners, projected along the patch's direction,
// add up to more than a full turn makes the projected patch overlap itself there, and every piece
// that keeps that whole fan keeps the overlap: ALSTOM_TEST4's last fallback patch (11 triangles,
// every normal within 15 degrees of one direction, yet the boundary crosses itself next to one
// vertex) stayed through all the halvings. Fills `fan` with that vertex's triangles of p in order
// around it (from a patch boundary edge when there is one) and returns how many of them, from the
// start, make up half of its projected turn: a half seeded with them and kept off the others
// splits the overlap. Returns 0 (and no `fan`) when no fan wraps.
size_t GreedyCuts::WrappedFan(Index p, const std::vector<Index>& inPatch, const std::vector<Index>& label,
  std::vector<Index>& fan) const
{
  fan.clear();
  const TriangleMesh& mesh = *this->Mesh;
  const Vec3 d = Normalized(this->HeightDirection[p]);
  std::vector<std::pair<Index, double>> corners;
  corners.reserve(3 * inPatch.size());
  for (Index t : inPatch)
  {
    for (int k = 0; k < 3; ++k)
    {
      corners.emplace_back(mesh.Triangle(t)[k], ProjectedCorner(mesh, t, mesh.Triangle(t)[k], d));
    }
  }
  std::sort(corners.begin(), corners.end());
  Index widest = InvalidIndex;
  double widestTurn = 2 * vtkMath::Pi() * (1 + 1e-9);
  for (size_t k = 0, next = 0; k < corners.size(); k = next)
  {
    double turn = 0;
    for (next = k; next < corners.size() && corners[next].first == corners[k].first; ++next)
    {
      turn += corners[next].second;
    }
    if (turn > widestTurn)
    {
      widest = corners[k].first;
      widestTurn = turn;
    }
  }
  if (widest == InvalidIndex)
  {
    return 0;
  }
  // The fan in order: start at a triangle with an edge at the vertex on the patch's boundary,
  // then cross the other edge at the vertex, at most once per triangle of the patch.
  std::vector<Index> around;
  for (Index t : inPatch)
  {
    const Index* tri = mesh.Triangle(t);
    if (tri[0] == widest || tri[1] == widest || tri[2] == widest)
    {
      around.push_back(t);
    }
  }
  auto acrossAt = [&](Index t, Index from) {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index n = this->Topology.EdgeNeighbor(t, k);
      if ((tri[k] == widest || tri[(k + 1) % 3] == widest) && n != from && (n == InvalidIndex || label[n] == p))
      {
        return n;
      }
    }
    return from;
  };
  Index start = around.front();
  for (Index t : around)
  {
    int inside = 0;
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index n = this->Topology.EdgeNeighbor(t, k);
      inside += (tri[k] == widest || tri[(k + 1) % 3] == widest) && n != InvalidIndex && label[n] == p;
    }
    start = inside < 2 ? t : start;
  }
  double turn = 0;
  for (Index t = start, from = InvalidIndex; t != InvalidIndex && fan.size() < around.size();)
  {
    if (std::find(fan.begin(), fan.end(), t) != fan.end())
    {
      break;
    }
    fan.push_back(t);
    turn += ProjectedCorner(mesh, t, widest, d);
    const Index n = acrossAt(t, from); // `from` again: the wedge ends here
    t = n == from ? InvalidIndex : n;
    from = fan.back();
  }
  if (fan.size() < 2 || !(turn > 2 * vtkMath::Pi()))
  {
    fan.clear(); // the wrap is not in one wedge of the fan: left to the halving
    return 0;
  }
  double part = 0;
  size_t seeds = 0;
  while (seeds + 1 < fan.size() && part < turn / 2)
  {
    part += ProjectedCorner(mesh, fan[seeds++], widest, d);
  }
  return seeds;
}

// A patch that fell back to its original triangles is cut in two instead (then retried): a disk
// grown breadth-first from a triangle on its boundary takes half of it, and every edge-connected
// piece of the rest becomes a patch too, each with its direction (UseOwnNormals). Returns whether
// any patch was split.
bool GreedyCuts::SplitPatches(const std::vector<Index>& patches)
{
  const Index KeptOutOfHalf = InvalidIndex - 2; // the rest of a wrapped fan, while the half grows
  std::vector<Index> label = this->Patches.TrianglePatches();
  Index next = this->Patches.NumberOfPatches();
  std::vector<Index> inPatch, queue, pieces, fan;
  std::vector<unsigned char> vertexUsed(size_t(this->Mesh->NumberOfPoints()), 0);
  bool split = false;
  for (Index p : patches)
  {
    inPatch.assign(this->PatchTriangleList.begin() + this->PatchTriangleOffsets[p],
      this->PatchTriangleList.begin() + this->PatchTriangleOffsets[p + 1]);
    if (inPatch.size() < 2)
    {
      continue;
    }
    // Half of the patch, grown as a disk from its first triangle (on its boundary: the patch is
    // a disk, its first triangle in index order need not be inside), or from the first part of a
    // fan that wraps in projection (WrappedFan; the rest of that fan may not join the half).
    const Index half = next++;
    pieces.push_back(p);
    pieces.push_back(half);
    this->HeightDirection.push_back(this->HeightDirection[p]);
    const size_t seeds = std::max(this->WrappedFan(p, inPatch, label, fan), size_t(1));
    queue.assign(1, inPatch.front());
    if (seeds < fan.size())
    {
      queue.assign(fan.begin(), fan.begin() + seeds);
      for (size_t k = seeds; k < fan.size(); ++k)
      {
        label[fan[k]] = KeptOutOfHalf;
      }
    }
    for (Index t : queue)
    {
      label[t] = half;
      for (const Index* v = this->Mesh->Triangle(t); v != this->Mesh->Triangle(t) + 3; ++v)
      {
        vertexUsed[*v] = 1;
      }
    }
    for (size_t head = 0; head < queue.size() && 2 * queue.size() < inPatch.size(); ++head)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index n = this->Topology.EdgeNeighbor(queue[head], k);
        if (n == InvalidIndex || label[n] != p)
        {
          continue;
        }
        int shared = 0;
        Index opposite = InvalidIndex;
        for (int j = 0; j < 3; ++j)
        {
          const Index m = this->Topology.EdgeNeighbor(n, j);
          if (m != InvalidIndex && label[m] == half)
          {
            ++shared;
            opposite = this->Mesh->Triangle(n)[(j + 2) % 3];
          }
        }
        // Checked per triangle, not per head: one head may add two neighbours, and a half that
        // took the whole patch would leave it empty and split nothing.
        if ((shared == 2 || (shared == 1 && !vertexUsed[opposite])) && 2 * queue.size() < inPatch.size())
        {
          label[n] = half;
          queue.push_back(n);
          for (const Index* v = this->Mesh->Triangle(n); v != this->Mesh->Triangle(n) + 3; ++v)
          {
            vertexUsed[*v] = 1;
          }
        }
      }
    }
    for (Index t : queue)
    {
      for (const Index* v = this->Mesh->Triangle(t); v != this->Mesh->Triangle(t) + 3; ++v)
      {
        vertexUsed[*v] = 0;
      }
    }
    for (Index t : fan)
    {
      label[t] = label[t] == KeptOutOfHalf ? p : label[t];
    }
    // The rest, piece by piece (the first piece keeps the label p).
    bool first = true;
    for (Index seed : inPatch)
    {
      if (label[seed] != p)
      {
        continue;
      }
      const Index piece = first ? InvalidIndex - 1 : next++;
      if (!first)
      {
        pieces.push_back(piece);
        this->HeightDirection.push_back(this->HeightDirection[p]);
      }
      first = false;
      queue.assign(1, seed);
      label[seed] = piece;
      for (size_t head = 0; head < queue.size(); ++head)
      {
        for (int k = 0; k < 3; ++k)
        {
          const Index n = this->Topology.EdgeNeighbor(queue[head], k);
          if (n != InvalidIndex && label[n] == p)
          {
            label[n] = piece;
            queue.push_back(n);
          }
        }
      }
    }
    for (Index t : inPatch)
    {
      label[t] = label[t] == InvalidIndex - 1 ? p : label[t];
    }
    split = true;
  }
  if (split)
  {
    if (!this->SeamPatch.empty())
    {
      this->SeamPatch.resize(size_t(next), 0); // the pieces of a split patch are no seam triangles
    }
    this->Patches.BuildFromLabels(*this->Mesh, this->Topology, label, next);
    this->UseOwnNormals(pieces);
    this->BuildPatchData();
  }
  return split;
}

// State of one run.
struct GreedyCuts::Worker
{
  const GreedyCuts& G;
  const TriangleMesh& M;
  const Patchification& PP;
  GreedyCutsParameters Prm;
  GreedyCutsResult& Res;
  double Eps, EpsLocal, MinAngle, ShapedAngle, EarShape;
  // Per patch: its first attempt asks for well-shaped triangles (ShapedAngle); a patch that gets
  // stuck releases that bound to MinAngle before any other escalation (section 3.4.3).
  std::vector<unsigned char> AngleReleased;
  // Per patch: its own input triangles are exempt from the shape bound (IsPatchTriangle), the next
  // escalation after the release above, before careful mode and full chains; only for patches
  // that hold an input triangle thinner than MinAngle (ThinInput), so no other patch's escalation
  // changes.
  std::vector<unsigned char> ThinOriginals, ThinInput;
  std::vector<unsigned char> ChainFull, PatchOriginal, Dirty, Kept, Refined;
  // Careful mode (a patch's second attempt at each chain resolution): ears that would swallow an
  // unused inner vertex wait until no bite is left, so the front keeps vertices to bite into.
  std::vector<unsigned char> Careful;
  std::vector<std::vector<Index>> PatchChains; // chains around each patch
  std::unordered_set<std::uint64_t> Segments;
  bool ChainsChanged = true; // ChainFull changed since the last SimplifyChains (or none yet)
  std::unordered_map<std::uint64_t, int> EdgeUse;
  std::vector<std::vector<Index>> PatchTris;
  std::vector<P2> Coord; // per mesh vertex, valid for the current patch
  std::vector<Index> FrontNode; // per mesh vertex: its node on the current front (or -1)
  // Split rounds (session 42): the same worker goes on after GreedyCuts::SplitPatches and cuts
  // again only the pieces and their neighbours. Its verification is then local: only the input
  // triangles that can have had their nearest output among the triangles taken out since the last
  // passed verification (Removed, 3 ids each) are proved again.
  bool LocalVerify = false;
  std::vector<Index> Removed;
  std::unordered_set<std::uint64_t> FullChainEdges; // edges of the full-resolution chains, across a split
  long long CutTriangles = 0; // input triangles of the patches cut in the last Execute (work count)
  // Chains whose resolution changed since the last chain pass (Escalate, ContinueAfterSplit): in a
  // split round only they are simplified again (SimplifyChainsLocally).
  std::vector<Index> ChangedChains;
  bool ChainsAroundSplitForgotten = false; // ChangedChains are the new chains around split pieces
  // Split rounds: the patches cut since the last passed verification, whose new edges alone can be
  // used by more than two triangles (the verification before saw none).
  std::vector<Index> CutSinceVerify;

  Worker(const GreedyCuts& g, const GreedyCutsParameters& prm, GreedyCutsResult& res)
    : G(g)
    , M(*g.Mesh)
    , PP(g.Patches)
    , Prm(prm)
    , Res(res)
  {
    this->Eps = prm.Epsilon;
    this->EpsLocal = prm.LocalTolerance * prm.Epsilon;
    this->MinAngle = vtkMath::RadiansFromDegrees(prm.MinimumAngle);
    this->ShapedAngle = vtkMath::RadiansFromDegrees(std::max(prm.MinimumAngle, prm.ShapedAngle));
    this->EarShape = vtkMath::RadiansFromDegrees(prm.EarShapeAngle);
    const Index np = PP.NumberOfPatches();
    this->ChainFull.assign(size_t(PP.NumberOfChains()), 0);
    this->PatchOriginal.assign(size_t(np), 0);
    this->Refined.assign(size_t(np), 0);
    this->Careful.assign(size_t(np), 0);
    this->AngleReleased.assign(size_t(np), this->ShapedAngle > this->MinAngle ? 0 : 1);
    this->ThinOriginals.assign(size_t(np), 0);
    this->ThinInput.assign(size_t(np), 0);
    for (Index p = 0; p < np; ++p)
    {
      this->ThinInput[p] = this->HasThinInput(p);
    }
    this->Dirty.assign(size_t(np), 1);
    this->PatchTris.assign(size_t(np), {});
    this->PatchChains.assign(size_t(np), {});
    for (Index p = 0; p < np; ++p)
    {
      this->PatchChains[p].assign(PP.PatchChainsBegin(p), PP.PatchChainsEnd(p));
    }
    this->Coord.resize(size_t(M.NumberOfPoints()));
    this->FrontNode.assign(size_t(M.NumberOfPoints()), InvalidIndex);
    for (Index p = 0; p < np; ++p)
    {
      this->StartOriginalWhenNoDisk(p);
    }
    for (Index c = 0; c < PP.NumberOfChains(); ++c)
    {
      if (PP.ChainIsNonManifold(c))
      {
        this->ChainFull[c] = 1;
      }
    }
  }

  bool HasThinInput(Index p) const
  {
    for (Index i = G.PatchTriangleOffsets[p]; i < G.PatchTriangleOffsets[p + 1]; ++i)
    {
      const Index* tri = M.Triangle(G.PatchTriangleList[i]);
      if (MinimumAngle(M.Point(tri[0]), M.Point(tri[1]), M.Point(tri[2])) < this->MinAngle)
      {
        return true;
      }
    }
    return false;
  }

  // A seam triangle's patch is kept as it is from the start, as a patch that is no disk is.
  void StartOriginalWhenNoDisk(Index p)
  {
    if (!G.LoopValid[p] || G.IsSeamPatch(p))
    {
      this->PatchOriginal[p] = 1;
      for (Index c : this->PatchChains[p])
      {
        this->ChainFull[c] = 1;
      }
    }
  }

  // Before GreedyCuts::SplitPatches(split) renumbers the chains: the edges of every chain at full
  // resolution, by which they are found again after it (a chain between two patches the split
  // leaves alone keeps its edges, and an edge lies on one chain only); the chains around the split
  // patches are forgotten (their segments would forbid diagonals the new chains do not make).
  void PrepareSplit(const std::vector<Index>& split)
  {
    std::vector<unsigned char> splitPatch(size_t(PP.NumberOfPatches()), 0);
    for (Index p : split)
    {
      splitPatch[p] = 1;
    }
    this->FullChainEdges.clear();
    for (Index c = 0; c < PP.NumberOfChains(); ++c)
    {
      const Index l = PP.ChainLeftPatch(c), r = PP.ChainRightPatch(c);
      if ((l != InvalidIndex && splitPatch[l]) || (r != InvalidIndex && splitPatch[r]))
      {
        this->ForgetChain(c, nullptr);
      }
      const Index* v = PP.ChainVerticesBegin(c);
      for (Index i = 0; this->ChainFull[c] && i + 1 < PP.ChainSize(c); ++i)
      {
        this->FullChainEdges.insert(EdgeKey(v[i], v[i + 1]));
      }
    }
  }

  // After GreedyCuts::SplitPatches(split) (the pieces: the split patches and the patches numbered
  // from oldPatches on): the pieces and every patch sharing a chain with one start again as in a
  // new run (Dirty, escalations undone, their chains simplified); every other patch keeps its
  // triangulation, its escalations and its chains' resolution. The next Execute cuts the dirty
  // patches and those whose chains' kept vertices the new chains change, and verifies locally.
  void ContinueAfterSplit(const std::vector<Index>& split, Index oldPatches)
  {
    const Index np = PP.NumberOfPatches();
    for (auto* v : { &this->PatchOriginal, &this->Refined, &this->Careful, &this->AngleReleased, &this->ThinOriginals,
           &this->ThinInput, &this->Dirty })
    {
      v->resize(size_t(np), 0);
    }
    this->PatchTris.resize(size_t(np));
    this->PatchChains.resize(size_t(np));
    std::vector<unsigned char> piece(size_t(np), 0);
    for (Index p : split)
    {
      piece[p] = 1;
    }
    std::fill(piece.begin() + oldPatches, piece.end(), 1);
    std::fill(this->Dirty.begin(), this->Dirty.end(), 0);
    this->ChainFull.assign(size_t(PP.NumberOfChains()), 0);
    this->ChangedChains.clear(); // the chains around the pieces: simplified again (PrepareSplit forgot the old ones)
    for (Index c = 0; c < PP.NumberOfChains(); ++c)
    {
      const Index l = PP.ChainLeftPatch(c), r = PP.ChainRightPatch(c);
      const bool nearPiece = (l != InvalidIndex && piece[l]) || (r != InvalidIndex && piece[r]);
      const Index* v = PP.ChainVerticesBegin(c);
      this->ChainFull[c] = PP.ChainIsNonManifold(c) ||
        (!nearPiece && PP.ChainSize(c) >= 2 && this->FullChainEdges.count(EdgeKey(v[0], v[1])));
      if (nearPiece)
      {
        this->ChangedChains.push_back(c);
      }
      for (Index q : { l, r })
      {
        if (q != InvalidIndex && nearPiece)
        {
          this->Dirty[q] = 1;
        }
      }
    }
    this->FullChainEdges.clear();
    for (Index p = 0; p < np; ++p)
    {
      this->PatchChains[p].assign(PP.PatchChainsBegin(p), PP.PatchChainsEnd(p));
    }
    for (Index p = 0; p < np; ++p)
    {
      if (this->Dirty[p] || piece[p])
      {
        this->Dirty[p] = 1;
        this->PatchOriginal[p] = this->Refined[p] = this->Careful[p] = this->ThinOriginals[p] = 0;
        this->AngleReleased[p] = this->ShapedAngle > this->MinAngle ? 0 : 1;
        this->ThinInput[p] = this->HasThinInput(p);
        this->StartOriginalWhenNoDisk(p);
      }
    }
    this->ChainsChanged = true;
    this->ChainsAroundSplitForgotten = true;
    this->LocalVerify = true;
  }

  void SimplifyChains()
  {
    this->Kept.assign(size_t(M.NumberOfPoints()), 0);
    this->Segments.clear();
    std::vector<unsigned char> keep;
    std::vector<Index> positions;
    for (Index c = 0; c < PP.NumberOfChains(); ++c)
    {
      this->SimplifyOneChain(c, keep, positions);
    }
    this->ChangedChains.clear();
  }

  // Chain c simplified against the segments of the chains simplified before it: its kept vertices
  // set in Kept, its segments added to Segments.
  void SimplifyOneChain(Index c, std::vector<unsigned char>& keep, std::vector<Index>& positions)
  {
    const Index* v = PP.ChainVerticesBegin(c);
    const Index n = PP.ChainSize(c);
    SimplifyChain(M, v, n, this->ChainFull[c] ? -1.0 : Prm.ChainTolerance * this->Eps, keep);
    // Two chains simplified to the same segment would make a non-manifold edge: keep a vertex
    // apart (the farthest one), until every segment is new.
    for (bool again = true; again;)
    {
      again = false;
      positions.clear();
      for (Index i = 0; i < n; ++i)
      {
        if (keep[i])
        {
          positions.push_back(i);
        }
      }
      for (size_t k = 0; k + 1 < positions.size(); ++k)
      {
        const Index i = positions[k], j = positions[k + 1];
        if (j - i >= 2 && (v[i] == v[j] || this->Segments.count(EdgeKey(v[i], v[j]))))
        {
          keep[FarthestChainVertex(M, v, i, j)] = 1;
          again = true;
        }
      }
    }
    for (size_t k = 0; k < positions.size(); ++k)
    {
      this->Kept[v[positions[k]]] = 1;
      if (k + 1 < positions.size())
      {
        this->Segments.insert(EdgeKey(v[positions[k]], v[positions[k + 1]]));
      }
    }
  }

  // Chain c's segments taken out of Segments (unless `segmentsOut`: PrepareSplit took them out
  // already, under the chains before the split) and its inner vertices out of Kept (its ends stay:
  // every chain keeps its ends); `inner` (when given) gets the inner vertices' old flags.
  void ForgetChain(Index c, std::vector<unsigned char>* inner, bool segmentsOut = false)
  {
    const Index* v = PP.ChainVerticesBegin(c);
    const Index n = PP.ChainSize(c);
    for (Index i = 0, last = 0; !segmentsOut && i + 1 < n; ++i)
    {
      if (i + 2 == n || this->Kept[v[i + 1]])
      {
        this->Segments.erase(EdgeKey(v[last], v[i + 1]));
        last = i + 1;
      }
    }
    for (Index i = 1; i + 1 < n; ++i)
    {
      if (inner)
      {
        inner->push_back(this->Kept[v[i]]);
      }
      this->Kept[v[i]] = 0;
    }
  }

  // A split round's chain pass: only the chains whose resolution changed (ChangedChains) are
  // simplified again (the global pass costs every chain of the input, half of a split round's CPU
  // on the 4M noisy scan). The other chains keep their kept vertices and segments, so both sides of
  // every chain still see the same polygon; the patches beside a chain whose kept vertices changed
  // are cut again.
  void SimplifyChainsLocally()
  {
    std::sort(this->ChangedChains.begin(), this->ChangedChains.end());
    this->ChangedChains.erase(
      std::unique(this->ChangedChains.begin(), this->ChangedChains.end()), this->ChangedChains.end());
    std::vector<unsigned char> before, keep; // the changed chains' inner kept flags, chain after chain
    std::vector<size_t> offsets;
    std::vector<Index> positions;
    for (Index c : this->ChangedChains)
    {
      offsets.push_back(before.size());
      this->ForgetChain(c, &before, this->ChainsAroundSplitForgotten);
    }
    this->ChainsAroundSplitForgotten = false;
    for (size_t k = 0; k < this->ChangedChains.size(); ++k)
    {
      const Index c = this->ChangedChains[k];
      const Index* v = PP.ChainVerticesBegin(c);
      this->SimplifyOneChain(c, keep, positions);
      bool changed = false;
      for (Index i = 1; i + 1 < PP.ChainSize(c) && !changed; ++i)
      {
        changed = this->Kept[v[i]] != before[offsets[k] + size_t(i - 1)];
      }
      for (Index q : { PP.ChainLeftPatch(c), PP.ChainRightPatch(c) })
      {
        if (changed && q != InvalidIndex)
        {
          this->Dirty[q] = 1;
        }
      }
    }
    this->ChangedChains.clear();
  }

  // A chain's simplification also depends on the chains simplified before it (no two may give the
  // same segment): refining one chain can drop a vertex another chain kept apart. Both patches of
  // every chain whose kept vertices changed are triangulated again, else the untouched side keeps
  // triangles on the dropped vertex and the surface opens there.
  void MarkChangedChainPatches(const std::vector<unsigned char>& keptBefore)
  {
    if (keptBefore.size() != this->Kept.size())
    {
      return; // first round: every patch is dirty
    }
    for (Index c = 0; c < PP.NumberOfChains(); ++c)
    {
      const Index* v = PP.ChainVerticesBegin(c);
      bool changed = false;
      for (Index i = 0; i < PP.ChainSize(c) && !changed; ++i)
      {
        changed = this->Kept[v[i]] != keptBefore[v[i]];
      }
      for (Index p : { PP.ChainLeftPatch(c), PP.ChainRightPatch(c) })
      {
        if (changed && p != InvalidIndex)
        {
          this->Dirty[p] = 1;
        }
      }
    }
  }

  void AddEdges(const std::vector<Index>& tris, int delta)
  {
    for (size_t t = 0; t < tris.size(); t += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        const std::uint64_t key = EdgeKey(tris[t + k], tris[t + (k + 1) % 3]);
        int& use = this->EdgeUse[key];
        use += delta;
        if (use == 0)
        {
          this->EdgeUse.erase(key);
        }
      }
    }
  }

  bool EdgeExists(Index a, Index b) const
  {
    const std::uint64_t key = EdgeKey(a, b);
    return this->Segments.count(key) || this->EdgeUse.count(key);
  }

  // --- Greedy cuts on one patch ---
  struct PatchState
  {
    Index Patch;
    Vec3 Normal;
    std::vector<Index> Vert, Prev, Next;
    std::vector<signed char> EarState; // -1 unknown, 0 not an ear, 1 feasible ear
    std::vector<double> EarArea;
    Index Head = 0, Count = 0;
    std::vector<Index> Inner;
    std::vector<unsigned char> Consumed;
    InnerBuckets InnerNear; // Inner by position (bite candidates)
    std::unordered_map<TripleKey, bool, TripleHash> Cache;
    double Tol = 0; // orientation tolerance (squared length scale)
    double SharpAngle = vtkMath::Pi() / 6; // front repair: corners below this are sharp
    bool Careful = false, Relaxed = false;

    // Inserts original vertex v into the front after node `after`; returns its node.
    Index InsertAfter(Index after, Index v)
    {
      const Index j = this->Next[after];
      const Index node = static_cast<Index>(this->Vert.size());
      this->Vert.push_back(v);
      this->Prev.push_back(after);
      this->Next.push_back(j);
      this->EarState.push_back(-1);
      this->EarArea.push_back(0);
      this->Next[after] = node;
      this->Prev[j] = node;
      ++this->Count;
      return node;
    }
  };

  bool Feasible(PatchState& s, Index a, Index b, Index c)
  {
    const TripleKey key = MakeTriple(a, b, c);
    auto it = s.Cache.find(key);
    if (it != s.Cache.end())
    {
      return it->second;
    }
    ++this->Res.FeasibilityTests;
    const bool ok = this->TestFeasible(s, a, b, c);
    s.Cache.emplace(key, ok);
    return ok;
  }

  // Whether a, b, c are the corners of one of patch p's own (input) triangles. Once the patch got
  // stuck (ThinOriginals), such a triangle is exempt from the shape bound: keeping it creates no
  // sliver the input did not have, and the patch's fallback would keep it anyway. Without this,
  // every input triangle thinner than MinimumAngle made its patch fall back and be split, whole
  // runs over, until it was a patch of its own (CAD meshes at 0.01 of the diagonal: anchor 16
  // fallback patches, boeing 104). Only once stuck, so a patch that closes without its thin input
  // triangles is cut as before. Called for thin candidates only: the triangles around a (the
  // input's vertex fan) in patch p, O(valence).
  bool IsPatchTriangle(Index p, Index a, Index b, Index c) const
  {
    const std::vector<Index>& patchOf = G.Patches.TrianglePatches();
    for (const Index* t = G.Topology.VertexTrianglesBegin(a); t != G.Topology.VertexTrianglesEnd(a); ++t)
    {
      if (patchOf[*t] != p)
      {
        continue;
      }
      const Index* tri = M.Triangle(*t);
      int shared = 0;
      for (int k = 0; k < 3; ++k)
      {
        shared += tri[k] == a || tri[k] == b || tri[k] == c;
      }
      if (shared == 3)
      {
        return true;
      }
    }
    return false;
  }

  bool TestFeasible(PatchState& s, Index ia, Index ib, Index ic)
  {
    const Vec3 A = M.Point(ia), B = M.Point(ib), C = M.Point(ic);
    if (IsDegenerate(A, B, C) ||
      (MinimumAngle(A, B, C) < (this->AngleReleased[s.Patch] ? this->MinAngle : this->ShapedAngle) &&
        !(this->ThinOriginals[s.Patch] && this->IsPatchTriangle(s.Patch, ia, ib, ic))))
    {
      return false;
    }
    const Vec3 nq = Normalized(Cross(B - A, C - A));
    // Chapter 3's terrain patches may be steep (their triangles only face the height direction):
    // Q need only face it too, as its patch's triangles do.
    // A stuck patch's own input triangle (ThinOriginals) need only face the patch's side: a sliver's
    // normal is ill-conditioned, and keeping it adds no triangle the input did not have.
    const double facing = Dot(nq, s.Normal);
    const bool ownTriangle = this->ThinOriginals[s.Patch] && facing > 0 && this->IsPatchTriangle(s.Patch, ia, ib, ic);
    if (facing <= (G.Terrain ? MinimumTerrainCosine : MinimumNormalCosine) && !ownTriangle)
    {
      return false;
    }
    // (b) the original surface under Q (the patch's triangles clipped to Q's prism) within
    // epsilon of Q, and facing the same way.
    const P2 a = this->Coord[ia], b = this->Coord[ib], c = this->Coord[ic];
    const double qArea2 = Orient(a, b, c);
    const double xmin = std::min({ a.x, b.x, c.x }), xmax = std::max({ a.x, b.x, c.x });
    const double ymin = std::min({ a.y, b.y, c.y }), ymax = std::max({ a.y, b.y, c.y });
    std::vector<ClipVertex> poly, tmp;
    for (Index i = G.PatchTriangleOffsets[s.Patch]; i < G.PatchTriangleOffsets[s.Patch + 1]; ++i)
    {
      const Index t = G.PatchTriangleList[i];
      const Index* tri = M.Triangle(t);
      const P2 &p0 = this->Coord[tri[0]], &p1 = this->Coord[tri[1]], &p2 = this->Coord[tri[2]];
      if (std::max({ p0.x, p1.x, p2.x }) < xmin || std::min({ p0.x, p1.x, p2.x }) > xmax ||
        std::max({ p0.y, p1.y, p2.y }) < ymin || std::min({ p0.y, p1.y, p2.y }) > ymax)
      {
        continue;
      }
      poly = { { p0, M.Point(tri[0]) }, { p1, M.Point(tri[1]) }, { p2, M.Point(tri[2]) } };
      ClipHalfPlane(poly, a, b, tmp);
      ClipHalfPlane(tmp, b, c, poly);
      ClipHalfPlane(poly, c, a, tmp);
      if (tmp.size() < 3)
      {
        continue;
      }
      const double clipped = std::fabs(PolygonArea2(tmp));
      if (clipped <= 1e-9 * qArea2)
      {
        continue;
      }
      if (clipped > 1e-6 * qArea2 && Dot(M.TriangleAreaVector(t), nq) <= 0)
      {
        return false; // Q would be flipped with respect to this original triangle
      }
      for (const ClipVertex& v : tmp)
      {
        const Vec3 d = v.x - ClosestPointOnTriangle(v.x, A, B, C);
        if (Dot(d, d) > this->EpsLocal * this->EpsLocal)
        {
          return false;
        }
      }
    }
    // The original surface nearest Q's centroid faces the same way.
    {
      const ClosestPointResult hit = G.Bvh.ClosestPoint((1.0 / 3.0) * (A + B + C));
      if (hit.Triangle == InvalidIndex || Dot(Normalized(M.TriangleAreaVector(hit.Triangle)), nq) <= MinimumNormalCosine)
      {
        return false;
      }
    }
    // (a) Q within epsilon of the original surface (rigorous, adaptive).
    return TriangleWithinDistance(G.Bvh, A, B, C, this->Eps, Prm.SubdivisionDepth, &G.ProofPieces);
  }

  void Emit(PatchState& s, std::vector<Index>& tris, Index a, Index b, Index c)
  {
    tris.push_back(a);
    tris.push_back(b);
    tris.push_back(c);
    for (const auto& [u, v] : { std::pair<Index, Index>{ a, b }, { b, c }, { c, a } })
    {
      ++this->EdgeUse[EdgeKey(u, v)];
    }
    const P2 pa = this->Coord[a], pb = this->Coord[b], pc = this->Coord[c];
    const double tol = 1e-12 * std::fabs(Orient(pa, pb, pc)) + s.Tol;
    for (size_t k = 0; k < s.Inner.size(); ++k)
    {
      if (!s.Consumed[k] && InClosedTriangle(this->Coord[s.Inner[k]], pa, pb, pc, tol))
      {
        s.Consumed[k] = 1;
      }
    }
  }

  bool EarValid(PatchState& s, Index i)
  {
    const Index pi = s.Prev[i], ni = s.Next[i];
    const Index a = s.Vert[pi], b = s.Vert[i], c = s.Vert[ni];
    const P2 pa = this->Coord[a], pb = this->Coord[b], pc = this->Coord[c];
    if (Orient(pa, pb, pc) <= s.Tol)
    {
      return false;
    }
    if (this->EdgeExists(a, c))
    {
      return false;
    }
    for (Index j = s.Next[ni]; j != pi; j = s.Next[j])
    {
      if (InClosedTriangle(this->Coord[s.Vert[j]], pa, pb, pc, s.Tol))
      {
        return false;
      }
    }
    if (s.Careful && !s.Relaxed)
    {
      for (size_t k = 0; k < s.Inner.size(); ++k)
      {
        if (!s.Consumed[k] && InClosedTriangle(this->Coord[s.Inner[k]], pa, pb, pc, s.Tol))
        {
          return false;
        }
      }
    }
    return true;
  }

  // Whether the bite (a, b, v) on front edge (node i -> next) keeps the front simple: no other
  // front vertex in it, no front edge crossing its new edges (a, v) and (v, b). Each front vertex's
  // sides of those two lines are computed once and carried to the next front edge (this walk is
  // about half of an open scan's instructions): the same values ProperCross computes, so the same
  // decisions.
  bool BiteValid(PatchState& s, Index i, Index v)
  {
    const Index j = s.Next[i];
    const P2 pa = this->Coord[s.Vert[i]], pb = this->Coord[s.Vert[j]], pv = this->Coord[v];
    if (Orient(pa, pb, pv) <= s.Tol)
    {
      return false;
    }
    Index k = j;
    P2 pk = this->Coord[s.Vert[k]];
    double sideAV = Orient(pa, pv, pk), sideVB = Orient(pv, pb, pk);
    do
    {
      const Index kn = s.Next[k];
      const P2 pkn = this->Coord[s.Vert[kn]];
      if (!Prm.CarryFrontSides)
      {
        sideAV = Orient(pa, pv, pk);
        sideVB = Orient(pv, pb, pk);
      }
      const double nextAV = Orient(pa, pv, pkn), nextVB = Orient(pv, pb, pkn);
      if (k != j && k != i && InClosedTriangle(pk, pa, pb, pv, s.Tol))
      {
        return false;
      }
      if (ProperCrossGivenSides(sideAV, nextAV, pa, pv, pk, pkn) ||
        ProperCrossGivenSides(sideVB, nextVB, pv, pb, pk, pkn))
      {
        return false;
      }
      k = kn;
      pk = pkn;
      sideAV = nextAV;
      sideVB = nextVB;
    } while (k != j);
    return true;
  }

  // Best bite on edge (node i -> next): candidates by distance to the equilateral apex.
  // Wide mode (nearOnly false) considers the inner vertices of `open` (those not consumed).
  bool BestBite(PatchState& s, Index i, size_t limit, bool nearOnly, Index& bestInner, double& area,
    std::vector<std::pair<double, Index>>& candidates, const std::vector<Index>& open = {})
  {
    const Index a = s.Vert[i], b = s.Vert[s.Next[i]];
    const P2 pa = this->Coord[a], pb = this->Coord[b];
    const double dx = pb.x - pa.x, dy = pb.y - pa.y;
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length <= 0)
    {
      return false;
    }
    const double h = 0.5 * std::sqrt(3.0);
    const P2 apex{ 0.5 * (pa.x + pb.x) - h * dy, 0.5 * (pa.y + pb.y) + h * dx };
    candidates.clear();
    const auto consider = [&](size_t k) {
      if (s.Consumed[k])
      {
        return;
      }
      const P2 pv = this->Coord[s.Inner[k]];
      if (Orient(pa, pb, pv) <= s.Tol)
      {
        return;
      }
      // Near mode: aspect ratio near 1 (distance to the equilateral apex). Wide mode: the
      // smallest triangles first (distance to the edge's midpoint): the likeliest to fit.
      const double d = nearOnly ? std::hypot(pv.x - apex.x, pv.y - apex.y)
                                : std::hypot(pv.x - 0.5 * (pa.x + pb.x), pv.y - 0.5 * (pa.y + pb.y));
      if (nearOnly && d > 1.5 * length)
      {
        return;
      }
      candidates.emplace_back(d, static_cast<Index>(k));
    };
    if (nearOnly)
    {
      // The same candidates as a scan of all (within 1.5 |ab| of the apex); their order below is
      // by (distance, index), so the choice does not depend on the buckets.
      s.InnerNear.ForEachNear(apex, 1.5 * length, [&](Index k) { consider(size_t(k)); });
    }
    else
    {
      for (Index k : open)
      {
        consider(size_t(k));
      }
    }
    const size_t m = std::min(limit, candidates.size());
    std::partial_sort(candidates.begin(), candidates.begin() + m, candidates.end());
    for (size_t q = 0; q < m; ++q)
    {
      const Index v = s.Inner[candidates[q].second];
      if (this->BiteValid(s, i, v) && this->Feasible(s, a, b, v))
      {
        bestInner = candidates[q].second;
        area = 0.5 * Norm(Cross(M.Point(b) - M.Point(a), M.Point(v) - M.Point(a)));
        return true;
      }
    }
    return false;
  }

  bool TriangulateGreedy(Index p, std::vector<Index>& tris)
  {
    PatchState s;
    const bool ok = this->Greedy(p, s, tris);
    for (Index v : s.Vert)
    {
      this->FrontNode[v] = InvalidIndex;
    }
    return ok;
  }

  // --- Front repair (section 3.4.3) ---
  // Position in tris of the generated triangle on edge (u, w) (at most one: the other side of a
  // front edge is still open), or size_t(-1).
  static size_t TriangleOnEdge(const std::vector<Index>& tris, Index u, Index w)
  {
    for (size_t t = 0; t < tris.size(); t += 3)
    {
      int shared = 0;
      for (int k = 0; k < 3; ++k)
      {
        shared += tris[t + k] == u || tris[t + k] == w;
      }
      if (shared == 2)
      {
        return t;
      }
    }
    return size_t(-1);
  }

  static Index ThirdVertex(const std::vector<Index>& tris, size_t t, Index u, Index w)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (tris[t + k] != u && tris[t + k] != w)
      {
        return tris[t + k];
      }
    }
    return InvalidIndex;
  }

  // Takes the triangle at tris[t] back out of the triangulation (it is never cut again: every
  // repair then makes progress) and frees the inner vertices it covered.
  void PutBack(PatchState& s, std::vector<Index>& tris, size_t t)
  {
    const Index a = tris[t], b = tris[t + 1], c = tris[t + 2];
    s.Cache[MakeTriple(a, b, c)] = false;
    for (const auto& [u, v] : { std::pair<Index, Index>{ a, b }, { b, c }, { c, a } })
    {
      auto it = this->EdgeUse.find(EdgeKey(u, v));
      if (it != this->EdgeUse.end() && --it->second == 0)
      {
        this->EdgeUse.erase(it);
      }
    }
    tris.erase(tris.begin() + std::ptrdiff_t(t), tris.begin() + std::ptrdiff_t(t) + 3);
    const P2 pa = this->Coord[a], pb = this->Coord[b], pc = this->Coord[c];
    const double tol = 1e-9 * std::fabs(Orient(pa, pb, pc)) + s.Tol;
    for (size_t k = 0; k < s.Inner.size(); ++k)
    {
      const Index v = s.Inner[k];
      const P2 q = this->Coord[v];
      if (s.Consumed[k] && this->FrontNode[v] == InvalidIndex && v != a && v != b && v != c &&
        Orient(pa, pb, q) > tol && Orient(pb, pc, q) > tol && Orient(pc, pa, q) > tol)
      {
        s.Consumed[k] = 0;
      }
    }
    std::fill(s.EarState.begin(), s.EarState.end(), -1);
    ++this->Res.Repairs;
  }

  // Inner angle of the front at node i (the front runs counter-clockwise around the open part).
  double FrontAngle(const PatchState& s, Index i) const
  {
    const P2 a = this->Coord[s.Vert[s.Prev[i]]], b = this->Coord[s.Vert[i]], c = this->Coord[s.Vert[s.Next[i]]];
    const double ux = c.x - b.x, uy = c.y - b.y, vx = a.x - b.x, vy = a.y - b.y;
    const double angle = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    return angle < 0 ? angle + 2 * vtkMath::Pi() : angle;
  }

  void RemoveFrontNode(PatchState& s, Index i)
  {
    const Index pi = s.Prev[i], ni = s.Next[i];
    s.Next[pi] = ni;
    s.Prev[ni] = pi;
    this->FrontNode[s.Vert[i]] = InvalidIndex;
    s.Head = pi;
    --s.Count;
    std::fill(s.EarState.begin(), s.EarState.end(), -1);
  }

  // The two front edges at node i as (first node of the edge, other corner of the ear at i),
  // the longer edge first.
  std::array<std::pair<Index, Index>, 2> CornerEdges(const PatchState& s, Index i) const
  {
    const Index pi = s.Prev[i], ni = s.Next[i];
    const Vec3 a = M.Point(s.Vert[pi]), b = M.Point(s.Vert[i]), c = M.Point(s.Vert[ni]);
    std::array<std::pair<Index, Index>, 2> edges{ std::pair<Index, Index>{ i, pi }, { pi, ni } };
    if (Dot(b - a, b - a) > Dot(c - b, c - b))
    {
      std::swap(edges[0], edges[1]);
    }
    return edges;
  }

  // Edge swap (figure 5): the ear at node i is infeasible; the triangle behind its longer front
  // edge (e1, e2, d) and the ear form a convex quadrilateral whose other diagonal (x, d) gives
  // two triangles that may be feasible. Node i leaves the front.
  bool EdgeSwap(PatchState& s, std::vector<Index>& tris, Index i)
  {
    const Index pi = s.Prev[i], ni = s.Next[i];
    const P2 pa = this->Coord[s.Vert[pi]], pb = this->Coord[s.Vert[i]], pc = this->Coord[s.Vert[ni]];
    for (Index j = s.Next[ni]; j != pi; j = s.Next[j])
    {
      if (InClosedTriangle(this->Coord[s.Vert[j]], pa, pb, pc, s.Tol))
      {
        return false; // the ear's area holds another part of the front
      }
    }
    for (const auto& [first, other] : this->CornerEdges(s, i))
    {
      const Index e1 = s.Vert[first], e2 = s.Vert[s.Next[first]], x = s.Vert[other];
      const size_t t = this->Segments.count(EdgeKey(e1, e2)) ? size_t(-1) : TriangleOnEdge(tris, e1, e2);
      const Index d = t == size_t(-1) ? InvalidIndex : ThirdVertex(tris, t, e1, e2);
      if (d == InvalidIndex || this->FrontNode[d] != InvalidIndex || this->EdgeExists(x, d) ||
        !ProperCross(this->Coord[x], this->Coord[d], this->Coord[e1], this->Coord[e2]))
      {
        continue;
      }
      // Counter-clockwise: (x, e1) and (e2, x) are front edges' directions around the ear.
      const std::array<Index, 3> t1{ x, d, e2 }, t2{ x, e1, d };
      const bool orderFirst = Orient(this->Coord[t1[0]], this->Coord[t1[1]], this->Coord[t1[2]]) > s.Tol &&
        Orient(this->Coord[t2[0]], this->Coord[t2[1]], this->Coord[t2[2]]) > s.Tol;
      if (!orderFirst || !this->Feasible(s, t1[0], t1[1], t1[2]) || !this->Feasible(s, t2[0], t2[1], t2[2]))
      {
        continue;
      }
      this->PutBack(s, tris, t);
      this->Emit(s, tris, t1[0], t1[1], t1[2]);
      this->Emit(s, tris, t2[0], t2[1], t2[2]);
      this->RemoveFrontNode(s, i);
      ++this->Res.EdgeSwaps;
      return true;
    }
    return false;
  }

  // Face split (figure 6): the triangle behind the longer front edge at node i is put back; its
  // third vertex joins the front (then bites into the freed area and ears follow). When that
  // triangle is the corner's own (behind both edges at i) and i is an inner vertex, the vertex is
  // deleted from the front instead (the extreme case of the paper's sequence of face splits).
  bool FaceSplit(PatchState& s, std::vector<Index>& tris, Index i)
  {
    for (const auto& [first, other] : this->CornerEdges(s, i))
    {
      const Index e1 = s.Vert[first], e2 = s.Vert[s.Next[first]];
      const size_t t = this->Segments.count(EdgeKey(e1, e2)) ? size_t(-1) : TriangleOnEdge(tris, e1, e2);
      const Index d = t == size_t(-1) ? InvalidIndex : ThirdVertex(tris, t, e1, e2);
      if (d == InvalidIndex)
      {
        continue;
      }
      if (this->FrontNode[d] == InvalidIndex)
      {
        this->PutBack(s, tris, t);
        this->FrontNode[d] = s.InsertAfter(first, d);
        ++this->Res.FaceSplits;
        return true;
      }
      const auto inner = std::find(s.Inner.begin(), s.Inner.end(), s.Vert[i]);
      if (d == s.Vert[other] && inner != s.Inner.end())
      {
        this->PutBack(s, tris, t);
        this->RemoveFrontNode(s, i);
        s.Consumed[size_t(inner - s.Inner.begin())] = 0;
        ++this->Res.VertexDeletions;
        return true;
      }
    }
    return false;
  }

  // Section 3.4.3: the sharpest corners of a stuck front first (edge swap, else face split); when
  // no corner below the current sharpness bound can be repaired the bound is released step by
  // step (s.SharpAngle), up to every convex corner.
  bool Repair(PatchState& s, std::vector<Index>& tris)
  {
    for (; s.SharpAngle <= vtkMath::Pi(); s.SharpAngle += vtkMath::Pi() / 6)
    {
      std::vector<std::pair<double, Index>> corners;
      Index i = s.Head;
      do
      {
        const double angle = this->FrontAngle(s, i);
        if (angle < s.SharpAngle)
        {
          corners.emplace_back(angle, i);
        }
        i = s.Next[i];
      } while (i != s.Head);
      std::sort(corners.begin(), corners.end());
      for (const auto& corner : corners)
      {
        if (this->EdgeSwap(s, tris, corner.second) || this->FaceSplit(s, tris, corner.second))
        {
          return true;
        }
      }
    }
    s.SharpAngle = vtkMath::Pi() / 6;
    return this->RepairLongestEdge(s, tris);
  }

  // Last resort: the triangle behind the longest front edge that is not a chain segment is put
  // back, which frees the inner vertices it covered and reopens the front there.
  bool RepairLongestEdge(PatchState& s, std::vector<Index>& tris)
  {
    size_t bestTri = size_t(-1);
    Index bestNode = InvalidIndex, bestX = InvalidIndex;
    double bestLength = -1;
    Index i = s.Head;
    do
    {
      const Index u = s.Vert[i], w = s.Vert[s.Next[i]];
      const size_t t = this->Segments.count(EdgeKey(u, w)) ? size_t(-1) : TriangleOnEdge(tris, u, w);
      const Index x = t == size_t(-1) ? InvalidIndex : ThirdVertex(tris, t, u, w);
      const Vec3 d = M.Point(w) - M.Point(u);
      if (x != InvalidIndex && this->FrontNode[x] == InvalidIndex && Dot(d, d) > bestLength)
      {
        bestLength = Dot(d, d);
        bestTri = t;
        bestNode = i;
        bestX = x;
      }
      i = s.Next[i];
    } while (i != s.Head);
    if (bestNode == InvalidIndex)
    {
      return false;
    }
    this->PutBack(s, tris, bestTri);
    this->FrontNode[bestX] = s.InsertAfter(bestNode, bestX);
    return true;
  }

  // The patch's kept boundary vertices, projected to the patch plane (section 3.4.1: a patch is
  // nearly planar). Fails when the patch has no plane.
  bool ProjectPatch(Index p, PatchState& s)
  {
    s.Patch = p;
    s.Normal = G.HeightDirection[p];
    s.Careful = this->Careful[p] != 0;
    for (Index v : G.PatchLoops[p])
    {
      if (this->Kept[v])
      {
        s.Vert.push_back(v);
      }
    }
    if (s.Vert.size() < 3 || Norm(s.Normal) == 0)
    {
      return false;
    }
    // Plane frame and 2D coordinates of the patch's vertices.
    const Vec3& nn = s.Normal;
    const Vec3 axis = std::fabs(nn[0]) < 0.6 ? Vec3{ 1, 0, 0 } : (std::fabs(nn[1]) < 0.6 ? Vec3{ 0, 1, 0 } : Vec3{ 0, 0, 1 });
    const Vec3 U = Normalized(Cross(axis, nn));
    const Vec3 W = Cross(nn, U);
    for (Index i = G.PatchTriangleOffsets[p]; i < G.PatchTriangleOffsets[p + 1]; ++i)
    {
      const Index* tri = M.Triangle(G.PatchTriangleList[i]);
      for (int k = 0; k < 3; ++k)
      {
        const Vec3 x = M.Point(tri[k]);
        this->Coord[tri[k]] = { Dot(x, U), Dot(x, W) };
      }
    }
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (Index v : s.Vert)
    {
      xmin = std::min(xmin, this->Coord[v].x);
      xmax = std::max(xmax, this->Coord[v].x);
      ymin = std::min(ymin, this->Coord[v].y);
      ymax = std::max(ymax, this->Coord[v].y);
    }
    const double scale = std::max(xmax - xmin, ymax - ymin);
    s.Tol = 1e-12 * scale * scale;
    return true;
  }

  // The boundary must project to a simple, counter-clockwise polygon.
  bool FrontIsSimpleCounterClockwise(const PatchState& s) const
  {
    const Index n = static_cast<Index>(s.Vert.size());
    double area2 = 0;
    for (Index i = 0; i < n; ++i)
    {
      const P2 &u = this->Coord[s.Vert[i]], &w = this->Coord[s.Vert[(i + 1) % n]];
      area2 += u.x * w.y - u.y * w.x;
    }
    if (area2 <= 0)
    {
      return false;
    }
    for (Index i = 0; i < n; ++i)
    {
      const P2 a = this->Coord[s.Vert[i]], b = this->Coord[s.Vert[(i + 1) % n]];
      for (Index j = i + 2; j < n; ++j)
      {
        if (i == 0 && j == n - 1)
        {
          continue;
        }
        if (ProperCross(a, b, this->Coord[s.Vert[j]], this->Coord[s.Vert[(j + 1) % n]]))
        {
          return false;
        }
      }
    }
    return true;
  }

  // The front starts as the boundary polygon (a doubly linked ring); the inner vertices inside it
  // are bite candidates, those outside count as consumed.
  void InitializeFront(Index p, PatchState& s)
  {
    const Index n = static_cast<Index>(s.Vert.size());
    s.Prev.resize(size_t(n));
    s.Next.resize(size_t(n));
    for (Index i = 0; i < n; ++i)
    {
      s.Prev[i] = (i + n - 1) % n;
      s.Next[i] = (i + 1) % n;
    }
    s.EarState.assign(size_t(n), -1);
    s.EarArea.assign(size_t(n), 0);
    for (Index i = 0; i < n; ++i)
    {
      this->FrontNode[s.Vert[i]] = i;
    }
    s.Count = n;
    s.Head = 0;
    s.Inner.assign(G.PatchInnerList.begin() + G.PatchInnerOffsets[p], G.PatchInnerList.begin() + G.PatchInnerOffsets[p + 1]);
    s.InnerNear.Build(this->Coord, s.Inner);
    s.Consumed.assign(s.Inner.size(), 0);
    for (size_t k = 0; k < s.Inner.size(); ++k)
    {
      const P2 q = this->Coord[s.Inner[k]];
      bool inside = false;
      for (Index i = 0, j = n - 1; i < n; j = i++)
      {
        const P2 &a = this->Coord[s.Vert[i]], &b = this->Coord[s.Vert[j]];
        if ((a.y > q.y) != (b.y > q.y) && q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x)
        {
          inside = !inside;
        }
      }
      s.Consumed[k] = inside ? 0 : 1;
    }
  }

  // Weight of an ear's area in the choice of the ear to cut: 1 for an ear whose smallest angle is
  // at least EarShape, falling with the square of the angle below it. The largest ear (Ho's greedy
  // rule) still wins among well-shaped ones, but the fans of caps that the largest-area rule cuts
  // along nearly straight chains on flat parts (measured: most slivers of the output there) come
  // last, after the ears that cut them off. Only the order changes: every ear is still checked by
  // Feasible, so the bound is untouched.
  double EarShapeFactor(Index a, Index b, Index c) const
  {
    if (this->EarShape <= 0)
    {
      return 1.0;
    }
    const double ratio = MinimumAngle(M.Point(a), M.Point(b), M.Point(c)) / this->EarShape;
    return ratio >= 1 ? 1.0 : ratio * ratio;
  }

  // Ear cutting: the feasible ear of largest area weighted by EarShapeFactor (a rescan of
  // non-ears before giving up). Returns whether an ear was cut.
  bool CutBestEar(PatchState& s, std::vector<Index>& tris)
  {
    Index best = InvalidIndex;
    for (int pass = 0; pass < 2 && best == InvalidIndex; ++pass)
    {
      double bestArea = -1;
      Index i = s.Head;
      do
      {
        if (s.EarState[i] < 0 || (pass == 1 && s.EarState[i] == 0))
        {
          s.EarState[i] = 0;
          if (this->EarValid(s, i) && this->Feasible(s, s.Vert[s.Prev[i]], s.Vert[i], s.Vert[s.Next[i]]))
          {
            s.EarState[i] = 1;
            s.EarArea[i] = 0.5 *
              Norm(Cross(M.Point(s.Vert[i]) - M.Point(s.Vert[s.Prev[i]]),
                M.Point(s.Vert[s.Next[i]]) - M.Point(s.Vert[s.Prev[i]])));
            s.EarArea[i] *= this->EarShapeFactor(s.Vert[s.Prev[i]], s.Vert[i], s.Vert[s.Next[i]]);
          }
        }
        if (s.EarState[i] == 1 && s.EarArea[i] > bestArea)
        {
          bestArea = s.EarArea[i];
          best = i;
        }
        i = s.Next[i];
      } while (i != s.Head);
    }
    if (best == InvalidIndex)
    {
      return false;
    }
    const Index pi = s.Prev[best], ni = s.Next[best];
    this->Emit(s, tris, s.Vert[pi], s.Vert[best], s.Vert[ni]);
    ++this->Res.Ears;
    this->FrontNode[s.Vert[best]] = InvalidIndex;
    if (s.Relaxed)
    {
      s.Relaxed = false;
      std::fill(s.EarState.begin(), s.EarState.end(), -1);
    }
    s.Next[pi] = ni;
    s.Prev[ni] = pi;
    s.EarState[pi] = s.EarState[ni] = -1;
    s.Head = pi;
    --s.Count;
    return true;
  }

  // Greedy biting: per front edge the best-shaped feasible bite, the largest over the edges; else
  // the wide search (edge splitting without Steiner points): any inner vertex, longest edges
  // first. Returns whether a bite was found (front node biteEdge, inner candidate biteInner).
  bool FindBite(PatchState& s, std::vector<std::pair<double, Index>>& candidates, Index& biteEdge, Index& biteInner)
  {
    biteEdge = biteInner = InvalidIndex;
    double bestArea = -1;
    Index i = s.Head;
    do
    {
      Index k = InvalidIndex;
      double area = 0;
      if (this->BestBite(s, i, size_t(std::max(1, Prm.BiteCandidates)), true, k, area, candidates) && area > bestArea)
      {
        bestArea = area;
        biteEdge = i;
        biteInner = k;
      }
      i = s.Next[i];
    } while (i != s.Head);
    if (biteEdge != InvalidIndex)
    {
      return true;
    }
    std::vector<std::pair<double, Index>> edges;
    i = s.Head;
    do
    {
      const Vec3 d = M.Point(s.Vert[s.Next[i]]) - M.Point(s.Vert[i]);
      edges.emplace_back(-Dot(d, d), i);
      i = s.Next[i];
    } while (i != s.Head);
    std::sort(edges.begin(), edges.end());
    // Nothing is consumed during this search: list the open inner vertices once, not per edge.
    std::vector<Index> open;
    for (size_t k = 0; k < s.Inner.size(); ++k)
    {
      if (!s.Consumed[k])
      {
        open.push_back(static_cast<Index>(k));
      }
    }
    for (const auto& e : edges)
    {
      double area = 0;
      if (this->BestBite(s, e.second, 64, false, biteInner, area, candidates, open))
      {
        biteEdge = e.second;
        ++this->Res.WideBites;
        return true;
      }
    }
    return false;
  }

  // The bite: inner vertex v joins the front between node biteEdge and its successor.
  void PerformBite(PatchState& s, std::vector<Index>& tris, Index biteEdge, Index biteInner)
  {
    const Index j = s.Next[biteEdge];
    const Index v = s.Inner[biteInner];
    s.Consumed[biteInner] = 1;
    this->FrontNode[v] = s.InsertAfter(biteEdge, v);
    this->Emit(s, tris, s.Vert[biteEdge], s.Vert[j], v);
    ++this->Res.Bites;
    std::fill(s.EarState.begin(), s.EarState.end(), -1);
  }

  // Section 3.4.2: the patch is triangulated from its boundary inwards by ears and bites, each
  // triangle checked against the error bound (Feasible). Returns false when stuck.
  bool Greedy(Index p, PatchState& s, std::vector<Index>& tris)
  {
    if (!this->ProjectPatch(p, s) || !this->FrontIsSimpleCounterClockwise(s))
    {
      return false;
    }
    this->InitializeFront(p, s);
    std::vector<std::pair<double, Index>> candidates;
    const long long size = static_cast<long long>(s.Vert.size()) + static_cast<long long>(s.Inner.size());
    const long long guard = 40 * size + 64;
    long long repairs = 4 * size + 16;
    for (long long step = 0; step < guard; ++step)
    {
      if (s.Count == 2)
      {
        return true; // an edge swap at the last three nodes covered the last ear and closed the front
      }
      if (s.Count == 3)
      {
        const Index a = s.Head, b = s.Next[a], c = s.Next[b];
        const Index va = s.Vert[a], vb = s.Vert[b], vc = s.Vert[c];
        if (Orient(this->Coord[va], this->Coord[vb], this->Coord[vc]) > s.Tol && this->Feasible(s, va, vb, vc))
        {
          this->Emit(s, tris, va, vb, vc);
          ++this->Res.Ears;
          return true;
        }
      }
      else if (this->CutBestEar(s, tris))
      {
        continue;
      }
      Index biteEdge = InvalidIndex, biteInner = InvalidIndex;
      if (this->FindBite(s, candidates, biteEdge, biteInner))
      {
        this->PerformBite(s, tris, biteEdge, biteInner);
        continue;
      }
      if (s.Careful && !s.Relaxed)
      {
        s.Relaxed = true; // one ear may now swallow inner vertices
        std::fill(s.EarState.begin(), s.EarState.end(), -1);
        continue;
      }
      if (repairs-- > 0 && this->Repair(s, tris))
      {
        continue;
      }
      return false; // stuck
    }
    return false;
  }

  // Escalation of a patch that got stuck or failed the verification: the shape bound released,
  // then its own thin input triangles allowed, then careful mode, then its chains at full
  // resolution (normal, then careful), then its original triangles.
  void Escalate(Index p, std::vector<Index>& touched)
  {
    if (this->PatchOriginal[p])
    {
      return;
    }
    touched.push_back(p);
    if (!this->AngleReleased[p])
    {
      this->AngleReleased[p] = 1;
      return;
    }
    if (this->ThinInput[p] && !this->ThinOriginals[p])
    {
      this->ThinOriginals[p] = 1;
      return;
    }
    if (!this->Careful[p])
    {
      this->Careful[p] = 1;
      return;
    }
    this->Careful[p] = 0;
    bool refined = false;
    for (Index c : this->PatchChains[p])
    {
      if (!this->ChainFull[c])
      {
        this->ChainFull[c] = 1;
        this->ChainsChanged = true;
        this->ChangedChains.push_back(c);
        refined = true;
        for (Index q : { PP.ChainLeftPatch(c), PP.ChainRightPatch(c) })
        {
          if (q != InvalidIndex)
          {
            touched.push_back(q);
          }
        }
      }
    }
    if (refined)
    {
      this->Refined[p] = 1;
    }
    else
    {
      this->PatchOriginal[p] = 1;
    }
  }

  void Original(Index p, std::vector<Index>& tris)
  {
    for (Index i = G.PatchTriangleOffsets[p]; i < G.PatchTriangleOffsets[p + 1]; ++i)
    {
      const Index* tri = M.Triangle(G.PatchTriangleList[i]);
      tris.insert(tris.end(), tri, tri + 3);
    }
    this->AddEdges(tris, +1);
  }

  bool Execute(const ProgressFunction& progress)
  {
    const Index np = PP.NumberOfPatches();
    std::vector<Index> touched;
    this->CutTriangles = 0;
    for (int round = 0;; ++round)
    {
      this->Res.Rounds = round + 1;
      if (round >= 64)
      {
        // Safety net (never expected): everything not yet settled keeps its original triangles.
        std::fill(this->ChainFull.begin(), this->ChainFull.end(), 1);
        this->ChainsChanged = true;
        this->LocalVerify = false; // every chain changed: the global pass and verification
        std::fill(this->PatchOriginal.begin(), this->PatchOriginal.end(), 1);
        std::fill(this->Dirty.begin(), this->Dirty.end(), 1);
      }
      // The chains' simplification depends on ChainFull only (and epsilon): a round after which no
      // chain was refined keeps the last one's (the same Kept and Segments), so a round costs the
      // dirty patches, not a pass over every chain of the input.
      if (this->ChainsChanged && this->LocalVerify)
      {
        this->SimplifyChainsLocally();
      }
      else if (this->ChainsChanged)
      {
        const std::vector<unsigned char> keptBefore = this->Kept;
        this->SimplifyChains();
        this->MarkChangedChainPatches(keptBefore);
      }
      this->Res.ChainPasses += this->ChainsChanged;
      this->ChainsChanged = false;
      for (Index p = 0; p < np; ++p)
      {
        if (this->Dirty[p])
        {
          if (this->LocalVerify)
          {
            this->Removed.insert(this->Removed.end(), this->PatchTris[p].begin(), this->PatchTris[p].end());
          }
          this->AddEdges(this->PatchTris[p], -1);
          this->PatchTris[p].clear();
        }
      }
      // Original patches first: their edges are fixed, greedy patches avoid them.
      touched.clear();
      Index done = 0, total = 0;
      for (Index p = 0; p < np; ++p)
      {
        total += this->Dirty[p];
      }
      for (int originals = 1; originals >= 0; --originals)
      {
        for (Index p = 0; p < np; ++p)
        {
          if (!this->Dirty[p] || this->PatchOriginal[p] != originals)
          {
            continue;
          }
          if (progress && !progress(double(++done) / double(std::max<Index>(total, 1))))
          {
            this->Res.Aborted = true;
            return false;
          }
          std::vector<Index>& tris = this->PatchTris[p];
          this->CutTriangles += G.PatchTriangleOffsets[p + 1] - G.PatchTriangleOffsets[p];
          if (this->LocalVerify)
          {
            this->CutSinceVerify.push_back(p);
          }
          if (originals)
          {
            this->Original(p, tris);
          }
          else if (!this->TriangulateGreedy(p, tris))
          {
            this->AddEdges(tris, -1);
            tris.clear();
            this->Escalate(p, touched);
          }
        }
      }
      std::fill(this->Dirty.begin(), this->Dirty.end(), 0);
      if (touched.empty())
      {
        this->Verify(touched);
      }
      if (touched.empty())
      {
        this->Removed.clear(); // every input triangle is proved against the output as it stands
        this->CutSinceVerify.clear();
        break;
      }
      for (Index p : touched)
      {
        this->Dirty[p] = 1;
      }
    }
    // Result in patch order.
    this->Res.Triangles.clear();
    this->Res.TrianglePatch.clear();
    this->Res.OriginalPatches = this->Res.RefinedPatches = 0;
    this->Res.FallbackPatchIds.clear();
    for (Index p = 0; p < np; ++p)
    {
      this->Res.Triangles.insert(this->Res.Triangles.end(), this->PatchTris[p].begin(), this->PatchTris[p].end());
      this->Res.TrianglePatch.insert(this->Res.TrianglePatch.end(), this->PatchTris[p].size() / 3, p);
      // A seam triangle kept as it is was never cut, so it is no fallback.
      // An empty patch (a split left nothing in it) keeps nothing either.
      const bool fellBack = this->PatchOriginal[p] && !G.IsSeamPatch(p) && !this->PatchTris[p].empty();
      this->Res.OriginalPatches += fellBack;
      if (fellBack)
      {
        this->Res.FallbackPatchIds.push_back(p);
      }
      this->Res.RefinedPatches += this->Refined[p] && !this->PatchOriginal[p];
    }
    this->Res.NumberOfPatches = np;
    this->Res.ErrorBound = this->Eps;
    return true;
  }

  // Every input triangle of a patch not yet failed (nor kept original) proved within epsilon of the
  // whole output.
  void VerifyAll(std::vector<unsigned char>& bad)
  {
    TriangleMesh output;
    output.Points = M.Points;
    for (Index p = 0; p < PP.NumberOfPatches(); ++p)
    {
      output.Triangles.insert(output.Triangles.end(), this->PatchTris[p].begin(), this->PatchTris[p].end());
    }
    TriangleBVH bvh(output);
    const std::vector<Index>& patchOf = PP.TrianglePatches();
    for (Index t = 0; t < M.NumberOfTriangles(); ++t)
    {
      const Index p = patchOf[t];
      if (bad[p] || this->PatchOriginal[p])
      {
        continue;
      }
      const Index* tri = M.Triangle(t);
      if (!TriangleWithinDistance(bvh, M.Point(tri[0]), M.Point(tri[1]), M.Point(tri[2]), this->Eps, Prm.SubdivisionDepth,
            &G.ProofPieces))
      {
        bad[p] = 1;
      }
    }
  }

  // The local verification of a split round. The output was proved (every input triangle within
  // epsilon of it) before the triangles in Removed were taken out; an input triangle farther than
  // epsilon from all of them kept its nearest output points, so only those whose box comes within
  // epsilon of a removed triangle's box are proved again, against the output within epsilon of
  // them (a subset: a proof against it holds for the whole output). Removed only grows until a
  // verification passes, so a triangle that failed is proved again after its patch's escalation.
  void VerifyNearRemoved(std::vector<unsigned char>& bad)
  {
    if (this->Removed.empty())
    {
      return;
    }
    Box3 region;
    std::vector<Box3> removedBoxes;
    for (size_t t = 0; t < this->Removed.size(); t += 3)
    {
      removedBoxes.push_back(TriangleBox(M, &this->Removed[t]).Grown(this->Eps));
      region.Add(removedBoxes.back());
    }
    // Past this many removed triangles the union box alone selects (more proofs, the same soundness).
    constexpr size_t MaximumBoxTests = 256;
    const std::vector<Index>& patchOf = PP.TrianglePatches();
    std::vector<Index> again;
    Box3 needed;
    for (Index t = 0; t < M.NumberOfTriangles(); ++t)
    {
      const Index p = patchOf[t];
      const Box3 box = TriangleBox(M, M.Triangle(t));
      bool near = !bad[p] && !this->PatchOriginal[p] && region.Meets(box);
      if (near && removedBoxes.size() <= MaximumBoxTests)
      {
        near = std::any_of(removedBoxes.begin(), removedBoxes.end(), [&](const Box3& r) { return r.Meets(box); });
      }
      if (near)
      {
        again.push_back(t);
        needed.Add(box);
      }
    }
    needed = needed.Grown(this->Eps);
    TriangleMesh output;
    output.Points = M.Points;
    for (Index p = 0; p < PP.NumberOfPatches() && !again.empty(); ++p)
    {
      const std::vector<Index>& tris = this->PatchTris[p];
      for (size_t t = 0; t < tris.size(); t += 3)
      {
        if (needed.Meets(TriangleBox(M, &tris[t])))
        {
          output.Triangles.insert(output.Triangles.end(), &tris[t], &tris[t] + 3);
        }
      }
    }
    this->Res.LocallyVerifiedTriangles += static_cast<long long>(again.size());
    if (output.Triangles.empty())
    {
      for (Index t : again)
      {
        bad[patchOf[t]] = 1;
      }
      return;
    }
    TriangleBVH bvh(output);
    for (Index t : again)
    {
      const Index* tri = M.Triangle(t);
      if (!bad[patchOf[t]] && !TriangleWithinDistance(bvh, M.Point(tri[0]), M.Point(tri[1]), M.Point(tri[2]), this->Eps,
                                 Prm.SubdivisionDepth, &G.ProofPieces))
      {
        bad[patchOf[t]] = 1;
      }
    }
  }

  // Stage 4: manifold edges and the original surface within epsilon of the output.
  void Verify(std::vector<Index>& touched)
  {
    const Index np = PP.NumberOfPatches();
    std::vector<unsigned char> bad(size_t(np), 0);
    std::vector<std::pair<std::uint64_t, int>> uses;
    if (this->LocalVerify)
    {
      // Only the edges of the patches cut since the last passed verification changed their use.
      for (Index p : this->CutSinceVerify)
      {
        const std::vector<Index>& tris = this->PatchTris[p];
        for (size_t t = 0; t < tris.size(); ++t)
        {
          const std::uint64_t key = EdgeKey(tris[t], tris[t - t % 3 + (t + 1) % 3]);
          const auto found = this->EdgeUse.find(key);
          if (found != this->EdgeUse.end() && found->second > 2)
          {
            uses.emplace_back(key, found->second);
          }
        }
      }
    }
    const auto checkEdge = [&](std::uint64_t key, int use)
    {
      const Index a = Index(key >> 32), b = Index(key & 0xffffffffu);
      // Between two non-manifold vertices only seam triangles, kept as they are, make an edge: an
      // input edge, non-manifold or not, as it was.
      const bool seamEdge = !G.SeamVertex.empty() && G.SeamVertex[a] && G.SeamVertex[b];
      if (use > 2 && !seamEdge)
      {
        for (Index p = 0; p < np; ++p)
        {
          const std::vector<Index>& tris = this->PatchTris[p];
          for (size_t t = 0; t < tris.size() && !bad[p]; t += 3)
          {
            for (int k = 0; k < 3; ++k)
            {
              if (EdgeKey(tris[t + k], tris[t + (k + 1) % 3]) == EdgeKey(a, b))
              {
                bad[p] = 1;
              }
            }
          }
        }
      }
    };
    if (this->LocalVerify)
    {
      for (const auto& [key, use] : uses)
      {
        checkEdge(key, use);
      }
    }
    else
    {
      for (const auto& [key, use] : this->EdgeUse)
      {
        checkEdge(key, use);
      }
    }
    if (this->LocalVerify)
    {
      this->VerifyNearRemoved(bad);
    }
    else
    {
      this->VerifyAll(bad);
    }
    for (Index p = 0; p < np; ++p)
    {
      if (bad[p])
      {
        this->Escalate(p, touched);
      }
    }
  }
};

// A patch that falls back to its original triangles is split in two and cut again (bounded:
// MaximumSplitRounds rounds more at most, each only when some patch fell back). With
// LocalSplitRounds the same worker goes on: a round cuts the pieces and their neighbours only.
bool GreedyCuts::CutWithSplitRounds(
  const GreedyCutsParameters& parameters, GreedyCutsResult& result, const ProgressFunction& progress)
{
  StageClock runClock("greedy cuts");
  char stage[200];
  long long splitRoundTriangles = 0, splitPatchTriangles = 0;
  result = GreedyCutsResult();
  std::unique_ptr<GreedyCuts::Worker> run;
  for (int round = 0;; ++round)
  {
    if (!run || !parameters.LocalSplitRounds)
    {
      result = GreedyCutsResult();
      run.reset(new GreedyCuts::Worker(*this, parameters, result));
    }
    if (!run->Execute(progress))
    {
      return false;
    }
    splitRoundTriangles += round > 0 ? run->CutTriangles : 0;
    // How much of the input a split round runs again for: the patches that fell back, their triangles.
    long long fallbackTriangles = 0;
    for (Index p : result.FallbackPatchIds)
    {
      fallbackTriangles += this->PatchTriangleOffsets[p + 1] - this->PatchTriangleOffsets[p];
    }
    if (vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE)
    {
      std::snprintf(stage, sizeof(stage),
        "cuts run %d at epsilon %g (%lld patches, %zu fell back with %lld triangles; %d rounds; %lld input triangles cut)",
        round, parameters.Epsilon, static_cast<long long>(result.NumberOfPatches), result.FallbackPatchIds.size(),
        fallbackTriangles, result.Rounds, run->CutTriangles);
      runClock.Lap(stage);
    }
    const Index patchesBefore = this->Patches.NumberOfPatches();
    if (parameters.LocalSplitRounds)
    {
      run->PrepareSplit(result.FallbackPatchIds);
    }
    const std::vector<Index> split = result.FallbackPatchIds;
    if (split.empty() || round >= MaximumSplitRounds || !this->SplitPatches(split))
    {
      result.SplitRounds = round;
      break;
    }
    splitPatchTriangles += fallbackTriangles;
    if (parameters.LocalSplitRounds)
    {
      run->ContinueAfterSplit(split, patchesBefore);
    }
  }
  result.SplitRoundTriangles = splitRoundTriangles;
  result.SplitPatchTriangles = splitPatchTriangles;
  return true;
}

bool GreedyCuts::Run(const GreedyCutsParameters& parameters, GreedyCutsResult& result, const ProgressFunction& progress)
{
  result = GreedyCutsResult();
  if (!this->Mesh || this->WasAborted || parameters.Epsilon <= 0)
  {
    // No tolerance: the input itself.
    if (this->Mesh)
    {
      result.Triangles = this->Mesh->Triangles;
      result.TrianglePatch = this->Patches.TrianglePatches();
      result.NumberOfPatches = this->Patches.NumberOfPatches();
    }
    return !this->WasAborted;
  }
  // Patches split by an earlier run are restored: a run's result depends on epsilon only.
  if (this->Patches.NumberOfPatches() != Index(this->InitialHeights.size()))
  {
    this->Patches.BuildFromLabels(*this->Mesh, this->Topology, this->InitialLabels, Index(this->InitialHeights.size()));
    this->HeightDirection = this->InitialHeights;
    if (!this->SeamPatch.empty())
    {
      this->SeamPatch.resize(this->InitialHeights.size());
    }
    this->BuildPatchData();
  }
  // Each level's cuts (their split rounds: whole runs again) and collapses, timed at TRACE verbosity
  // (`surfacelod --log-verbosity 9`): which of them grows with the input.
  StageClock clock("greedy cuts");
  char stage[200];
  // The cuts report the first 80 % of the progress when the final collapses follow.
  const double cutsShare = parameters.FinalCollapses ? 0.8 : 1.0;
  const ProgressFunction cutsProgress =
    progress ? ProgressFunction([&](double f) { return progress(cutsShare * f); }) : ProgressFunction();
  const ProgressFunction collapseProgress =
    progress ? ProgressFunction([&](double f) { return progress(cutsShare + (1 - cutsShare) * f); }) : ProgressFunction();
  if (!this->CutWithSplitRounds(parameters, result, cutsProgress))
  {
    return false;
  }
  std::snprintf(stage, sizeof(stage), "cuts at epsilon %g (%d split rounds, %d rounds in the last, %d chain passes)",
    parameters.Epsilon, result.SplitRounds, result.Rounds, result.ChainPasses);
  clock.Lap(stage);
  const bool collapsed = !parameters.FinalCollapses || this->CollapseFinal(parameters, result, collapseProgress);
  std::snprintf(stage, sizeof(stage), "final collapses at epsilon %g (%lld collapses)", parameters.Epsilon,
    result.FinalCollapses);
  clock.Lap(stage);
  return collapsed;
}

namespace
{
// The work counts of one call of the final collapses, at TRACE verbosity beside the stage clocks:
// whether a stage that grows faster than the input does more tries (passes, targets, proofs) or
// pays more per try. Counts of the whole call (its staged steps included); nothing is read when
// TRACE is off.
void LogCollapseWork(double epsilon, Index target, const ProvedCollapseStatistics& s, long long pieces,
  const GreedyCutsResult& result)
{
  if (vtkLogger::GetCurrentVerbosityCutoff() < vtkLogger::VERBOSITY_TRACE)
  {
    return;
  }
  vtkLogF(TRACE,
    "greedy cuts: collapses at epsilon %g (target %lld): %lld triangles left, %d passes, %lld tries, "
    "%lld collapses, %lld flips, refused %lld / %lld / %lld (topology, new triangles, relying input), "
    "%lld new-triangle proofs (%lld recalled), %lld input gatherings, %lld input triangles examined, "
    "%lld proof pieces%s",
    epsilon, static_cast<long long>(target), static_cast<long long>(result.Triangles.size() / 3), s.Rounds,
    s.Attempts, s.Collapses, s.Flips, s.Rejected[0], s.Rejected[1], s.Rejected[2], s.NewTriangleProofs,
    s.NewTrianglesRecalled, s.InputGatherings, s.InputTrianglesGathered, pieces,
    s.WorkBoundReached ? " (work bound reached)" : "");
}
}

bool GreedyCuts::CollapseFinal(const GreedyCutsParameters& parameters, GreedyCutsResult& result,
  const ProgressFunction& progress, Index target)
{
  ProvedCollapseParameters collapse;
  collapse.Epsilon = parameters.Epsilon;
  collapse.SubdivisionDepth = parameters.SubdivisionDepth;
  collapse.MinimumAngle = parameters.ShapedAngle;
  collapse.TargetTriangles = target;
  collapse.BorderCollapses = parameters.BorderCollapses;
  collapse.EarlySliverStep = parameters.EarlySliverStep;
  collapse.PassOrderBands = parameters.PassOrderBands;
  collapse.MaximumProofPieces = this->WorkLimit; // 0 (one plain run): their own bounds only
  collapse.LockedVertices = this->SeamVertex.empty() ? nullptr : this->SeamVertex.data();
  // A proof holds at every larger tolerance only: after a call at a larger one (the target
  // search's top level before its finer levels) the table holds answers this call cannot recall,
  // so it is emptied; a chain at rising tolerances keeps it. Past MaximumCarriedProofs too
  // (bounded memory: the answers are only a saving; the decisions are the same either way).
  if (this->CarriedProofs.Size() > MaximumCarriedProofs || parameters.Epsilon < this->CarriedEpsilon)
  {
    this->CarriedProofs.Clear();
  }
  this->CarriedEpsilon = parameters.Epsilon;
  collapse.CarriedProofs = parameters.CarryProofs && this->RisingTolerances ? &this->CarriedProofs : nullptr;
  collapse.CollapsesOnly = this->CollapseStepsOnly && target == 0;
  ProvedCollapseStatistics statistics;
  // Staged (CollapseStages): the lower stages take the collapses that move the surface least first.
  // Each is proved at Epsilon for the input, so the bound holds after each one.
  const int stages = target > 0 ? 0 : std::max(parameters.CollapseStages, 0);
  int done = 0; // each stage and the final collapses report an equal share of the progress
  const ProgressFunction share =
    progress ? ProgressFunction([&](double f) { return progress((done + f) / double(stages + 1)); }) : ProgressFunction();
  for (int k = stages; k > 0; --k, ++done)
  {
    ProvedCollapseParameters stage = collapse;
    stage.NewTriangleTolerance = std::ldexp(parameters.Epsilon, -k);
    stage.CollapsesOnly = true;
    if (!ProvedCollapses(*this->Mesh, this->Bvh, stage, result.Triangles, result.TrianglePatch, statistics, share,
          &this->ProofPieces))
    {
      result.Aborted = true;
      return false;
    }
    result.FinalCollapses += statistics.Collapses;
  }
  const long long piecesBefore = this->ProofPieces;
  const bool finished = ProvedCollapses(*this->Mesh, this->Bvh, collapse, result.Triangles, result.TrianglePatch,
    statistics, share, &this->ProofPieces);
  result.FinalCollapses += statistics.Collapses;
  result.FinalFlips += statistics.Flips;
  result.Aborted = !finished;
  LogCollapseWork(parameters.Epsilon, target, statistics, this->ProofPieces - piecesBefore, result);
  return finished;
}

// The finish of a chain in collapse-only steps: flips alone (the fatter-pair flips, then the sliver
// step's flips), each proved at the level's tolerance; the count stays.
bool GreedyCuts::FlipFinal(const GreedyCutsParameters& parameters, GreedyCutsResult& result,
  const ProgressFunction& progress)
{
  ProvedCollapseParameters flips;
  flips.Epsilon = parameters.Epsilon;
  flips.SubdivisionDepth = parameters.SubdivisionDepth;
  flips.MinimumAngle = parameters.ShapedAngle;
  flips.BorderCollapses = parameters.BorderCollapses;
  flips.LockedVertices = this->SeamVertex.empty() ? nullptr : this->SeamVertex.data();
  flips.FlipsOnly = true;
  ProvedCollapseStatistics statistics;
  const bool finished = ProvedCollapses(*this->Mesh, this->Bvh, flips, result.Triangles, result.TrianglePatch,
    statistics, progress, &this->ProofPieces);
  result.FinalFlips += statistics.Flips;
  result.Aborted = !finished;
  return finished;
}

// A level's start: its own cuts or the finer level, whichever has fewer triangles (the finer one is
// within its smaller epsilon, hence within this one). With the collapses, once a level's cuts lost
// to the finer level the coarser levels skip their cuts (they lost on every mesh measured, and the
// cuts are the costly part at small tolerances): a saving that changes no guarantee.
bool GreedyCuts::StartLevel(const GreedyCutsParameters& prm, const GreedyCutsResult* finer, bool collapses,
  GreedyCutsResult& level, const ProgressFunction& progress)
{
  // The cheap chain (LadderOwnRuns off) never runs a level's own cuts above the bottom.
  const bool skipCuts = collapses && finer && (finer->StartedFromFinerLevel || !prm.LadderOwnRuns);
  if (!skipCuts && !this->Run(prm, level, progress))
  {
    return false;
  }
  if (finer && (skipCuts || finer->Triangles.size() < level.Triangles.size()))
  {
    if (skipCuts)
    {
      level = *finer;
    }
    level.Triangles = finer->Triangles;
    level.TrianglePatch = finer->TrianglePatch;
    level.FinalCollapses = finer->FinalCollapses;
    level.FinalFlips = finer->FinalFlips;
    level.StartedFromFinerLevel = true;
  }
  level.ErrorBound = prm.Epsilon;
  return true;
}

bool GreedyCuts::RunLevels(const std::vector<double>& epsilons, const GreedyCutsParameters& base,
  std::vector<GreedyCutsResult>& results, const ProgressFunction& progress, const std::vector<bool>* freshRuns)
{
  std::vector<double> sorted = epsilons;
  std::sort(sorted.begin(), sorted.end());
  results.assign(sorted.size(), GreedyCutsResult());
  const ScopedFlag rising(this->RisingTolerances); // the levels' collapses recall each other's answers
  GreedyCutsParameters prm = base;
  prm.FinalCollapses = false;
  for (size_t i = 0; i < sorted.size(); ++i)
  {
    auto stage = [&](double from, double to) {
      return [&progress, &sorted, i, from, to](double f) {
        return progress ? progress((double(i) + from + (to - from) * f) / double(sorted.size())) : true;
      };
    };
    prm.Epsilon = sorted[i];
    if (i > 0 && this->WorkSpent())
    {
      // Past the work bound: the finer level, within its smaller epsilon (the count stays).
      results[i] = results[i - 1];
      results[i].ErrorBound = prm.Epsilon;
      results[i].StartedFromFinerLevel = true;
      continue;
    }
    const bool fresh = freshRuns && i < freshRuns->size() && (*freshRuns)[i];
    if (!this->NextLevel(prm, i > 0 ? &results[i - 1] : nullptr, base.FinalCollapses, fresh, results[i],
          stage(0.0, 0.8), stage(0.8, 1.0)))
    {
      return false;
    }
  }
  return true;
}

// One level from the finer one (StartLevel, then the collapses, which never add a triangle:
// count(level) <= count(finer)). With `fresh`, the level's own cuts with their collapses are run
// too and kept when they have fewer triangles (still within this level's epsilon).
bool GreedyCuts::NextLevel(const GreedyCutsParameters& prm, const GreedyCutsResult* finer, bool collapses, bool fresh,
  GreedyCutsResult& level, const ProgressFunction& startProgress, const ProgressFunction& collapseProgress)
{
  if (!this->StartLevel(prm, finer, collapses, level, startProgress))
  {
    return false;
  }
  if (prm.Epsilon <= 0 || !collapses)
  {
    return true;
  }
  if (!this->CollapseFinal(prm, level, collapseProgress))
  {
    return false;
  }
  if (fresh && finer && level.StartedFromFinerLevel && !this->WorkSpent())
  {
    GreedyCutsParameters own = prm;
    own.FinalCollapses = true;
    GreedyCutsResult alone;
    if (!this->Run(own, alone, collapseProgress))
    {
      return false;
    }
    if (alone.Triangles.size() < level.Triangles.size())
    {
      level = std::move(alone);
    }
  }
  return true;
}

bool GreedyCuts::IsFreshLevel(double relative)
{
  // 1, 2 and 5 times a power of ten: one level in two or three of the ladder.
  const double mantissa = relative / std::pow(10.0, std::floor(std::log10(relative) + 1e-9));
  return std::fabs(mantissa - 1) < 1e-6 || std::fabs(mantissa - 2) < 1e-6 || std::fabs(mantissa - 5) < 1e-6;
}

namespace
{
// The ladder's round values per decade (ratios 1.2 to 1.33).
constexpr double LadderSeries[] = { 1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0 };
}

double GreedyCuts::LadderFloor(double x)
{
  if (!(x > 0) || !std::isfinite(x))
  {
    return 0;
  }
  const int decade = int(std::floor(std::log10(x)));
  double best = 0;
  for (int d = decade - 1; d <= decade + 1; ++d) // either side: log10 may round across a decade
  {
    for (double s : LadderSeries)
    {
      const double v = s * std::pow(10.0, d);
      if (v <= x * (1 + 1e-12))
      {
        best = std::max(best, v);
      }
    }
  }
  return std::min(best, x); // a round value just above x by rounding is x itself
}

std::vector<double> GreedyCuts::ToleranceLadder(double bottom, double top)
{
  std::vector<double> ladder;
  const double last = LadderFloor(top), first = LadderFloor(bottom);
  if (last <= 0 || first <= 0 || first >= last)
  {
    if (last > 0)
    {
      ladder.push_back(last);
    }
    return ladder;
  }
  // Bounded: at most 10 values per decade between two finite positive numbers.
  for (int d = int(std::floor(std::log10(first))) - 1; ladder.empty() || ladder.back() < last; ++d)
  {
    for (double s : LadderSeries)
    {
      const double v = std::min(s * std::pow(10.0, d), last);
      if (v >= first * (1 - 1e-12) && (ladder.empty() || v > ladder.back()))
      {
        ladder.push_back(v);
      }
    }
  }
  return ladder;
}

bool GreedyCuts::RunMonotone(const GreedyCutsParameters& parameters, GreedyCutsResult& result,
  const ProgressFunction& progress)
{
  const double diagonal = this->Mesh ? this->Mesh->BoundingBoxDiagonal() : 0.0;
  std::vector<double> levels =
    diagonal > 0 && parameters.Epsilon > 0 ? ToleranceLadder(parameters.LadderBottom, parameters.Epsilon / diagonal) : std::vector<double>();
  if (levels.empty())
  {
    return this->Run(parameters, result, progress);
  }
  std::vector<bool> fresh;
  for (double& e : levels)
  {
    fresh.push_back(parameters.LadderOwnRuns && IsFreshLevel(e));
    e = std::min(e * diagonal, parameters.Epsilon);
  }
  std::vector<GreedyCutsResult> results;
  this->OpenWorkAccount(MaximumLadderPiecesPerTriangle);
  const bool stepsOnly = parameters.LadderCollapsesOnly && !parameters.LadderOwnRuns && parameters.FinalCollapses;
  bool finished = true;
  {
    const ScopedFlag collapseSteps(this->CollapseStepsOnly, stepsOnly);
    finished = this->RunLevels(levels, parameters, results, progress, &fresh);
  }
  this->SearchStoppedByWorkBound = this->WorkSpent();
  this->WorkLimit = 0;
  if (!finished)
  {
    return false;
  }
  result = std::move(results.back());
  if (stepsOnly)
  {
    // The chain's levels ran without flips: the level returned gets them now (not passed on, so
    // every epsilon still reads the same chain).
    GreedyCutsParameters last = parameters;
    last.Epsilon = result.ErrorBound;
    return this->FlipFinal(last, result, nullptr);
  }
  return true;
}

void GreedyCuts::OpenWorkAccount(long long piecesPerTriangle)
{
  this->WorkLimit = this->ProofPieces + std::max<long long>(1, piecesPerTriangle * this->Mesh->NumberOfTriangles());
}

bool GreedyCuts::WorkSpent() const
{
  return this->WorkLimit > 0 && this->ProofPieces > this->WorkLimit;
}

bool GreedyCuts::RunForTarget(Index target, const GreedyCutsParameters& base, double lo, double hi, int steps,
  GreedyCutsResult& result, const ProgressFunction& progress)
{
  this->SearchStoppedByWorkBound = false;
  if (!base.FinalCollapses || !this->Mesh || this->Mesh->BoundingBoxDiagonal() <= 0)
  {
    return this->SearchCutsForTarget(target, base, lo, hi, steps, result, progress);
  }
  return this->SearchCollapsedForTarget(target, base, hi, steps, result, progress);
}

bool GreedyCuts::SearchCollapsedForTarget(Index target, const GreedyCutsParameters& base, double hi, int steps,
  GreedyCutsResult& result, const ProgressFunction& progress)
{
  const double diagonal = this->Mesh->BoundingBoxDiagonal();
  const std::vector<double> ladder = ToleranceLadder(base.LadderBottom, hi / diagonal);
  auto count = [](const GreedyCutsResult& r) { return Index(r.Triangles.size() / 3); };
  GreedyCutsParameters prm = base;
  int evaluation = 0;
  const ProgressFunction stage = [&](double f) {
    return progress ? progress(0.8 * (evaluation + f) / double(steps + 1)) : true;
  };
  this->LevelsRun = 0;
  auto evaluate = [&](int level, GreedyCutsResult& r) {
    ++this->LevelsRun;
    prm.Epsilon = std::min(ladder[size_t(level)] * diagonal, hi);
    return this->Run(prm, r, stage);
  };
  // Search over the ladder's levels, each one run (cuts and collapses), from the top: `within`
  // (level `up`) has at most `target` triangles, `finer` (level `down`; -1: the input) more.
  this->OpenWorkAccount(MaximumLadderPiecesPerTriangle);
  int up = int(ladder.size()) - 1, down = -1;
  GreedyCutsResult within, finer;
  if (!evaluate(up, within))
  {
    return false;
  }
  // The count need not fall with the tolerance at the top (bunny00: the cuts at 0.1 of the diagonal
  // leave long fans whose proofs gather too much of the input, and the collapses stall above the
  // target that 0.01 reaches): a top over the target sends the search down the ladder (DescendBelowTop).
  // A top that removed (nearly) nothing does not go down: the rise comes from the stalls of a
  // top that moved the surface a lot, and where the largest tolerance proved (almost) no cut or
  // collapse the finer ones, whose proofs only reject more, are not expected to do better (the
  // corpus' valence-5000 cone: 10,000 -> 10,000, every patch kept original, no collapse; each
  // level tried is a whole run, 4-5 s there, and the proof pieces, 24 per input triangle, leave
  // the work account far from spent).
  const Index input = this->Mesh->NumberOfTriangles();
  if (count(within) > target && (input - count(within)) * DescentMinimumRemoved >= input)
  {
    if (!this->DescendBelowTop(target, evaluate, steps, evaluation, up, within))
    {
      return false;
    }
  }
  if (count(within) > target)
  {
    this->SearchStoppedByWorkBound = this->WorkSpent();
    result = std::move(within); // no level tried reaches the target: the bound wins
    this->WorkLimit = 0;
    return true;
  }
  // Each step tries the level where the count is predicted to reach the target (fandisk -t 1500:
  // 20 triangles at the top, 0.1 of the diagonal, predict the bottom level, within the target, so
  // the search ends after two runs instead of four), and bisects after a prediction that did not
  // halve the bracket (at most about twice the steps of a bisection). The bracket it ends with is
  // the bisection's whenever the counts fall with the levels (the same result).
  bool predict = true;
  while (up - down > 1 && ++evaluation <= steps && !this->WorkSpent())
  {
    const int span = up - down;
    const int middle = predict ? PredictedLevel(ladder, down, up, down < 0 ? input : count(finer), count(within), target)
                               : (up + down) / 2;
    GreedyCutsResult trial;
    if (!evaluate(middle, trial))
    {
      return false;
    }
    (count(trial) <= target ? up : down) = middle;
    (count(trial) <= target ? within : finer) = std::move(trial);
    predict = 2 * (up - down) <= span;
  }
  this->SearchStoppedByWorkBound = this->WorkSpent();
  if (down < 0)
  {
    finer.Triangles = this->Mesh->Triangles; // within every tolerance
    finer.TrianglePatch = this->Patches.TrianglePatches();
  }
  const double finerBound = down < 0 ? 0.0 : std::min(ladder[size_t(down)] * diagonal, hi);
  return this->CollapseToTarget(target, within, finer, finerBound, prm, progress, result);
}

int GreedyCuts::PredictedLevel(const std::vector<double>& ladder, int down, int up, Index countDown, Index countUp,
  Index target)
{
  const double logTarget = std::log(double(std::max<Index>(target, 1)));
  const double logUp = std::log(double(std::max<Index>(countUp, 1)));
  double logEpsilon = std::log(ladder[size_t(up)]) + logUp - logTarget; // count ~ 1 / epsilon
  const double logDown = std::log(double(std::max<Index>(countDown, 1)));
  if (down >= 0 && logDown > logUp)
  {
    const double t = (logDown - logTarget) / (logDown - logUp);
    logEpsilon = std::log(ladder[size_t(down)]) + t * (std::log(ladder[size_t(up)]) - std::log(ladder[size_t(down)]));
  }
  int level = down + 1;
  while (level < up - 1 && std::log(ladder[size_t(level)]) < logEpsilon)
  {
    ++level;
  }
  return level;
}

// A top level over the target: finer levels, halving the level index, until one is within the
// target (the bisection then runs below it). Charged to the search's steps and work account (a
// level starts only while neither is spent). It stops at the first finer level that does not
// lower the count (there the count falls with the tolerance again, and finer runs only cost
// more). `within` (level `up`) ends as the fewest triangles tried.
bool GreedyCuts::DescendBelowTop(Index target, const LevelRun& evaluate, int steps, int& evaluation, int& up,
  GreedyCutsResult& within)
{
  auto count = [](const GreedyCutsResult& r) { return Index(r.Triangles.size() / 3); };
  while (count(within) > target && up > 0 && ++evaluation <= steps && !this->WorkSpent())
  {
    const int level = up / 2;
    GreedyCutsResult trial;
    if (!evaluate(level, trial))
    {
      return false;
    }
    if (count(trial) >= count(within))
    {
      break;
    }
    within = std::move(trial);
    up = level;
  }
  return true;
}

// The finer start (more than `target` triangles, within `finerBound`: 0 for the input) collapsed
// until the target, at tolerances that double up to that of `within`: from within / 16 (or the
// finer bound) when the finer start is below it, so the cheapest collapses (those that move the
// surface least) are made first and the result carries the smallest tolerance at which it reached
// the target, not the whole of within's. Target or target - 1 triangles (a collapse removes one or
// two); `within` itself when the collapses get stuck (or their work bound stops them) above it.
bool GreedyCuts::CollapseToTarget(Index target, GreedyCutsResult& within, GreedyCutsResult& finer, double finerBound,
  GreedyCutsParameters prm, const ProgressFunction& progress, GreedyCutsResult& result)
{
  const ScopedFlag rising(this->RisingTolerances); // the stages below run at doubling tolerances
  std::vector<double> stages{ within.ErrorBound };
  while (stages.size() < size_t(CollapseStages) && 0.5 * stages.back() > finerBound)
  {
    stages.push_back(0.5 * stages.back());
  }
  std::reverse(stages.begin(), stages.end());
  const std::vector<Index> triangles = std::move(finer.Triangles), patches = std::move(finer.TrianglePatch);
  finer = within;
  finer.Triangles = triangles;
  finer.TrianglePatch = patches;
  finer.FinalCollapses = 0;
  finer.FinalFlips = 0;
  finer.StartedFromFinerLevel = true;
  // The final collapses' own allowance, shared out so that each stage may spend up to its share
  // and what the earlier ones left: a stage stopped by its share hands a valid start (within its
  // smaller tolerance) to the next, so the proofs at the smallest tolerances, the dearest ones,
  // cannot take the whole allowance.
  this->OpenWorkAccount(MaximumLadderPiecesPerTriangle);
  const long long start = this->ProofPieces, allowance = this->WorkLimit - start;
  auto allSpent = [&]() { return this->ProofPieces - start > allowance; };
  for (size_t i = 0; i < stages.size() && Index(finer.Triangles.size() / 3) > target && !allSpent(); ++i)
  {
    this->WorkLimit = start + allowance * static_cast<long long>(i + 1) / static_cast<long long>(stages.size());
    const ProgressFunction last = [&](double f) {
      return progress ? progress(0.8 + 0.2 * (double(i) + f) / double(stages.size())) : true;
    };
    prm.Epsilon = stages[i];
    if (!this->CollapseFinal(prm, finer, last, target))
    {
      return false;
    }
    finer.ErrorBound = stages[i]; // proved at this tolerance (and the start within a smaller one)
  }
  this->SearchStoppedByWorkBound = this->SearchStoppedByWorkBound || allSpent();
  this->WorkLimit = 0;
  result = Index(finer.Triangles.size() / 3) <= target ? std::move(finer) : std::move(within);
  return true;
}

bool GreedyCuts::SearchCutsForTarget(Index target, const GreedyCutsParameters& base, double lo, double hi, int steps,
  GreedyCutsResult& result, const ProgressFunction& progress)
{
  // The cuts alone (FinalCollapses off): their counts fall roughly with epsilon, not monotonically.
  GreedyCutsParameters prm = base;
  prm.Epsilon = hi;
  int evaluation = 0;
  this->SearchStoppedByWorkBound = false;
  const long long workStart = this->ProofPieces;
  const long long workBudget = MaximumProofPiecesPerTriangle * (this->Mesh ? this->Mesh->NumberOfTriangles() : 0);
  auto spent = [&]() {
    this->SearchStoppedByWorkBound = this->ProofPieces - workStart > workBudget;
    return this->SearchStoppedByWorkBound;
  };
  auto stage = [&](double f) {
    return progress ? progress((evaluation + f) / double(steps + 1)) : true;
  };
  if (!this->Run(prm, result, stage))
  {
    return false;
  }
  if (Index(result.Triangles.size() / 3) > target)
  {
    return true; // even the coarsest tolerance gives more triangles: its result
  }
  // Descend from hi by halving while the count stays within the target (large tolerances are the
  // fast runs), then bisect on log(epsilon) between the last two tolerances.
  GreedyCutsResult trial;
  double h = hi, l = hi;
  // The same triangles at three tolerances in a row: the result no longer depends on epsilon
  // there (a flat region, a patch at its coarsest), and smaller tolerances only cost more (the
  // proofs subdivide deeper): stop with the smallest one tried.
  int unchanged = 0;
  while (evaluation < steps && l > lo && !spent())
  {
    ++evaluation;
    l = std::max(lo, 0.5 * h);
    prm.Epsilon = l;
    if (!this->Run(prm, trial, stage))
    {
      return false;
    }
    if (Index(trial.Triangles.size() / 3) > target)
    {
      break;
    }
    unchanged = trial.Triangles == result.Triangles ? unchanged + 1 : 0;
    result = std::move(trial);
    trial = GreedyCutsResult();
    h = l;
    if (unchanged >= 2)
    {
      return true;
    }
  }
  if (l >= h)
  {
    return true;
  }
  while (evaluation < steps && !spent())
  {
    ++evaluation;
    const double mid = std::sqrt(l * h);
    prm.Epsilon = mid;
    if (!this->Run(prm, trial, stage))
    {
      return false;
    }
    if (Index(trial.Triangles.size() / 3) <= target)
    {
      result = std::move(trial);
      trial = GreedyCutsResult();
      h = mid;
    }
    else
    {
      l = mid;
    }
  }
  return true;
}
} // namespace slod
