#include "slodTriangleBVH.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

// One triangle during the build: its box, box centre and id (moved together by partitioning).
struct Primitive
{
  float Box[6];
  float Centre[3];
  Index Id;
};

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

constexpr int BinCount = 16;
// Below this depth splits use the object median, which halves the range: the depth (and the
// traversal stack) stays bounded whatever the triangle distribution.
constexpr int SAHDepthLimit = 48;
constexpr int MaxStack = 128;

// Binned SAH split of [begin, end): returns the partition point, or begin when no useful split exists.
Primitive* SplitSAH(Primitive* begin, Primitive* end, const float* centreBounds)
{
  const size_t count = size_t(end - begin);
  double bestCost = std::numeric_limits<double>::max();
  int bestAxis = -1, bestBin = -1;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double lo = centreBounds[2 * axis], extent = double(centreBounds[2 * axis + 1]) - lo;
    if (!(extent > 0) || !std::isfinite(extent))
    {
      continue;
    }
    const double scale = BinCount / extent;
    Box bins[BinCount];
    size_t counts[BinCount] = {};
    for (const Primitive* p = begin; p != end; ++p)
    {
      const int bin = std::min(BinCount - 1, static_cast<int>((p->Centre[axis] - lo) * scale));
      bins[bin].Grow(p->Box);
      ++counts[bin];
    }
    // Sweep from the right to get the right-side areas, then from the left.
    double rightArea[BinCount];
    size_t rightCount[BinCount];
    Box acc;
    size_t n = 0;
    for (int i = BinCount - 1; i > 0; --i)
    {
      acc.Grow(bins[i].B);
      n += counts[i];
      rightArea[i] = acc.HalfArea();
      rightCount[i] = n;
    }
    Box left;
    size_t nl = 0;
    for (int i = 0; i < BinCount - 1; ++i)
    {
      left.Grow(bins[i].B);
      nl += counts[i];
      const size_t nr = rightCount[i + 1];
      if (nl == 0 || nr == 0)
      {
        continue;
      }
      const double cost = double(nl) * left.HalfArea() + double(nr) * rightArea[i + 1];
      if (cost < bestCost)
      {
        bestCost = cost;
        bestAxis = axis;
        bestBin = i;
      }
    }
  }
  if (bestAxis < 0)
  {
    return begin;
  }
  const double lo = centreBounds[2 * bestAxis];
  const double scale = BinCount / (double(centreBounds[2 * bestAxis + 1]) - lo);
  Primitive* mid = std::partition(begin, end, [&](const Primitive& p) {
    return std::min(BinCount - 1, static_cast<int>((p.Centre[bestAxis] - lo) * scale)) <= bestBin;
  });
  return (mid == begin || mid == end || size_t(mid - begin) == count) ? begin : mid;
}

Primitive* SplitMedian(Primitive* begin, Primitive* end, const float* centreBounds)
{
  int axis = 0;
  double extent = -1;
  for (int k = 0; k < 3; ++k)
  {
    const double e = double(centreBounds[2 * k + 1]) - centreBounds[2 * k];
    if (e > extent)
    {
      extent = e;
      axis = k;
    }
  }
  Primitive* mid = begin + (end - begin) / 2;
  std::nth_element(begin, mid, end, [axis](const Primitive& a, const Primitive& b) {
    return a.Centre[axis] < b.Centre[axis] || (a.Centre[axis] == b.Centre[axis] && a.Id < b.Id);
  });
  return mid;
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

  std::vector<Primitive> prims(static_cast<size_t>(nt));
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    Primitive& p = prims[size_t(t)];
    for (int k = 0; k < 3; ++k)
    {
      double lo = Infinity, hi = -Infinity;
      for (int j = 0; j < 3; ++j)
      {
        const double x = mesh.Points[3 * size_t(tri[j]) + k];
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      p.Box[2 * k] = RoundDown(lo);
      p.Box[2 * k + 1] = RoundUp(hi);
      const double c = 0.5 * (lo + hi);
      p.Centre[k] = static_cast<float>(std::isfinite(c) ? std::max(-3e38, std::min(3e38, c)) : 0.0);
    }
    p.Id = t;
  }

  // A binary tree with leaves of >= 1 triangle has < 2 * nt nodes.
  this->Nodes.reserve(2 * size_t(nt) / TriangleBVH::LeafSize + 16);
  this->Nodes.push_back(Node{});
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
    this->Depth = std::max(this->Depth, task.Depth);
    Primitive* begin = prims.data() + task.Begin;
    Primitive* end = prims.data() + task.End;
    Box box, centres;
    for (const Primitive* p = begin; p != end; ++p)
    {
      box.Grow(p->Box);
      const float c[6] = { p->Centre[0], p->Centre[0], p->Centre[1], p->Centre[1], p->Centre[2], p->Centre[2] };
      centres.Grow(c);
    }
    Node& node = this->Nodes[size_t(task.NodeIndex)];
    std::copy(box.B, box.B + 6, node.Bounds);
    const Index count = task.End - task.Begin;
    if (count <= TriangleBVH::LeafSize)
    {
      node.First = task.Begin;
      node.Count = count;
      continue;
    }
    Primitive* mid = task.Depth < SAHDepthLimit ? SplitSAH(begin, end, centres.B) : begin;
    if (mid == begin)
    {
      mid = SplitMedian(begin, end, centres.B);
    }
    const Index left = static_cast<Index>(this->Nodes.size());
    node.First = left;
    node.Count = 0;
    this->Nodes.push_back(Node{});
    this->Nodes.push_back(Node{});
    const Index split = static_cast<Index>(mid - prims.data());
    // Right first on the stack so the left subtree is laid out right after its parent.
    tasks.push_back({ left + 1, split, task.End, task.Depth + 1 });
    tasks.push_back({ left, task.Begin, split, task.Depth + 1 });
  }

  this->Order.resize(size_t(nt));
  this->Corners.resize(9 * size_t(nt));
  for (size_t i = 0; i < prims.size(); ++i)
  {
    const Index t = prims[i].Id;
    this->Order[i] = t;
    const Index* tri = mesh.Triangle(t);
    for (int j = 0; j < 3; ++j)
    {
      std::copy_n(&mesh.Points[3 * size_t(tri[j])], 3, &this->Corners[9 * i + 3 * size_t(j)]);
    }
  }
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

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  Vec3 out;
  ClosestOnTriangle(p.data(), a.data(), b.data(), c.data(), out.data());
  return out;
}
} // namespace slod
