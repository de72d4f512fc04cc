// SPDX-License-Identifier: BSD-3-Clause
#include "slodLevelInterpolation.h"

#include "slodIndexedHeap.h"
#include "slodMeshTopology.h"
#include "slodTriangleBVH.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace slod
{
namespace
{
// A point of the low-detail surface: on a vertex, on an edge, or inside a triangle.
struct SurfaceLocation
{
  Vec3 Point{ 0, 0, 0 };
  Index Triangle = InvalidIndex;
  Index Vertex = InvalidIndex;
  Index Edge = InvalidIndex;
};

struct Crossing
{
  Index Edge;   // low-detail edge crossed
  Vec3 Point;   // on that edge
  double Along; // path length from the start to here
};

// Barycentric coordinates of p (projected into the triangle's plane), least squares.
void Barycentric(const TriangleMesh& mesh, Index t, const Vec3& p, double b[3])
{
  const Index* tri = mesh.Triangle(t);
  const Vec3 v0 = mesh.Point(tri[0]);
  const Vec3 e1 = mesh.Point(tri[1]) - v0;
  const Vec3 e2 = mesh.Point(tri[2]) - v0;
  const Vec3 w = p - v0;
  const double d11 = Dot(e1, e1), d12 = Dot(e1, e2), d22 = Dot(e2, e2);
  const double r1 = Dot(w, e1), r2 = Dot(w, e2);
  const double det = d11 * d22 - d12 * d12;
  if (!(std::abs(det) > 0))
  {
    b[0] = b[1] = b[2] = 1.0 / 3.0;
    return;
  }
  b[1] = (d22 * r1 - d12 * r2) / det;
  b[2] = (d11 * r2 - d12 * r1) / det;
  b[0] = 1.0 - b[1] - b[2];
}

Vec3 FromBarycentric(const TriangleMesh& mesh, Index t, const double b[3])
{
  const Index* tri = mesh.Triangle(t);
  return b[0] * mesh.Point(tri[0]) + b[1] * mesh.Point(tri[1]) + b[2] * mesh.Point(tri[2]);
}

class LowSurface
{
public:
  explicit LowSurface(const TriangleMesh& mesh)
    : Mesh(mesh)
    , Topology(mesh)
  {
  }

  // The triangles a location belongs to (several on an edge or a vertex).
  void Containing(const SurfaceLocation& loc, std::vector<Index>& out) const
  {
    out.clear();
    if (loc.Vertex != InvalidIndex)
    {
      out.assign(this->Topology.VertexTrianglesBegin(loc.Vertex), this->Topology.VertexTrianglesEnd(loc.Vertex));
    }
    else if (loc.Edge != InvalidIndex)
    {
      out.assign(this->Topology.EdgeTrianglesBegin(loc.Edge), this->Topology.EdgeTrianglesEnd(loc.Edge));
    }
    else
    {
      out.push_back(loc.Triangle);
    }
  }

  // Location of a point known to lie in triangle t (within rounding): snapped to an edge or a
  // vertex when a barycentric coordinate is (relatively) zero.
  SurfaceLocation Locate(Index t, const Vec3& p) const
  {
    const double snap = 1e-9;
    double b[3];
    Barycentric(this->Mesh, t, p, b);
    int small = 0;
    for (double& x : b)
    {
      if (x < snap)
      {
        x = 0;
        ++small;
      }
    }
    const double sum = b[0] + b[1] + b[2];
    for (double& x : b)
    {
      x /= sum;
    }
    SurfaceLocation loc;
    loc.Triangle = t;
    const Index* tri = this->Mesh.Triangle(t);
    if (small >= 2)
    {
      const int k = b[0] > 0.5 ? 0 : (b[1] > 0.5 ? 1 : 2);
      loc.Vertex = tri[k];
      loc.Point = this->Mesh.Point(tri[k]);
      return loc;
    }
    if (small == 1)
    {
      const int opposite = b[0] == 0 ? 0 : (b[1] == 0 ? 1 : 2);
      loc.Edge = this->Topology.TriangleEdge(t, (opposite + 1) % 3);
    }
    loc.Point = FromBarycentric(this->Mesh, t, b);
    return loc;
  }

  // A path from `from` to `to` on the surface; appends the crossed low edges in order. Returns the
  // path length, or -1 when none is found.
  double Trace(const SurfaceLocation& from, const SurfaceLocation& to, std::vector<Crossing>& crossings,
    std::vector<Index>& scratchA, std::vector<Index>& scratchB) const
  {
    std::vector<Index>& startSet = scratchA;
    std::vector<Index>& targetSet = scratchB;
    this->Containing(from, startSet);
    this->Containing(to, targetSet);
    auto inTarget = [&](Index t) { return std::find(targetSet.begin(), targetSet.end(), t) != targetSet.end(); };
    for (Index t : startSet)
    {
      if (inTarget(t))
      {
        return Norm(to.Point - from.Point);
      }
    }
    return this->TraceStrip(from, to, startSet, targetSet, crossings);
  }

  // The path is the shortest strip of edge-adjacent triangles from the start to the target
  // (Dijkstra over triangle centroids, bounded), crossed on each shared edge at the point closest to
  // the straight segment between the two ends (a little away from the edge's ends, so that no path
  // runs through a low vertex). A walk re-aimed at the target in each triangle was tried first: it
  // cycles between sharply folded triangles and goes round low vertices on the wrong side 3-4
  // times as often.
  double TraceStrip(const SurfaceLocation& from, const SurfaceLocation& to, const std::vector<Index>& startSet,
    const std::vector<Index>& targetSet, std::vector<Crossing>& crossings) const
  {
    std::vector<Index> strip;
    if (!this->ShortestStrip(from, startSet, targetSet, strip))
    {
      return -1;
    }
    return this->CrossStrip(from, to, strip, crossings);
  }

  // The strip of edge-adjacent triangles from a start triangle to a target triangle, shortest over
  // the centroids, from start to target; false when none is found within the bound.
  bool ShortestStrip(const SurfaceLocation& from, const std::vector<Index>& startSet,
    const std::vector<Index>& targetSet, std::vector<Index>& strip) const
  {
    const size_t limit = 4096; // triangles visited: a path is a few triangles long; beyond, give up
    std::vector<Index>& queue = this->Queue;
    queue.clear();
    if (this->Parent.size() != static_cast<size_t>(this->Mesh.NumberOfTriangles()))
    {
      this->Parent.assign(static_cast<size_t>(this->Mesh.NumberOfTriangles()), InvalidIndex);
      this->Cost.assign(static_cast<size_t>(this->Mesh.NumberOfTriangles()), 0.0);
    }
    for (Index t : startSet)
    {
      this->Parent[t] = t;
      queue.push_back(t);
    }
    Index found = InvalidIndex;
    {
      // Dijkstra over triangle centroids (ties by triangle id: deterministic).
      auto centroid = [&](Index t) {
        const Index* x = this->Mesh.Triangle(t);
        return (1.0 / 3.0) * (this->Mesh.Point(x[0]) + this->Mesh.Point(x[1]) + this->Mesh.Point(x[2]));
      };
      IndexedHeap<double>& heap = this->Frontier;
      heap.Reserve(this->Mesh.NumberOfTriangles());
      heap.Clear();
      for (Index t : startSet)
      {
        this->Cost[t] = Norm(centroid(t) - from.Point);
        heap.Set(t, this->Cost[t]);
      }
      while (!heap.Empty() && queue.size() < limit)
      {
        const double cost = heap.TopKey();
        const Index t = heap.Pop();
        if (std::find(targetSet.begin(), targetSet.end(), t) != targetSet.end())
        {
          found = t;
          break;
        }
        const Vec3 ct = centroid(t);
        for (int k = 0; k < 3; ++k)
        {
          const Index n = this->Topology.EdgeNeighbor(t, k);
          if (n == InvalidIndex)
          {
            continue;
          }
          const double c = cost + Norm(centroid(n) - ct);
          if (this->Parent[n] == InvalidIndex || c < this->Cost[n])
          {
            if (this->Parent[n] == InvalidIndex)
            {
              queue.push_back(n);
            }
            if (this->Parent[n] != n)
            {
              this->Parent[n] = t;
              this->Cost[n] = c;
              heap.Set(n, c);
            }
          }
        }
      }
    }
    strip.clear();
    for (Index t = found; t != InvalidIndex; t = this->Parent[t] == t ? InvalidIndex : this->Parent[t])
    {
      strip.push_back(t);
    }
    for (Index t : queue)
    {
      this->Parent[t] = InvalidIndex;
    }
    if (found == InvalidIndex)
    {
      return false;
    }
    std::reverse(strip.begin(), strip.end());
    return true;
  }

  // Crosses each shared edge of the strip at the point closest to the straight segment between the
  // ends; appends the crossings, returns the path length.
  double CrossStrip(const SurfaceLocation& from, const SurfaceLocation& to, const std::vector<Index>& strip,
    std::vector<Crossing>& crossings) const
  {
    Vec3 point = from.Point;
    double length = 0;
    const Vec3 pq = to.Point - from.Point;
    for (size_t i = 0; i + 1 < strip.size(); ++i)
    {
      const Index* tri = this->Mesh.Triangle(strip[i]);
      int k = 0;
      while (k < 3 && this->Topology.EdgeNeighbor(strip[i], k) != strip[i + 1])
      {
        ++k;
      }
      const Vec3 y = this->Mesh.Point(tri[k]), yz = this->Mesh.Point(tri[(k + 1) % 3]) - y;
      // Closest points of the lines y + s yz and from + r pq (s clamped inside the edge).
      const double a = Dot(yz, yz), b = Dot(yz, pq), c = Dot(pq, pq), d = Dot(yz, from.Point - y),
                   e = Dot(pq, from.Point - y);
      const double det = a * c - b * b;
      double sParam = det > 1e-300 ? (d * c - b * e) / det : (a > 0 ? d / a : 0.5);
      sParam = std::min(1 - 1e-6, std::max(1e-6, sParam));
      const Vec3 x = y + sParam * yz;
      length += Norm(x - point);
      crossings.push_back({ this->Topology.TriangleEdge(strip[i], k), x, length });
      point = x;
    }
    return length + Norm(to.Point - point);
  }

  const TriangleMesh& Mesh;
  MeshTopology Topology;
  mutable std::vector<Index> Parent, Queue;
  mutable std::vector<double> Cost;
  mutable IndexedHeap<double> Frontier; // ShortestStrip's Dijkstra: triangles by cost, ties by id
};

struct PointKey
{
  double X, Y, Z;
  bool operator==(const PointKey& o) const { return X == o.X && Y == o.Y && Z == o.Z; }
};
struct PointKeyHash
{
  size_t operator()(const PointKey& k) const
  {
    const std::hash<double> h;
    size_t s = h(k.X);
    s ^= h(k.Y) + 0x9e3779b97f4a7c15ULL + (s << 6) + (s >> 2);
    s ^= h(k.Z) + 0x9e3779b97f4a7c15ULL + (s << 6) + (s >> 2);
    return s;
  }
};

// One point of a high triangle's boundary: a corner or a crossing.
struct BoundaryEvent
{
  Index Vertex;    // output vertex
  Index LowVertex; // corner flattened onto a low vertex, else InvalidIndex
  Index LowEdge;   // crossing: the low edge, else InvalidIndex
  Index OnEdge;    // corner flattened onto a low edge (inside it), else InvalidIndex
  int Sides;       // bit k: on edge k of the high triangle (corner k is on edges k and k-1)
};
// Inserts a new high vertex at the closest point of `high` to q (splitting the triangle, or the edge
// it lands on, or reusing a vertex it lands on); the new vertex is tied to low vertex `lowVertex`.
void InsertVertex(TriangleMesh& high, std::vector<Index>& parent, const Vec3& q, std::vector<Index>& lowVertexOf,
  Index lowVertex)
{
  const TriangleBVH bvh(high);
  const ClosestPointResult closest = bvh.ClosestPoint(q);
  const Index t = closest.Triangle;
  double b[3];
  Barycentric(high, t, closest.Point, b);
  Index tri[3] = { high.Triangle(t)[0], high.Triangle(t)[1], high.Triangle(t)[2] };
  int small = 0, opposite = -1, big = 0;
  for (int i = 0; i < 3; ++i)
  {
    if (b[i] < 1e-9)
    {
      ++small;
      opposite = i;
    }
    if (b[i] > b[big])
    {
      big = i;
    }
  }
  if (small >= 2 && lowVertexOf[tri[big]] == InvalidIndex)
  {
    lowVertexOf[tri[big]] = lowVertex; // lands on a high-only vertex: that one is flattened onto q
    return;
  }
  const Index p = high.AddPoint(closest.Point);
  lowVertexOf.push_back(lowVertex);
  auto replace = [&](Index triangle, Index a, Index c, Index d) {
    Index* x = &high.Triangles[3 * static_cast<size_t>(triangle)];
    x[0] = a;
    x[1] = c;
    x[2] = d;
  };
  if (small == 1)
  {
    // Split edge (u, w) opposite corner `opposite` in t and in the triangle across it.
    const Index u = tri[(opposite + 1) % 3], w = tri[(opposite + 2) % 3];
    for (Index s = 0; s < high.NumberOfTriangles(); ++s)
    {
      const Index* x = high.Triangle(s);
      for (int k = 0; k < 3 && s != t; ++k)
      {
        if (x[k] == w && x[(k + 1) % 3] == u)
        {
          const Index d = x[(k + 2) % 3];
          replace(s, w, p, d);
          high.AddTriangle(p, u, d);
          parent.push_back(parent[s]);
          break;
        }
      }
    }
    replace(t, tri[opposite], u, p);
    high.AddTriangle(tri[opposite], p, w);
    parent.push_back(parent[t]);
    return;
  }
  replace(t, tri[0], tri[1], p);
  high.AddTriangle(tri[1], tri[2], p);
  high.AddTriangle(tri[2], tri[0], p);
  parent.push_back(parent[t]);
  parent.push_back(parent[t]);
}

Vec3 PositionOf(const std::vector<double>& xyz, Index v)
{
  const double* p = &xyz[3 * static_cast<size_t>(v)];
  return Vec3{ p[0], p[1], p[2] };
}

// Stage 1a, nesting: ties every high vertex at the exact position of a used low vertex to that low
// vertex (lowVertexOf); lists the used low vertices with no such high vertex (missing).
Index MatchSharedVertices(
  const TriangleMesh& high, const TriangleMesh& low, std::vector<Index>& lowVertexOf, std::vector<Index>& missing)
{
  std::unordered_map<PointKey, Index, PointKeyHash> highVertexAt;
  highVertexAt.reserve(static_cast<size_t>(high.NumberOfPoints()));
  for (Index v = 0; v < high.NumberOfPoints(); ++v)
  {
    const Vec3 p = high.Point(v);
    highVertexAt.emplace(PointKey{ p[0], p[1], p[2] }, v);
  }
  lowVertexOf.assign(static_cast<size_t>(high.NumberOfPoints()), InvalidIndex);
  std::vector<char> lowUsed(static_cast<size_t>(low.NumberOfPoints()), 0);
  for (Index t : low.Triangles)
  {
    lowUsed[t] = 1;
  }
  Index usedLow = 0;
  for (Index v = 0; v < low.NumberOfPoints(); ++v)
  {
    if (!lowUsed[v])
    {
      continue;
    }
    ++usedLow;
    const Vec3 p = low.Point(v);
    const auto it = highVertexAt.find(PointKey{ p[0], p[1], p[2] });
    if (it == highVertexAt.end() || lowVertexOf[it->second] != InvalidIndex)
    {
      missing.push_back(v);
    }
    else
    {
      lowVertexOf[it->second] = v;
    }
  }
  return usedLow;
}

// Stage 1c: the flattened location of every high vertex on the low surface: a shared vertex maps
// to itself, a high-only vertex to its closest point.
void FlattenVertices(const TriangleMesh& high, const LowSurface& surface, const std::vector<Index>& lowVertexOf,
  std::vector<SurfaceLocation>& flat, LevelInterpolation& result)
{
  const TriangleBVH bvh(surface.Mesh);
  flat.assign(static_cast<size_t>(high.NumberOfPoints()), SurfaceLocation());
  for (Index v = 0; v < high.NumberOfPoints(); ++v)
  {
    SurfaceLocation& loc = flat[v];
    if (lowVertexOf[v] != InvalidIndex)
    {
      loc.Vertex = lowVertexOf[v];
      loc.Point = surface.Mesh.Point(loc.Vertex);
      loc.Triangle = *surface.Topology.VertexTrianglesBegin(loc.Vertex);
      ++result.SharedVertices;
    }
    else
    {
      const ClosestPointResult closest = bvh.ClosestPoint(high.Point(v));
      loc = surface.Locate(closest.Triangle, closest.Point);
      ++result.FlattenedVertices;
    }
  }
}

// Stage 2: the path of every high edge on the low surface (from its lower-numbered vertex):
// crossings of edge e are Crossings[Offset[e]] .. Crossings[Offset[e + 1] - 1].
struct EdgePaths
{
  std::vector<Index> Offset;
  std::vector<Crossing> Crossings;
  std::vector<double> Length;
};

void TraceHighEdges(const MeshTopology& highTopology, const LowSurface& surface,
  const std::vector<SurfaceLocation>& flat, EdgePaths& paths, LevelInterpolation& result)
{
  const Index nEdges = highTopology.NumberOfEdges();
  paths.Offset.assign(static_cast<size_t>(nEdges) + 1, 0);
  paths.Length.assign(static_cast<size_t>(nEdges), 0);
  std::vector<Index> scratchA, scratchB;
  for (Index e = 0; e < nEdges; ++e)
  {
    const Index u = highTopology.EdgeVertex(e, 0), w = highTopology.EdgeVertex(e, 1);
    const double length = surface.Trace(flat[u], flat[w], paths.Crossings, scratchA, scratchB);
    if (length < 0)
    {
      ++result.UntracedEdges;
    }
    paths.Length[e] = length;
    paths.Offset[e + 1] = static_cast<Index>(paths.Crossings.size());
  }
  result.Crossings = static_cast<Index>(paths.Crossings.size());
}

// Output vertices: high vertices, then crossings (a crossing at fraction f of the path sits at
// fraction f of the high edge).
void StoreVertexPositions(const TriangleMesh& high, const MeshTopology& highTopology,
  const std::vector<SurfaceLocation>& flat, const EdgePaths& paths, LevelInterpolation& result)
{
  const Index nHigh = high.NumberOfPoints();
  const size_t nOut = static_cast<size_t>(nHigh) + paths.Crossings.size();
  result.LowPositions.resize(3 * nOut);
  result.HighPositions.resize(3 * nOut);
  auto store = [&](size_t i, const Vec3& lowP, const Vec3& highP) {
    std::copy(lowP.begin(), lowP.end(), result.LowPositions.begin() + 3 * i);
    std::copy(highP.begin(), highP.end(), result.HighPositions.begin() + 3 * i);
  };
  for (Index v = 0; v < nHigh; ++v)
  {
    store(v, flat[v].Point, high.Point(v));
  }
  for (Index e = 0; e < highTopology.NumberOfEdges(); ++e)
  {
    const Vec3 a = high.Point(highTopology.EdgeVertex(e, 0));
    const Vec3 b = high.Point(highTopology.EdgeVertex(e, 1));
    for (Index c = paths.Offset[e]; c < paths.Offset[e + 1]; ++c)
    {
      const double f = paths.Length[e] > 0 ? std::min(1.0, paths.Crossings[c].Along / paths.Length[e]) : 0.5;
      store(static_cast<size_t>(nHigh) + c, paths.Crossings[c].Point, (1 - f) * a + f * b);
    }
  }
}

// Stage 3: cuts each high triangle along the chords (low edges) into fragments, each inside one
// low triangle, and triangulates the fragments.
class FragmentCutter
{
public:
  FragmentCutter(const TriangleMesh& high, const MeshTopology& highTopology, const std::vector<Index>& parent,
    const LowSurface& surface, const std::vector<SurfaceLocation>& flat, const EdgePaths& paths,
    LevelInterpolation& result)
    : High(high)
    , HighTopology(highTopology)
    , Parent(parent)
    , Surface(surface)
    , Flat(flat)
    , Paths(paths)
    , Result(result)
    , NumberOfHighVertices(high.NumberOfPoints())
  {
  }

  void Cut(Index t)
  {
    this->CollectBoundaryEvents(t);
    this->PairChords();
    this->FindLoneCenters();
    this->SplitIntoFragments(t);
  }

private:
  // The boundary of high triangle t: its corners and, between them, the crossings of its edges.
  void CollectBoundaryEvents(Index t)
  {
    const Index* tri = this->High.Triangle(t);
    this->Events.clear();
    for (int k = 0; k < 3; ++k)
    {
      const Index a = tri[k];
      this->Events.push_back(
        { a, this->Flat[a].Vertex, InvalidIndex, this->Flat[a].Edge, (1 << k) | (1 << ((k + 2) % 3)) });
      const Index e = this->HighTopology.TriangleEdge(t, k);
      const Index first = this->Paths.Offset[e], last = this->Paths.Offset[e + 1];
      const std::vector<Crossing>& crossings = this->Paths.Crossings;
      if (this->HighTopology.EdgeVertex(e, 0) == a)
      {
        for (Index c = first; c < last; ++c)
        {
          this->Events.push_back({ this->NumberOfHighVertices + c, InvalidIndex, crossings[c].Edge, InvalidIndex, 1 << k });
        }
      }
      else
      {
        for (Index c = last - 1; c >= first; --c)
        {
          this->Events.push_back({ this->NumberOfHighVertices + c, InvalidIndex, crossings[c].Edge, InvalidIndex, 1 << k });
        }
      }
    }
  }

  // Chords: crossings of the same low edge in boundary order, paired two by two; a lone crossing
  // pairs with the corner that is an end of its low edge.
  void PairChords()
  {
    const std::vector<BoundaryEvent>& events = this->Events;
    const int n = static_cast<int>(events.size());
    this->Chords.clear();
    this->Lone.clear();
    std::vector<char> paired(static_cast<size_t>(n), 0);
    for (int i = 0; i < n; ++i)
    {
      if (events[i].LowEdge == InvalidIndex || paired[i])
      {
        continue;
      }
      int partner = -1;
      for (int j = i + 1; j < n && partner < 0; ++j)
      {
        if (!paired[j] && events[j].LowEdge == events[i].LowEdge)
        {
          partner = j;
        }
      }
      if (partner < 0)
      {
        const Index e = events[i].LowEdge;
        const Index u = this->Surface.Topology.EdgeVertex(e, 0), w = this->Surface.Topology.EdgeVertex(e, 1);
        for (int j = 0; j < n && partner < 0; ++j)
        {
          if ((events[j].LowVertex != InvalidIndex && (events[j].LowVertex == u || events[j].LowVertex == w)) ||
            events[j].OnEdge == e)
          {
            partner = j;
          }
        }
      }
      paired[i] = 1;
      if (partner < 0)
      {
        this->Lone.push_back(i);
        continue;
      }
      if (events[partner].LowEdge != InvalidIndex)
      {
        paired[partner] = 1;
      }
      // Both ends on one side of the high triangle: the low edge doubles back across it (a fold);
      // cutting there would give a flat fragment that both triangles of that side share.
      if ((events[i].Sides & events[partner].Sides) == 0)
      {
        this->Chords.emplace_back(std::min(i, partner), std::max(i, partner));
      }
    }
  }

  // Lone crossings: where the flattening folds, a low vertex can fall inside the image of a high
  // triangle, and the low edges around it cross the boundary once each. Such a vertex becomes an
  // interior vertex of the triangle (flattened onto the low vertex, at the mean of its crossings on
  // the high triangle), joined to those crossings.
  void FindLoneCenters()
  {
    const MeshTopology& lowTopology = this->Surface.Topology;
    this->CenterOf.assign(this->Events.size(), InvalidIndex);
    for (int i : this->Lone)
    {
      const Index e = this->Events[i].LowEdge;
      Index best = InvalidIndex;
      int bestCount = 0;
      for (int end = 0; end < 2; ++end)
      {
        const Index x = lowTopology.EdgeVertex(e, end);
        int count = 0;
        for (int j : this->Lone)
        {
          const Index f = this->Events[j].LowEdge;
          count += (lowTopology.EdgeVertex(f, 0) == x || lowTopology.EdgeVertex(f, 1) == x) ? 1 : 0;
        }
        if (count > bestCount)
        {
          bestCount = count;
          best = x;
        }
      }
      if (bestCount >= 2)
      {
        this->CenterOf[i] = best;
      }
    }
  }

  // Recursive split of the boundary polygon by the chords, then around the interior low vertices;
  // what remains are the fragments.
  void SplitIntoFragments(Index t)
  {
    const int n = static_cast<int>(this->Events.size());
    this->Stack.clear();
    this->Stack.emplace_back();
    for (int i = 0; i < n; ++i)
    {
      this->Stack.back().push_back(i);
    }
    while (!this->Stack.empty())
    {
      std::vector<int> polygon = std::move(this->Stack.back());
      this->Stack.pop_back();
      if (!this->SplitByChord(polygon) && !this->SplitAroundCenter(polygon, n))
      {
        this->EmitFragment(t, polygon);
      }
    }
  }

  bool SplitByChord(const std::vector<int>& polygon)
  {
    const int m = static_cast<int>(polygon.size());
    for (const auto& chord : this->Chords)
    {
      const auto pi = std::find(polygon.begin(), polygon.end(), chord.first);
      const auto pj = std::find(polygon.begin(), polygon.end(), chord.second);
      if (pi == polygon.end() || pj == polygon.end())
      {
        continue;
      }
      const int i = static_cast<int>(pi - polygon.begin()), j = static_cast<int>(pj - polygon.begin());
      const int gap = std::abs(i - j);
      if (gap <= 1 || gap >= m - 1)
      {
        continue; // already an edge of this polygon
      }
      const int lo = std::min(i, j), hi = std::max(i, j);
      std::vector<int> inner(polygon.begin() + lo, polygon.begin() + hi + 1);
      std::vector<int> outer(polygon.begin(), polygon.begin() + lo + 1);
      outer.insert(outer.end(), polygon.begin() + hi, polygon.end());
      this->Stack.push_back(std::move(inner));
      this->Stack.push_back(std::move(outer));
      return true;
    }
    return false;
  }

  // Star split around a low vertex inside the triangle (see FindLoneCenters). n: the number of
  // boundary events (interior vertices come after them).
  bool SplitAroundCenter(const std::vector<int>& polygon, int n)
  {
    const int m = static_cast<int>(polygon.size());
    for (int k = 0; k < m; ++k)
    {
      const Index x = polygon[k] < n ? this->CenterOf[polygon[k]] : InvalidIndex;
      if (x == InvalidIndex)
      {
        continue;
      }
      std::vector<int> fan;
      for (int j = 0; j < m; ++j)
      {
        if (polygon[j] < n && this->CenterOf[polygon[j]] == x)
        {
          fan.push_back(j);
        }
      }
      if (fan.size() < 2)
      {
        continue;
      }
      const int center = this->AddInteriorVertex(polygon, fan, x);
      for (size_t f = 0; f < fan.size(); ++f)
      {
        const int from = fan[f], to = fan[(f + 1) % fan.size()];
        std::vector<int> piece;
        for (int j = from;; j = (j + 1) % m)
        {
          piece.push_back(polygon[j]);
          if (j == to)
          {
            break;
          }
        }
        piece.push_back(center);
        if (piece.size() >= 3)
        {
          this->Stack.push_back(std::move(piece));
        }
      }
      for (int j : fan)
      {
        this->CenterOf[polygon[j]] = InvalidIndex; // done: the pieces are final
      }
      return true;
    }
    return false;
  }

  // The interior vertex on low vertex x, at the mean of its crossings on the high triangle; returns
  // its event.
  int AddInteriorVertex(const std::vector<int>& polygon, const std::vector<int>& fan, Index x)
  {
    LevelInterpolation& result = this->Result;
    Vec3 lowP = this->Surface.Mesh.Point(x), highP{ 0, 0, 0 };
    for (int j : fan)
    {
      highP = highP +
        (1.0 / static_cast<double>(fan.size())) * PositionOf(result.HighPositions, this->Events[polygon[j]].Vertex);
    }
    const Index id = static_cast<Index>(result.LowPositions.size() / 3);
    result.LowPositions.insert(result.LowPositions.end(), lowP.begin(), lowP.end());
    result.HighPositions.insert(result.HighPositions.end(), highP.begin(), highP.end());
    ++result.InteriorVertices;
    const int center = static_cast<int>(this->Events.size());
    this->Events.push_back({ id, x, InvalidIndex, InvalidIndex, 0 });
    return center;
  }

  // The low triangle holding all the vertices of a fragment (InvalidIndex: none).
  Index LowTriangleOf(const std::vector<int>& polygon)
  {
    const MeshTopology& lowTopology = this->Surface.Topology;
    for (size_t k = 0; k < polygon.size(); ++k)
    {
      const BoundaryEvent& ev = this->Events[polygon[k]];
      if (ev.LowEdge != InvalidIndex)
      {
        this->Set.assign(lowTopology.EdgeTrianglesBegin(ev.LowEdge), lowTopology.EdgeTrianglesEnd(ev.LowEdge));
      }
      else if (ev.Vertex >= this->NumberOfHighVertices) // interior vertex on a low vertex
      {
        this->Set.assign(lowTopology.VertexTrianglesBegin(ev.LowVertex), lowTopology.VertexTrianglesEnd(ev.LowVertex));
      }
      else
      {
        this->Surface.Containing(this->Flat[ev.Vertex], this->Set);
      }
      if (k == 0)
      {
        this->Common = this->Set;
      }
      else
      {
        const std::vector<Index>& set = this->Set;
        this->Common.erase(std::remove_if(this->Common.begin(), this->Common.end(),
                             [&](Index x) { return std::find(set.begin(), set.end(), x) == set.end(); }),
          this->Common.end());
      }
    }
    return this->Common.empty() ? InvalidIndex : this->Common.front();
  }

  void EmitFragment(Index t, const std::vector<int>& polygon)
  {
    const Index lowTriangle = this->LowTriangleOf(polygon);
    if (lowTriangle == InvalidIndex)
    {
      ++this->Result.InconsistentFragments;
    }
    const Index fragment = this->Result.Fragments++;
    this->Ring.clear();
    this->RingSides.clear();
    for (int k : polygon)
    {
      this->Ring.push_back(this->Events[k].Vertex);
      this->RingSides.push_back(this->Events[k].Sides);
    }
    const Index* tri = this->High.Triangle(t);
    const Vec3 normal = TriangleNormal(this->High.Point(tri[0]), this->High.Point(tri[1]), this->High.Point(tri[2]));
    // No diagonal along a side of the high triangle (that side holds other fragment vertices).
    auto sides = [this](Index v) {
      return this->RingSides[size_t(std::find(this->Ring.begin(), this->Ring.end(), v) - this->Ring.begin())];
    };
    ClipFragmentEars(this->Ring, normal, [&](Index p, Index s) { return (sides(p) & sides(s)) == 0; },
      this->Parent[t], lowTriangle, fragment, this->Result);
  }

  const TriangleMesh& High;
  const MeshTopology& HighTopology;
  const std::vector<Index>& Parent;
  const LowSurface& Surface;
  const std::vector<SurfaceLocation>& Flat;
  const EdgePaths& Paths;
  LevelInterpolation& Result;
  const Index NumberOfHighVertices;
  // Per high triangle (kept to reuse their memory).
  std::vector<BoundaryEvent> Events;
  std::vector<std::pair<int, int>> Chords;
  std::vector<int> Lone;
  std::vector<Index> CenterOf;
  std::vector<std::vector<int>> Stack;
  std::vector<Index> Common, Set, Ring;
  std::vector<int> RingSides;
};
} // namespace

void ClipFragmentEars(std::vector<Index> ring, const Vec3& normal, const std::function<bool(Index, Index)>& allowed,
  Index highTriangle, Index lowTriangle, Index fragment, LevelInterpolation& result)
{
  while (ring.size() >= 3)
  {
    const size_t r = ring.size();
    size_t best = 0;
    double bestAngle = -1;
    for (size_t k = 0; k < r && r > 3; ++k)
    {
      const Index p = ring[(k + r - 1) % r], q = ring[k], s = ring[(k + 1) % r];
      const Vec3 hp = PositionOf(result.HighPositions, p), hq = PositionOf(result.HighPositions, q),
                 hs = PositionOf(result.HighPositions, s);
      const double highAngle = MinimumAngle(hp, hq, hs);
      const bool valid = highAngle > 1e-9 && Dot(Cross(hq - hp, hs - hq), normal) > 0 && allowed(p, s);
      double angle = 0.0;
      if (valid)
      {
        const double lowAngle = MinimumAngle(
          PositionOf(result.LowPositions, p), PositionOf(result.LowPositions, q), PositionOf(result.LowPositions, s));
        angle = std::min(highAngle, lowAngle) + 1e-6;
      }
      if (angle > bestAngle)
      {
        bestAngle = angle;
        best = k;
      }
    }
    result.Triangles.push_back(ring[(best + r - 1) % r]);
    result.Triangles.push_back(ring[best]);
    result.Triangles.push_back(ring[(best + 1) % r]);
    result.HighTriangle.push_back(highTriangle);
    result.LowTriangle.push_back(lowTriangle);
    result.Fragment.push_back(fragment);
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(best));
  }
}

void LevelInterpolation::Evaluate(double t, TriangleMesh& mesh) const
{
  mesh.Points.resize(this->LowPositions.size());
  for (size_t i = 0; i < this->LowPositions.size(); ++i)
  {
    mesh.Points[i] = (1 - t) * this->LowPositions[i] + t * this->HighPositions[i];
  }
  mesh.Triangles = this->Triangles;
}

void InterpolateLevels(
  const TriangleMesh& highInput, const TriangleMesh& low, LevelInterpolation& result, const ProgressFunction& progress)
{
  result = LevelInterpolation();
  if (highInput.NumberOfTriangles() == 0 || low.NumberOfTriangles() == 0)
  {
    result.Error = "both levels need triangles";
    return;
  }
  // Stage 1: which high vertices are low vertices (nesting), and the flattened location of every vertex.
  TriangleMesh high = highInput;
  std::vector<Index> parent(static_cast<size_t>(high.NumberOfTriangles()));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<Index> lowVertexOf, missing;
  const Index usedLow = MatchSharedVertices(high, low, lowVertexOf, missing);
  // A few low vertices missing from the high level (levels that are not quite nested, e.g. made by
  // another tool; vtkRetile's nested levels have none) are inserted into the high level at their
  // closest point on it: the high shape is unchanged and the levels become nested. Mostly
  // unrelated meshes are an error.
  if (2 * static_cast<size_t>(missing.size()) > static_cast<size_t>(usedLow))
  {
    result.Error = "the levels are not nested: " + std::to_string(missing.size()) + " of the " +
      std::to_string(usedLow) + " low-detail vertices are not vertices of the high-detail level";
    return;
  }
  for (Index v : missing)
  {
    InsertVertex(high, parent, low.Point(v), lowVertexOf, v);
  }
  result.InsertedVertices = static_cast<Index>(missing.size());

  LowSurface surface(low);
  for (Index e = 0; e < surface.Topology.NumberOfEdges(); ++e)
  {
    if (surface.Topology.IsNonManifoldEdge(e))
    {
      result.Error = "the low-detail level has non-manifold edges";
      return;
    }
  }
  std::vector<SurfaceLocation> flat;
  if (progress && !progress(0.0))
  {
    result.Aborted = true;
    return;
  }
  FlattenVertices(high, surface, lowVertexOf, flat, result);

  const MeshTopology highTopology(high);
  EdgePaths paths;
  TraceHighEdges(highTopology, surface, flat, paths, result);
  StoreVertexPositions(high, highTopology, flat, paths, result);

  FragmentCutter cutter(high, highTopology, parent, surface, flat, paths, result);
  constexpr Index ProgressStride = 1024;
  const Index triangles = high.NumberOfTriangles();
  for (Index t = 0; t < triangles; ++t)
  {
    if (t % ProgressStride == 0 && progress && !progress(0.5 + 0.5 * double(t) / double(triangles)))
    {
      result.Aborted = true;
      return;
    }
    cutter.Cut(t);
  }
  result.Valid = !(progress && !progress(1.0));
  result.Aborted = !result.Valid;
}
} // namespace slod
