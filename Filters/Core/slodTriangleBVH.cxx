// SPDX-License-Identifier: BSD-3-Clause
#include "slodTriangleBVH.h"

#include "slodHugePages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>

#include "vtkSMPTools.h"

namespace slod
{
namespace
{
constexpr double Infinity = std::numeric_limits<double>::infinity();

// Triangles whose sin(angle)^2 at vertex a is below this are treated as needles: their face
// projection is numerically unreliable, so the edges are checked as well.
constexpr double NeedleSin2 = 1e-8;

inline double Dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Closest point of segment [a, b] to p (a point when a == b); returns the squared distance.
inline double ClosestOnSegment(const double* p, const double* a, const double* b, double* out)
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  const double len2 = Dot3(ab, ab);
  double t = len2 > 0 ? Dot3(ap, ab) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  double d2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    out[k] = a[k] + t * ab[k];
    const double d = p[k] - out[k];
    d2 += d * d;
  }
  return d2;
}

inline double Distance2(const double* p, const double* q)
{
  const double d[3] = { p[0] - q[0], p[1] - q[1], p[2] - q[2] };
  return Dot3(d, d);
}

// Closest point of triangle (a,b,c) to p by Voronoi-region tests (Ericson, Real-Time Collision
// Detection 5.1.5). Every division is guarded and barycentrics are clamped, so the answer is always
// a point of the triangle even when the region tests are fooled by rounding.
inline void ClosestByRegions(const double* p, const double* a, const double* b, const double* c, double* out)
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ac[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  const double d1 = Dot3(ab, ap), d2 = Dot3(ac, ap);
  auto setBary = [&](double v, double w) {
    for (int k = 0; k < 3; ++k)
    {
      out[k] = a[k] + v * ab[k] + w * ac[k];
    }
  };
  if (d1 <= 0 && d2 <= 0)
  {
    setBary(0, 0); // vertex a
    return;
  }
  const double bp[3] = { p[0] - b[0], p[1] - b[1], p[2] - b[2] };
  const double d3 = Dot3(ab, bp), d4 = Dot3(ac, bp);
  if (d3 >= 0 && d4 <= d3)
  {
    setBary(1, 0); // vertex b
    return;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
  {
    const double den = d1 - d3;
    setBary(den > 0 ? std::min(1.0, d1 / den) : 0.0, 0); // edge ab
    return;
  }
  const double cp[3] = { p[0] - c[0], p[1] - c[1], p[2] - c[2] };
  const double d5 = Dot3(ab, cp), d6 = Dot3(ac, cp);
  if (d6 >= 0 && d5 <= d6)
  {
    setBary(0, 1); // vertex c
    return;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
  {
    const double den = d2 - d6;
    setBary(0, den > 0 ? std::min(1.0, d2 / den) : 0.0); // edge ac
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  const double e43 = d4 - d3, e56 = d5 - d6;
  if (va <= 0 && e43 >= 0 && e56 >= 0)
  {
    const double den = e43 + e56;
    const double w = den > 0 ? std::min(1.0, e43 / den) : 0.0; // edge bc
    setBary(1 - w, w);
    return;
  }
  // Face: clamp into the triangle (va, vb, vc > 0 in exact arithmetic here).
  const double den = std::max(va, 0.0) + std::max(vb, 0.0) + std::max(vc, 0.0);
  if (!(den > 0))
  {
    setBary(0, 0);
    return;
  }
  const double v = std::max(vb, 0.0) / den, w = std::max(vc, 0.0) / den;
  setBary(v, w);
}

// Exact closest point with the needle / zero-area fallback; returns the squared distance.
inline double ClosestOnTriangle(const double* p, const double* a, const double* b, const double* c, double* out)
{
  ClosestByRegions(p, a, b, c, out);
  double best = Distance2(p, out);
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ac[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double n[3] = { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0] };
  // The region answer is a point of the triangle, so it can only overestimate; on needles the
  // edges (exact segment projections) bound the error by the needle's width.
  if (Dot3(n, n) <= NeedleSin2 * Dot3(ab, ab) * Dot3(ac, ac))
  {
    const double* edges[3][2] = { { a, b }, { b, c }, { c, a } };
    for (const auto& e : edges)
    {
      double q[3];
      const double d2 = ClosestOnSegment(p, e[0], e[1], q);
      if (d2 < best)
      {
        best = d2;
        out[0] = q[0];
        out[1] = q[1];
        out[2] = q[2];
      }
    }
  }
  return best;
}

// Float rounding towards -inf / +inf, so float boxes contain the double triangles.
inline float RoundDown(double x)
{
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x)
  {
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  }
  return f;
}
inline float RoundUp(double x)
{
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x)
  {
    f = std::nextafter(f, std::numeric_limits<float>::infinity());
  }
  return f;
}

inline double BoxDistance2(const float* b, const double* q)
{
  double d2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    const double lo = b[2 * k], hi = b[2 * k + 1];
    const double d = q[k] < lo ? lo - q[k] : (q[k] > hi ? q[k] - hi : 0.0);
    d2 += d * d;
  }
  return d2;
}

struct Box
{
  float B[6] = { std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
    std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
    -std::numeric_limits<float>::max() };
  void Grow(const float* b)
  {
    for (int k = 0; k < 3; ++k)
    {
      this->B[2 * k] = std::min(this->B[2 * k], b[2 * k]);
      this->B[2 * k + 1] = std::max(this->B[2 * k + 1], b[2 * k + 1]);
    }
  }
  bool Valid() const { return this->B[0] <= this->B[1]; }
  double HalfArea() const
  {
    if (!this->Valid())
    {
      return 0;
    }
    const double dx = double(this->B[1]) - this->B[0], dy = double(this->B[3]) - this->B[2],
                 dz = double(this->B[5]) - this->B[4];
    return dx * dy + dy * dz + dz * dx;
  }
};

// Depth <= 63 Morton bits + 31 halvings of identical codes: the traversal stack cannot overflow.
constexpr int MaxStack = 160;

// Extent along axis k of the triangle whose corners are `corners[0..2]`.
inline void TriangleExtent(const double* const corners[3], int k, double& lo, double& hi)
{
  lo = Infinity;
  hi = -Infinity;
  for (int j = 0; j < 3; ++j)
  {
    lo = std::min(lo, corners[j][k]);
    hi = std::max(hi, corners[j][k]);
  }
}

// The centre of triangle t's box, computed on demand: an array of them (and of the boxes) for
// every triangle cost more in page faults than the arithmetic (MRI, 2.1M triangles).
inline void TriangleBoxCentre(const TriangleMesh& mesh, Index t, double* centre)
{
  const Index* tri = mesh.Triangle(t);
  const double* const corners[3] = { &mesh.Points[3 * size_t(tri[0])], &mesh.Points[3 * size_t(tri[1])],
    &mesh.Points[3 * size_t(tri[2])] };
  for (int k = 0; k < 3; ++k)
  {
    double lo, hi;
    TriangleExtent(corners, k, lo, hi);
    centre[k] = 0.5 * (lo + hi);
  }
}

// Grows `box` by the box (float, rounded outwards) of the triangle of 9 coordinates `t`.
inline void GrowByTriangle(const double* t, Box& box)
{
  const double* const corners[3] = { t, t + 3, t + 6 };
  float b[6];
  for (int k = 0; k < 3; ++k)
  {
    double lo, hi;
    TriangleExtent(corners, k, lo, hi);
    b[2 * k] = RoundDown(lo);
    b[2 * k + 1] = RoundUp(hi);
  }
  box.Grow(b);
}

// The tree's nodes over the sorted entries (children after their parent); returns the depth.
int BuildHierarchy(const std::vector<MortonEntry>& entries, std::vector<TriangleBVH::Node>& nodes)
{
  const Index nt = static_cast<Index>(entries.size());
  int depth = 0;
  ReserveOnHugePages(nodes, size_t(nt) + 16);
  nodes.push_back(TriangleBVH::Node{});
  struct Task
  {
    Index NodeIndex, Begin, End;
    int Depth;
  };
  std::vector<Task> tasks;
  tasks.push_back({ 0, 0, nt, 1 });
  while (!tasks.empty())
  {
    const Task task = tasks.back();
    tasks.pop_back();
    depth = std::max(depth, task.Depth);
    TriangleBVH::Node& node = nodes[size_t(task.NodeIndex)];
    const Index count = task.End - task.Begin;
    if (count <= TriangleBVH::LeafSize)
    {
      node.First = task.Begin;
      node.Count = count;
      continue;
    }
    const std::uint64_t c0 = entries[size_t(task.Begin)].Code, c1 = entries[size_t(task.End - 1)].Code;
    Index split = task.Begin + count / 2; // identical codes: halve
    if (c0 != c1)
    {
      int bit = 63;
      while (!(((c0 ^ c1) >> bit) & 1))
      {
        --bit;
      }
      const auto it = std::partition_point(entries.begin() + task.Begin, entries.begin() + task.End,
        [bit](const MortonEntry& e) { return !((e.Code >> bit) & 1); });
      split = static_cast<Index>(it - entries.begin());
    }
    const Index left = static_cast<Index>(nodes.size());
    node.First = left;
    node.Count = 0;
    nodes.push_back(TriangleBVH::Node{});
    nodes.push_back(TriangleBVH::Node{});
    tasks.push_back({ left + 1, split, task.End, task.Depth + 1 });
    tasks.push_back({ left, task.Begin, split, task.Depth + 1 });
  }
  return depth;
}

// Bounds bottom-up (children always come after their parent) from the corners in leaf order.
void ComputeNodeBounds(const std::vector<double>& corners, std::vector<TriangleBVH::Node>& nodes)
{
  for (size_t n = nodes.size(); n-- > 0;)
  {
    TriangleBVH::Node& node = nodes[n];
    Box box;
    if (node.Count > 0)
    {
      for (Index i = node.First; i < node.First + node.Count; ++i)
      {
        GrowByTriangle(&corners[9 * size_t(i)], box);
      }
    }
    else
    {
      box.Grow(nodes[size_t(node.First)].Bounds);
      box.Grow(nodes[size_t(node.First) + 1].Bounds);
    }
    std::copy(box.B, box.B + 6, node.Bounds);
  }
}
} // namespace

void TriangleBVH::Build(const TriangleMesh& mesh)
{
  this->Mesh = &mesh;
  this->Nodes.clear();
  this->Order.clear();
  this->Corners.clear();
  this->Depth = 0;
  const Index nt = mesh.NumberOfTriangles();
  if (nt == 0)
  {
    return;
  }
  const std::vector<MortonEntry> entries =
    MortonOrder(nt, [&mesh](Index t, double* centre) { TriangleBoxCentre(mesh, t, centre); });
  this->Depth = BuildHierarchy(entries, this->Nodes);
  // Leaf order and the triangles' corners in that order (coherent memory for the queries).
  // On huge pages: the corners are 72 bytes per triangle (152 MB on the MRI), and first touches of
  // 4 KiB pages were most of the build's CPU time on that input (session 32).
  AssignOnHugePages(this->Order, size_t(nt), Index(0));
  AssignOnHugePages(this->Corners, 9 * size_t(nt), 0.0);
  auto copyCorners = [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType i = first; i < last; ++i)
    {
      const Index t = entries[size_t(i)].Id;
      this->Order[size_t(i)] = t;
      const Index* tri = mesh.Triangle(t);
      for (int j = 0; j < 3; ++j)
      {
        std::copy_n(&mesh.Points[3 * size_t(tri[j])], 3, &this->Corners[9 * size_t(i) + 3 * size_t(j)]);
      }
    }
  };
  if (nt < SerialBelow)
  {
    copyCorners(0, nt);
  }
  else
  {
    vtkSMPTools::For(0, nt, copyCorners);
  }
  ComputeNodeBounds(this->Corners, this->Nodes);
}

bool TriangleBVH::Empty() const
{
  return this->Nodes.empty();
}

ClosestPointResult TriangleBVH::ClosestPoint(const Vec3& query, double maxDistance2) const
{
  ClosestPointResult result;
  double best = maxDistance2 >= 0 ? maxDistance2 : Infinity;
  result.Distance2 = best;
  if (this->Nodes.empty())
  {
    return result;
  }
  const double q[3] = { query[0], query[1], query[2] };
  bool found = false;
  // Before the first hit, boxes at exactly the bound are visited (the bound itself may be attained).
  auto visit = [&](double d2) { return found ? d2 < best : d2 <= best; };
  if (!visit(BoxDistance2(this->Nodes[0].Bounds, q)))
  {
    return result;
  }

  struct Entry
  {
    Index NodeIndex;
    double Distance2;
  };
  Entry stack[MaxStack];
  int top = 0;
  Index current = 0;
  const Node* nodes = this->Nodes.data();
  const double* corners = this->Corners.data();
  for (;;)
  {
    const Node& node = nodes[current];
    if (node.Count > 0)
    {
      for (Index i = node.First, e = node.First + node.Count; i < e; ++i)
      {
        const double* t = corners + 9 * size_t(i);
        double p[3];
        const double d2 = ClosestOnTriangle(q, t, t + 3, t + 6, p);
        if (visit(d2))
        {
          found = true;
          best = d2;
          result.Point = { p[0], p[1], p[2] };
          result.Triangle = i; // leaf position for now, mapped to the triangle id at the end
        }
      }
    }
    else
    {
      Index nearChild = node.First, farChild = node.First + 1;
      double nearD2 = BoxDistance2(nodes[nearChild].Bounds, q);
      double farD2 = BoxDistance2(nodes[farChild].Bounds, q);
      if (farD2 < nearD2)
      {
        std::swap(nearChild, farChild);
        std::swap(nearD2, farD2);
      }
      if (visit(farD2))
      {
        stack[top++] = { farChild, farD2 };
      }
      if (visit(nearD2))
      {
        current = nearChild;
        continue;
      }
    }
    current = InvalidIndex;
    while (top > 0)
    {
      const Entry& e = stack[--top];
      if (visit(e.Distance2))
      {
        current = e.NodeIndex;
        break;
      }
    }
    if (current == InvalidIndex)
    {
      break;
    }
  }
  if (found)
  {
    result.Distance2 = best;
    result.Triangle = this->Order[size_t(result.Triangle)];
  }
  return result;
}

bool TriangleBVH::AnyWithin(const Vec3& query, double maxDistance2) const
{
  Index none = InvalidIndex;
  return this->AnyWithin(query, maxDistance2, none);
}

bool TriangleBVH::AnyWithin(const Vec3& query, double maxDistance2, Index& hint) const
{
  if (this->Nodes.empty() || !(maxDistance2 >= 0))
  {
    return false;
  }
  const double q[3] = { query[0], query[1], query[2] };
  const Node* nodes = this->Nodes.data();
  const double* corners = this->Corners.data();
  if (hint != InvalidIndex && size_t(hint) < this->Nodes.size() && nodes[hint].Count > 0 &&
    BoxDistance2(nodes[hint].Bounds, q) <= maxDistance2)
  {
    for (Index i = nodes[hint].First, e = nodes[hint].First + nodes[hint].Count; i < e; ++i)
    {
      const double* t = corners + 9 * size_t(i);
      double p[3];
      if (ClosestOnTriangle(q, t, t + 3, t + 6, p) <= maxDistance2)
      {
        return true;
      }
    }
  }
  Index pending[MaxStack];
  int top = 0;
  pending[top++] = 0;
  while (top > 0)
  {
    const Index at = pending[--top];
    const Node& node = nodes[at];
    if (BoxDistance2(node.Bounds, q) > maxDistance2)
    {
      continue;
    }
    if (node.Count > 0)
    {
      for (Index i = node.First, e = node.First + node.Count; i < e; ++i)
      {
        const double* t = corners + 9 * size_t(i);
        double p[3];
        if (ClosestOnTriangle(q, t, t + 3, t + 6, p) <= maxDistance2)
        {
          hint = at;
          return true;
        }
      }
      continue;
    }
    // The nearer child popped first: most queries end in the first leaf they reach.
    Index nearChild = node.First, farChild = node.First + 1;
    if (BoxDistance2(nodes[farChild].Bounds, q) < BoxDistance2(nodes[nearChild].Bounds, q))
    {
      std::swap(nearChild, farChild);
    }
    pending[top++] = farChild;
    pending[top++] = nearChild;
  }
  return false;
}

bool TriangleBVH::TrianglesNear(const Vec3& query, double radius, size_t limit, std::vector<Index>& triangles) const
{
  const double q[3] = { query[0], query[1], query[2] };
  const double radius2 = radius * radius;
  // Depth first, two children pushed per node popped: at most the depth + 1 entries (no allocation
  // per query: the collapses of the greedy cuts ask several per try).
  Index pending[MaxStack];
  int top = 0;
  if (!this->Nodes.empty())
  {
    pending[top++] = 0;
  }
  const size_t start = triangles.size();
  while (top > 0)
  {
    const Node& node = this->Nodes[size_t(pending[--top])];
    if (BoxDistance2(node.Bounds, q) > radius2)
    {
      continue;
    }
    if (node.Count == 0)
    {
      pending[top++] = node.First;
      pending[top++] = node.First + 1;
      continue;
    }
    if (triangles.size() - start + size_t(node.Count) > limit)
    {
      return false; // each node is visited once, so the work is bounded by the tree size
    }
    for (Index i = node.First, e = node.First + node.Count; i < e; ++i)
    {
      triangles.push_back(this->Order[size_t(i)]);
    }
  }
  return true;
}

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  Vec3 out;
  ClosestOnTriangle(p.data(), a.data(), b.data(), c.data(), out.data());
  return out;
}
} // namespace slod
