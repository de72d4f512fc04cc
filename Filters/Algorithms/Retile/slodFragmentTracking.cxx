// SPDX-License-Identifier: BSD-3-Clause
#include "slodFragmentTracking.h"

#include "slodEditableMesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <limits>
#include <string>
#include <unordered_map>

namespace slod
{
namespace
{
using Vec2 = std::array<double, 2>;


double Orient(const Vec2& a, const Vec2& b, const Vec2& p)
{
  return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

// A point of the mesh being edited: weights over one to three of its vertices (one triangle's).
struct Support
{
  Index V[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
  double W[3] = { 0, 0, 0 };
  int N = 0;

  bool Uses(Index v) const { return std::find(this->V, this->V + this->N, v) != this->V + this->N; }
};

struct TrackedVertex
{
  Vec3 High;
  Support Where;
};

struct Fragment
{
  Index HighTriangle;
  std::vector<Index> Ring; // tracked vertices, oriented as the high triangle
};

// One local re-triangulation in the plane: a removal's hole (the removed vertex, its ring) or an
// edge flip's quad, its old and new triangles and the new edges inside it.
struct Hole
{
  Index Removed = InvalidIndex, Target = InvalidIndex; // removal r -> c; a flip has no removed vertex
  std::array<Index, 4> Quad{};                         // flip of edge (x, y) of triangles (x, y, q), (y, x, z)
  std::vector<Index> Ring;   // link of the removed vertex, in order
  bool Closed = true;        // false: the removed vertex is on a border (Ring runs border to border)
  std::vector<Index> Star;   // its triangles (edit ids)
  std::vector<Index> Kept;   // the star triangles that survive the collapse (edit ids)
  std::vector<std::array<Index, 3>> NewCorners; // per kept triangle: its corners after the collapse
  std::vector<std::array<Index, 2>> Chords; // the new edges inside the hole
};

class FragmentTracker
{
public:
  explicit FragmentTracker(const TriangleMesh& high)
    : Edit(high)
  {
    const Index nv = high.NumberOfPoints(), nt = high.NumberOfTriangles();
    this->Vertices.resize(size_t(nv));
    for (Index v = 0; v < nv; ++v)
    {
      this->Vertices[v].High = high.Point(v);
      this->Vertices[v].Where.V[0] = v;
      this->Vertices[v].Where.W[0] = 1.0;
      this->Vertices[v].Where.N = 1;
    }
    this->FragmentsOf.resize(size_t(nt));
    for (Index t = 0; t < nt; ++t)
    {
      const Index* tri = high.Triangle(t);
      this->Fragments.push_back({ t, { tri[0], tri[1], tri[2] } });
      this->FragmentsOf[t].push_back(t);
    }
    this->SlotOf.assign(size_t(nv), InvalidIndex);
    this->SlotStamp.assign(size_t(nv), 0);
  }

  // Replays one operation with its fragments: the half-edge collapse a -> b, or for a < 0 the flip
  // of edge (-1 - a, b). False (error set) when it cannot be.
  bool Apply(Index a, Index b, std::string& error)
  {
    ++this->Epoch;
    Hole& hole = this->Current;
    const bool flip = a < 0;
    if (!(flip ? this->GatherQuad(-1 - a, b, hole, error) : this->GatherHole(a, b, hole, error)) ||
      !this->LayOutStar(hole, error))
    {
      return false;
    }
    std::vector<Index> pieces;
    for (Index t : hole.Star)
    {
      for (Index f : this->FragmentsOf[t])
      {
        if (!this->FlattenFragment(f, error))
        {
          return false;
        }
        this->SplitByChords(f, hole, pieces);
      }
      this->FragmentsOf[t].clear();
    }
    this->Splits.clear();
    if (!this->AssignPieces(hole, pieces, error))
    {
      return false;
    }
    if (flip)
    {
      return this->Edit.FlipEdge(hole.Quad[0], hole.Quad[1]);
    }
    const Index pair[2] = { a, b };
    this->Edit.Collapse(pair, 2, b, this->Edit.Point(b));
    return true;
  }

  EditableMesh Edit;
  std::vector<TrackedVertex> Vertices;
  std::vector<Fragment> Fragments;
  std::vector<std::vector<Index>> FragmentsOf; // per edit triangle

private:
  // The star of r as an ordered ring; the triangles that survive and their corners after the collapse.
  bool GatherHole(Index r, Index c, Hole& hole, std::string& error)
  {
    const Index nv = this->Edit.NumberOfPoints();
    if (r < 0 || c < 0 || r >= nv || c >= nv || r == c || !this->Edit.IsVertexAlive(r) ||
      !this->Edit.IsVertexAlive(c) || this->Edit.EdgeTriangleCount(r, c) == 0)
    {
      error = "removal " + std::to_string(r) + " -> " + std::to_string(c) + " is not an edge of the mesh";
      return false;
    }
    CollapseOptions options;
    options.MinimumNormalDot = -1.0;
    const Index pair[2] = { r, c };
    if (this->Edit.CheckCollapse(pair, 2, this->Edit.Point(c), options) != CollapseStatus::Ok)
    {
      error = "removal " + std::to_string(r) + " -> " + std::to_string(c) + " would break the mesh";
      return false;
    }
    hole = Hole();
    hole.Removed = r;
    hole.Target = c;
    std::map<Index, Index> next, previous;
    this->Edit.ForEachTriangle(r, [&](Index t) {
      const Index* tri = this->Edit.Triangle(t);
      const int k = tri[0] == r ? 0 : (tri[1] == r ? 1 : 2);
      hole.Star.push_back(t);
      next[tri[(k + 1) % 3]] = tri[(k + 2) % 3];
      previous[tri[(k + 2) % 3]] = tri[(k + 1) % 3];
    });
    Index start = next.begin()->first;
    for (const auto& link : next)
    {
      if (previous.find(link.first) == previous.end())
      {
        start = link.first;
        hole.Closed = false;
      }
    }
    for (Index v = start; hole.Ring.size() <= hole.Star.size() + 1;)
    {
      hole.Ring.push_back(v);
      const auto it = next.find(v);
      if (it == next.end() || it->second == start)
      {
        break;
      }
      v = it->second;
    }
    if (hole.Ring.size() != hole.Star.size() + (hole.Closed ? 0 : 1) || next.size() != hole.Star.size())
    {
      error = "the star of vertex " + std::to_string(r) + " is not a disk";
      return false;
    }
    return this->NewTriangles(hole, error);
  }

  bool NewTriangles(Hole& hole, std::string& error)
  {
    const Index r = hole.Removed, c = hole.Target;
    const size_t n = hole.Ring.size();
    const size_t j = size_t(std::find(hole.Ring.begin(), hole.Ring.end(), c) - hole.Ring.begin());
    if (!hole.Closed && j != 0 && j + 1 != n)
    {
      error = "border vertex " + std::to_string(r) + " removed onto an inner neighbour";
      return false;
    }
    for (Index t : hole.Star)
    {
      const Index* tri = this->Edit.Triangle(t);
      if (tri[0] == c || tri[1] == c || tri[2] == c)
      {
        continue;
      }
      hole.Kept.push_back(t);
      std::array<Index, 3> corners{ tri[0], tri[1], tri[2] };
      std::replace(corners.begin(), corners.end(), r, c);
      hole.NewCorners.push_back(corners);
    }
    for (size_t i = 0; i < n; ++i)
    {
      const size_t gap = (i + n - j) % n; // steps from c along the ring
      const bool neighbour = hole.Closed ? (gap <= 1 || gap == n - 1) : (i + 1 == j || i == j || i == j + 1);
      const bool farEnd = !hole.Closed && (i == 0 || i + 1 == n); // the new border edge
      if (!neighbour && !farEnd)
      {
        hole.Chords.push_back({ c, hole.Ring[i] });
      }
    }
    return true;
  }

  // The two triangles of edge (x, y), their new corners after the flip and the new diagonal.
  bool GatherQuad(Index x, Index y, Hole& hole, std::string& error)
  {
    hole = Hole();
    const Index nv = this->Edit.NumberOfPoints();
    Index q = InvalidIndex, z = InvalidIndex;
    if (x >= 0 && y >= 0 && x < nv && y < nv && this->Edit.IsVertexAlive(x) && this->Edit.IsVertexAlive(y))
    {
      this->Edit.ForEachTriangle(x, [&](Index t) {
        const Index* tri = this->Edit.Triangle(t);
        for (int k = 0; k < 3; ++k)
        {
          if (tri[k] == x && tri[(k + 1) % 3] == y)
          {
            hole.Star.insert(hole.Star.begin(), t);
            q = tri[(k + 2) % 3];
          }
          else if (tri[k] == y && tri[(k + 1) % 3] == x)
          {
            hole.Star.push_back(t);
            z = tri[(k + 2) % 3];
          }
        }
      });
    }
    if (hole.Star.size() != 2 || q == InvalidIndex || z == InvalidIndex || q == z || this->Edit.EdgeTriangleCount(q, z) > 0)
    {
      error = "edge " + std::to_string(x) + " - " + std::to_string(y) + " cannot be flipped";
      return false;
    }
    hole.Quad = { x, y, q, z };
    hole.Kept = hole.Star;
    for (int k = 0; k < 2; ++k)
    {
      const Index* tri = this->Edit.Triangle(hole.Star[k]);
      std::array<Index, 3> corners{ tri[0], tri[1], tri[2] };
      std::replace(corners.begin(), corners.end(), k == 0 ? y : x, k == 0 ? z : q); // as EditableMesh::FlipEdge
      hole.NewCorners.push_back(corners);
    }
    hole.Chords.push_back({ q, z });
    return true;
  }

  Vec2& Slot(Index v)
  {
    if (this->SlotStamp[v] != this->Epoch)
    {
      this->SlotStamp[v] = this->Epoch;
      this->SlotOf[v] = static_cast<Index>(this->Plane.size());
      this->Plane.push_back({ 0, 0 });
    }
    return this->Plane[this->SlotOf[v]];
  }

  bool InLayout(Index v) const { return this->SlotStamp[v] == this->Epoch; }

  // The star in the plane: the polar map when the new fan is valid there, else the ring on a circle.
  bool LayOutStar(const Hole& hole, std::string& error)
  {
    for (int attempt = 0; attempt < 2; ++attempt)
    {
      this->Plane.clear();
      ++this->Epoch;
      if (hole.Removed == InvalidIndex)
      {
        this->PlaceQuad(hole, attempt == 1);
      }
      else
      {
        this->PlaceRing(hole, attempt == 1);
      }
      if (this->FanIsValid(hole))
      {
        return true;
      }
    }
    error = "the hole of vertex " + std::to_string(hole.Removed) + " cannot be laid out in the plane";
    return false;
  }

  void PlaceRing(const Hole& hole, bool convex)
  {
    const size_t n = hole.Ring.size();
    const Vec3 center = this->Edit.Point(hole.Removed);
    const size_t gaps = hole.Closed ? n : n - 1;
    std::vector<double> angle(gaps), radius(n);
    double total = 0, longest = 0;
    for (size_t i = 0; i < n; ++i)
    {
      radius[i] = Norm(this->Edit.Point(hole.Ring[i]) - center);
      longest = std::max(longest, radius[i]);
    }
    for (size_t i = 0; i < gaps; ++i)
    {
      const Vec3 a = this->Edit.Point(hole.Ring[i]) - center, b = this->Edit.Point(hole.Ring[(i + 1) % n]) - center;
      angle[i] = convex ? 1.0 : std::atan2(Norm(Cross(a, b)), Dot(a, b));
      total += angle[i];
    }
    const double turn = (hole.Closed ? 2 * Pi : Pi) / (total > 0 ? total : 1.0);
    this->Slot(hole.Removed) = { 0, 0 };
    double phi = 0;
    for (size_t i = 0; i < n; ++i)
    {
      const double rho = convex || !(longest > 0) ? 1.0 : radius[i] / longest;
      this->Slot(hole.Ring[i]) = { rho * std::cos(phi), rho * std::sin(phi) };
      phi += i < gaps ? angle[i] * turn : 0.0;
    }
  }

  // The quad unfolded along its diagonal (lengths kept), or a square.
  void PlaceQuad(const Hole& hole, bool convex)
  {
    const Index x = hole.Quad[0], y = hole.Quad[1], q = hole.Quad[2], z = hole.Quad[3];
    if (convex)
    {
      this->Slot(x) = { -1, 0 };
      this->Slot(y) = { 1, 0 };
      this->Slot(q) = { 0, 1 };
      this->Slot(z) = { 0, -1 };
      return;
    }
    const Vec3 origin = this->Edit.Point(x), axis = this->Edit.Point(y) - origin;
    const double length = Norm(axis);
    auto unfold = [&](Index v, double sign) {
      const Vec3 d = this->Edit.Point(v) - origin;
      const double along = Dot(d, axis) / (length * length);
      return Vec2{ along, sign * Norm(Cross(axis, d)) / (length * length) };
    };
    this->Slot(x) = { 0, 0 };
    this->Slot(y) = { 1, 0 };
    this->Slot(q) = unfold(q, 1.0);
    this->Slot(z) = unfold(z, -1.0);
  }

  // Every old and new triangle of the hole positively oriented in the plane.
  bool FanIsValid(const Hole& hole)
  {
    const double minimum = 1e-12;
    for (Index t : hole.Star)
    {
      const Index* tri = this->Edit.Triangle(t);
      if (!(Orient(this->Slot(tri[0]), this->Slot(tri[1]), this->Slot(tri[2])) > minimum))
      {
        return false;
      }
    }
    for (const auto& corners : hole.NewCorners)
    {
      if (!(Orient(this->Slot(corners[0]), this->Slot(corners[1]), this->Slot(corners[2])) > minimum))
      {
        return false;
      }
    }
    return true;
  }

  // The plane position of every vertex of fragment f (from its weights over the star's vertices).
  bool FlattenFragment(Index f, std::string& error)
  {
    for (Index v : this->Fragments[f].Ring)
    {
      if (this->VertexStamp.size() <= size_t(v))
      {
        this->VertexStamp.resize(this->Vertices.size(), 0);
        this->VertexPlane.resize(this->Vertices.size());
      }
      if (this->VertexStamp[v] == this->Epoch)
      {
        continue;
      }
      const Support& s = this->Vertices[v].Where;
      Vec2 p{ 0, 0 };
      for (int k = 0; k < s.N; ++k)
      {
        if (!this->InLayout(s.V[k]))
        {
          error = "a fragment vertex lies outside the star of the vertex removed";
          return false;
        }
        const Vec2& q = this->Plane[this->SlotOf[s.V[k]]];
        p[0] += s.W[k] * q[0];
        p[1] += s.W[k] * q[1];
      }
      this->VertexStamp[v] = this->Epoch;
      this->VertexPlane[v] = p;
    }
    return true;
  }

  // Side of tracked vertex v of the line from a to b: 0 when v is a point of that edge by its
  // weights, else the sign of its plane position (within rounding).
  int Side(Index v, Index a, Index b) const
  {
    const Support& s = this->Vertices[v].Where;
    bool onEdge = s.N > 0; // vertices made by this removal have no weights yet
    for (int k = 0; k < s.N; ++k)
    {
      onEdge = onEdge && (s.V[k] == a || s.V[k] == b);
    }
    if (onEdge)
    {
      return 0;
    }
    const double d = Orient(this->Plane[this->SlotOf[a]], this->Plane[this->SlotOf[b]], this->VertexPlane[v]);
    return d > 1e-13 ? 1 : (d < -1e-13 ? -1 : 0);
  }

  // The vertex where edge (p, q) of a fragment crosses the chord (c, b): one per edge and chord.
  Index Crossing(Index p, Index q, Index c, Index b)
  {
    if (p > q)
    {
      std::swap(p, q);
    }
    const auto key = std::make_tuple(p, q, c, b);
    const auto found = this->Splits.find(key);
    if (found != this->Splits.end())
    {
      return found->second;
    }
    const Vec2 &pp = this->VertexPlane[p], &qp = this->VertexPlane[q];
    const Vec2 &a = this->Plane[this->SlotOf[c]], &e = this->Plane[this->SlotOf[b]];
    const double dp = Orient(a, e, pp), dq = Orient(a, e, qp);
    const double s = dp / (dp - dq);
    TrackedVertex x;
    x.High = this->Vertices[p].High + s * (this->Vertices[q].High - this->Vertices[p].High);
    const Index id = static_cast<Index>(this->Vertices.size());
    const Vec2 plane{ pp[0] + s * (qp[0] - pp[0]), pp[1] + s * (qp[1] - pp[1]) };
    this->Vertices.push_back(x);
    this->VertexStamp.resize(this->Vertices.size(), 0);
    this->VertexPlane.resize(this->Vertices.size());
    this->VertexStamp[id] = this->Epoch;
    this->VertexPlane[id] = plane;
    this->Splits.emplace(key, id);
    return id;
  }

  // Splits fragment f (and its pieces) by every chord of the hole; appends the pieces' fragment ids.
  void SplitByChords(Index f, const Hole& hole, std::vector<Index>& pieces)
  {
    const size_t first = pieces.size();
    pieces.push_back(f);
    for (const auto& chord : hole.Chords)
    {
      const size_t count = pieces.size();
      for (size_t i = first; i < count; ++i)
      {
        this->SplitPiece(pieces[i], chord[0], chord[1], pieces);
      }
    }
  }

  void SplitPiece(Index f, Index c, Index b, std::vector<Index>& pieces)
  {
    const std::vector<Index> ring = this->Fragments[f].Ring;
    const size_t m = ring.size();
    std::vector<int> side(m);
    bool positive = false, negative = false;
    for (size_t i = 0; i < m; ++i)
    {
      side[i] = this->Side(ring[i], c, b);
      positive = positive || side[i] > 0;
      negative = negative || side[i] < 0;
    }
    if (!positive || !negative || !this->CrossesChordSegment(ring, side, c, b))
    {
      return;
    }
    std::vector<Index> left, right;
    for (size_t i = 0; i < m; ++i)
    {
      const size_t j = (i + 1) % m;
      if (side[i] >= 0)
      {
        left.push_back(ring[i]);
      }
      if (side[i] <= 0)
      {
        right.push_back(ring[i]);
      }
      if (side[i] * side[j] < 0)
      {
        const Index x = this->Crossing(ring[i], ring[j], c, b);
        left.push_back(x);
        right.push_back(x);
      }
    }
    this->Fragments[f].Ring.swap(left);
    pieces.push_back(static_cast<Index>(this->Fragments.size()));
    this->Fragments.push_back({ this->Fragments[f].HighTriangle, std::move(right) });
  }

  // Whether the piece crosses the chord itself, not its line beyond c or b (the line leaves the
  // hole there: a split would leave a T-junction with the fragment across the hole's boundary).
  bool CrossesChordSegment(const std::vector<Index>& ring, const std::vector<int>& side, Index c, Index b) const
  {
    const Vec2 &a = this->Plane[this->SlotOf[c]], &e = this->Plane[this->SlotOf[b]];
    const Vec2 ae{ e[0] - a[0], e[1] - a[1] };
    const double length2 = ae[0] * ae[0] + ae[1] * ae[1];
    const size_t m = ring.size();
    for (size_t i = 0; i < m; ++i)
    {
      const size_t j = (i + 1) % m;
      if (side[i] * side[j] >= 0)
      {
        continue;
      }
      const Vec2 &p = this->VertexPlane[ring[i]], &q = this->VertexPlane[ring[j]];
      const double dp = Orient(a, e, p), dq = Orient(a, e, q), s = dp / (dp - dq);
      const Vec2 x{ p[0] + s * (q[0] - p[0]) - a[0], p[1] + s * (q[1] - p[1]) - a[1] };
      const double u = (x[0] * ae[0] + x[1] * ae[1]) / length2;
      if (u < -1e-9 || u > 1 + 1e-9)
      {
        return false;
      }
    }
    return true;
  }

  // Barycentric coordinates of p in the new triangle k of the hole.
  void NewBarycentric(const Hole& hole, size_t k, const Vec2& p, double w[3])
  {
    const auto& corners = hole.NewCorners[k];
    const Vec2 &a = this->Plane[this->SlotOf[corners[0]]], &b = this->Plane[this->SlotOf[corners[1]]],
               &c = this->Plane[this->SlotOf[corners[2]]];
    const double area = Orient(a, b, c);
    w[0] = Orient(b, c, p) / area;
    w[1] = Orient(c, a, p) / area;
    w[2] = Orient(a, b, p) / area;
  }

  // Each piece into the new triangle holding its centroid; then every vertex that depended on the
  // removed vertex gets weights over the new triangles' corners, restricted to the corners common
  // to every new triangle it is a vertex of (consistent on a chord).
  bool AssignPieces(const Hole& hole, const std::vector<Index>& pieces, std::string& error)
  {
    if (hole.NewCorners.empty())
    {
      error = "the removal of vertex " + std::to_string(hole.Removed) + " leaves no triangle";
      return false;
    }
    std::unordered_map<Index, std::vector<size_t>> triangles; // vertex -> new triangles it is in
    for (Index f : pieces)
    {
      Vec2 centroid{ 0, 0 };
      const std::vector<Index>& ring = this->Fragments[f].Ring;
      for (Index v : ring)
      {
        centroid[0] += this->VertexPlane[v][0] / double(ring.size());
        centroid[1] += this->VertexPlane[v][1] / double(ring.size());
      }
      size_t best = 0;
      double bestWeight = -std::numeric_limits<double>::max();
      for (size_t k = 0; k < hole.NewCorners.size(); ++k)
      {
        double w[3];
        this->NewBarycentric(hole, k, centroid, w);
        const double smallest = std::min({ w[0], w[1], w[2] });
        if (smallest > bestWeight)
        {
          bestWeight = smallest;
          best = k;
        }
      }
      this->FragmentsOf[hole.Kept[best]].push_back(f);
      for (Index v : ring)
      {
        if (!this->InOneNewTriangle(hole, this->Vertices[v].Where))
        {
          auto& list = triangles[v];
          if (std::find(list.begin(), list.end(), best) == list.end())
          {
            list.push_back(best);
          }
        }
      }
    }
    for (const auto& entry : triangles)
    {
      this->Relocate(hole, entry.first, entry.second);
    }
    return true;
  }

  // Whether a location is already a point of one new triangle (a corner, or on the hole's boundary).
  bool InOneNewTriangle(const Hole& hole, const Support& s) const
  {
    for (const auto& corners : hole.NewCorners)
    {
      bool inside = s.N > 0;
      for (int k = 0; k < s.N; ++k)
      {
        inside = inside && std::find(corners.begin(), corners.end(), s.V[k]) != corners.end();
      }
      if (inside)
      {
        return true;
      }
    }
    return false;
  }

  void Relocate(const Hole& hole, Index v, const std::vector<size_t>& in)
  {
    double w[3];
    this->NewBarycentric(hole, in.front(), this->VertexPlane[v], w);
    const auto& corners = hole.NewCorners[in.front()];
    Support s;
    double sum = 0;
    for (int k = 0; k < 3; ++k)
    {
      bool common = true;
      for (size_t t : in)
      {
        const auto& other = hole.NewCorners[t];
        common = common && std::find(other.begin(), other.end(), corners[k]) != other.end();
      }
      const double weight = common && w[k] > 1e-12 ? w[k] : 0.0;
      if (weight > 0)
      {
        s.V[s.N] = corners[k];
        s.W[s.N++] = weight;
        sum += weight;
      }
    }
    if (!(sum > 0))
    {
      s = Support();
      s.V[0] = corners[0];
      s.W[0] = sum = 1.0;
      s.N = 1;
    }
    for (int k = 0; k < s.N; ++k)
    {
      s.W[k] /= sum;
    }
    this->Vertices[v].Where = s;
  }

  Hole Current;
  std::uint64_t Epoch = 0;
  std::vector<Vec2> Plane;            // layout positions of the star's mesh vertices
  std::vector<Index> SlotOf;          // mesh vertex -> index into Plane (valid when SlotStamp == Epoch)
  std::vector<std::uint64_t> SlotStamp;
  std::vector<std::uint64_t> VertexStamp; // tracked vertex: VertexPlane valid when == Epoch
  std::vector<Vec2> VertexPlane;
  std::map<std::tuple<Index, Index, Index, Index>, Index> Splits;
};
// Whether m lies on the segment ab, strictly between its ends (a diagonal there leaves a T-junction).
bool OnSegment(const Vec3& m, const Vec3& a, const Vec3& b)
{
  const Vec3 ab = b - a;
  const double length2 = Dot(ab, ab);
  const double t = length2 > 0 ? Dot(m - a, ab) / length2 : -1.0;
  return t > 0 && t < 1 && Norm(m - (a + t * ab)) < 1e-9 * std::sqrt(length2);
}

// The replayed mesh against the low level: each live vertex at the position of one low vertex,
// each live triangle one low triangle (lowTriangleOf, per edit triangle).
bool MatchReplay(const EditableMesh& edit, const TriangleMesh& low, std::vector<Index>& lowTriangleOf, std::string& error)
{
  std::map<std::array<double, 3>, Index> lowVertexAt;
  for (Index v = 0; v < low.NumberOfPoints(); ++v)
  {
    const Vec3 p = low.Point(v);
    lowVertexAt.emplace(std::array<double, 3>{ p[0], p[1], p[2] }, v);
  }
  auto canonical = [](std::array<Index, 3> t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  std::map<std::array<Index, 3>, Index> lowTriangleAt;
  for (Index t = 0; t < low.NumberOfTriangles(); ++t)
  {
    const Index* tri = low.Triangle(t);
    lowTriangleAt.emplace(canonical({ tri[0], tri[1], tri[2] }), t);
  }
  lowTriangleOf.assign(size_t(edit.NumberOfTriangles()), InvalidIndex);
  std::vector<char> used(size_t(low.NumberOfTriangles()), 0);
  Index live = 0;
  for (Index t = 0; t < edit.NumberOfTriangles(); ++t)
  {
    if (!edit.IsTriangleAlive(t))
    {
      continue;
    }
    ++live;
    std::array<Index, 3> mapped{};
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 p = edit.Point(edit.Triangle(t)[k]);
      const auto it = lowVertexAt.find({ p[0], p[1], p[2] });
      mapped[k] = it == lowVertexAt.end() ? InvalidIndex : it->second;
    }
    const auto it = lowTriangleAt.find(canonical(mapped));
    if (it == lowTriangleAt.end() || used[it->second])
    {
      error = "the removals do not give the low-detail level (a triangle of the replay is not one of its triangles)";
      return false;
    }
    used[it->second] = 1;
    lowTriangleOf[t] = it->second;
  }
  if (live != low.NumberOfTriangles())
  {
    error = "the removals give " + std::to_string(live) + " triangles, the low-detail level has " +
      std::to_string(low.NumberOfTriangles());
    return false;
  }
  return true;
}

// The fragments as the result: end positions of every tracked vertex, each fragment triangulated.
void EmitFragments(const TriangleMesh& high, const FragmentTracker& tracker, const std::vector<Index>& lowTriangleOf,
  LevelInterpolation& result)
{
  const EditableMesh& edit = tracker.Edit;
  const size_t nv = tracker.Vertices.size();
  result.LowPositions.resize(3 * nv);
  result.HighPositions.resize(3 * nv);
  for (size_t v = 0; v < nv; ++v)
  {
    const TrackedVertex& x = tracker.Vertices[v];
    Vec3 low{ 0, 0, 0 };
    for (int k = 0; k < x.Where.N; ++k)
    {
      low = low + x.Where.W[k] * edit.Point(x.Where.V[k]);
    }
    std::copy(low.begin(), low.end(), &result.LowPositions[3 * v]);
    std::copy(x.High.begin(), x.High.end(), &result.HighPositions[3 * v]);
  }
  for (Index v = 0; v < edit.NumberOfPoints(); ++v)
  {
    result.SharedVertices += edit.IsVertexAlive(v) ? 1 : 0;
  }
  result.FlattenedVertices = high.NumberOfPoints() - result.SharedVertices;
  result.Crossings = static_cast<Index>(nv) - high.NumberOfPoints();
  for (Index t = 0; t < edit.NumberOfTriangles(); ++t)
  {
    if (!edit.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* corners = edit.Triangle(t);
    for (Index f : tracker.FragmentsOf[t])
    {
      const Fragment& fragment = tracker.Fragments[f];
      bool inside = true;
      for (Index v : fragment.Ring)
      {
        const Support& s = tracker.Vertices[v].Where;
        for (int k = 0; k < s.N; ++k)
        {
          inside = inside && (s.V[k] == corners[0] || s.V[k] == corners[1] || s.V[k] == corners[2]);
        }
      }
      result.InconsistentFragments += inside ? 0 : 1;
      const Index* tri = high.Triangle(fragment.HighTriangle);
      const Vec3 normal = TriangleNormal(high.Point(tri[0]), high.Point(tri[1]), high.Point(tri[2]));
      // No diagonal through another vertex of the fragment (a T-junction).
      auto throughNoVertex = [&](Index p, Index s) {
        const Vec3 a = tracker.Vertices[p].High, b = tracker.Vertices[s].High;
        return std::none_of(fragment.Ring.begin(), fragment.Ring.end(),
          [&](Index m) { return m != p && m != s && OnSegment(tracker.Vertices[m].High, a, b); });
      };
      ClipFragmentEars(fragment.Ring, normal, throughNoVertex, fragment.HighTriangle,
        inside ? lowTriangleOf[t] : InvalidIndex, result.Fragments++, result);
    }
  }
}
} // namespace

void TrackLevels(const TriangleMesh& high, const TriangleMesh& low, const std::vector<Index>& removals,
  LevelInterpolation& result, const ProgressFunction& progress)
{
  result = LevelInterpolation();
  if (high.NumberOfTriangles() == 0 || low.NumberOfTriangles() == 0)
  {
    result.Error = "both levels need triangles";
    return;
  }
  if (removals.size() % 2 != 0)
  {
    result.Error = "the removal records are not pairs of the high-detail level's vertices";
    return;
  }
  // The replay is most of the work: 90% of the progress, a report every ProgressStride records.
  constexpr size_t ProgressStride = 512;
  auto proceed = [&](double fraction) {
    result.Aborted = progress && !progress(fraction);
    return !result.Aborted;
  };
  FragmentTracker tracker(high);
  for (size_t i = 0; i < removals.size(); i += 2)
  {
    if ((i % ProgressStride == 0 && !proceed(0.9 * double(i) / double(removals.size()))) ||
      !tracker.Apply(removals[i], removals[i + 1], result.Error))
    {
      return;
    }
  }
  std::vector<Index> lowTriangleOf;
  if (!proceed(0.9) || !MatchReplay(tracker.Edit, low, lowTriangleOf, result.Error))
  {
    return;
  }
  EmitFragments(high, tracker, lowTriangleOf, result);
  result.Valid = proceed(1.0);
}
} // namespace slod
