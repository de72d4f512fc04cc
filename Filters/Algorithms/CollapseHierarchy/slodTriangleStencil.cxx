// SPDX-License-Identifier: BSD-3-Clause
#include "slodTriangleStencil.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace slod
{
void TriangleStencil::Clear()
{
  this->Triangle = InvalidIndex;
  this->Triangles.clear();
  this->Neighbors.clear();
  this->OppositeVertices.clear();
  this->BoundaryPolygon.clear();
  this->Connected = this->Cyclic = this->Complete = false;
}

const char* ToString(CollapsibleStatus status)
{
  switch (status)
  {
    case CollapsibleStatus::Ok: return "collapsible";
    case CollapsibleStatus::DeadTriangle: return "dead triangle";
    case CollapsibleStatus::IncompleteStencil: return "incomplete stencil";
    case CollapsibleStatus::CyclicStencil: return "cyclic stencil";
    case CollapsibleStatus::CreatesCycle: return "collapse would create a cycle";
    case CollapsibleStatus::NotStarShaped: return "stencil polygon not star-shaped";
    case CollapsibleStatus::MeshCheckFailed: return "mesh check failed";
  }
  return "unknown";
}

namespace
{
inline int SharedVertices(const Index* a, const Index* b)
{
  int n = 0;
  for (int i = 0; i < 3; ++i)
  {
    n += (a[i] == b[0] || a[i] == b[1] || a[i] == b[2]) ? 1 : 0;
  }
  return n;
}

// The other triangles around T's vertices (first seen first), and the ones sharing an edge with T
// with their vertex not in T.
void GatherStencil(const EditableMesh& mesh, TriangleStencil& s)
{
  const Index* tri = s.Vertices;
  for (int k = 0; k < 3; ++k)
  {
    mesh.ForEachTriangle(tri[k], [&](Index x) {
      if (x != s.Triangle && std::find(s.Triangles.begin(), s.Triangles.end(), x) == s.Triangles.end())
      {
        s.Triangles.push_back(x);
      }
    });
  }
  for (Index x : s.Triangles)
  {
    const Index* q = mesh.Triangle(x);
    if (SharedVertices(q, tri) == 2)
    {
      s.Neighbors.push_back(x);
      for (int k = 0; k < 3; ++k)
      {
        if (q[k] != tri[0] && q[k] != tri[1] && q[k] != tri[2])
        {
          s.OppositeVertices.push_back(q[k]);
        }
      }
    }
  }
}
} // namespace

// The stencil of t (gathered, its edge neighbours and their opposite vertices) and its
// classification: connected, cyclic, complete.
void StencilBuilder::Build(const EditableMesh& mesh, Index t, TriangleStencil& s)
{
  s.Clear();
  s.Triangle = t;
  if (!mesh.IsTriangleAlive(t))
  {
    return;
  }
  const Index* tri = mesh.Triangle(t);
  std::copy(tri, tri + 3, s.Vertices);
  GatherStencil(mesh, s);
  const size_t n = s.Triangles.size();
  if (n == 0 || n > 64)
  {
    // Isolated triangle, or a neighbourhood too irregular to collapse (valence > ~60).
    return;
  }
  this->MatchRegionEdges(mesh, s);
  this->ClassifyAdjacency(s);
  bool touchesT = false;
  const bool simple = this->TraceBoundaryPolygon(s, touchesT);
  s.Complete = s.Connected && !s.Cyclic && simple && !touchesT;
}

// Directed edges of the region S u {T} (T's first), grouped by undirected edge by one sort: two
// triangles are edge neighbours when they share an undirected edge (sharing two vertices is
// sharing that edge), and a directed edge is on the region's boundary when its reverse is not in
// the region. Sorting keeps this O(m log m) where the pairwise loops were O(m^2). Fills EdgeFrom,
// EdgeTo, EdgeBoundary and the stencil triangles' Adjacency bit masks.
void StencilBuilder::MatchRegionEdges(const EditableMesh& mesh, const TriangleStencil& s)
{
  this->EdgeFrom.clear();
  this->EdgeTo.clear();
  auto addEdges = [&](Index x) {
    const Index* q = mesh.Triangle(x);
    for (int k = 0; k < 3; ++k)
    {
      this->EdgeFrom.push_back(q[k]);
      this->EdgeTo.push_back(q[(k + 1) % 3]);
    }
  };
  addEdges(s.Triangle);
  for (Index x : s.Triangles)
  {
    addEdges(x);
  }
  const size_t m = this->EdgeFrom.size();
  this->EdgeKeys.resize(m);
  for (size_t i = 0; i < m; ++i)
  {
    const auto a = static_cast<std::uint32_t>(std::min(this->EdgeFrom[i], this->EdgeTo[i]));
    const auto b = static_cast<std::uint32_t>(std::max(this->EdgeFrom[i], this->EdgeTo[i]));
    this->EdgeKeys[i] = { (static_cast<std::uint64_t>(a) << 32) | b, static_cast<std::uint32_t>(i) };
  }
  std::sort(this->EdgeKeys.begin(), this->EdgeKeys.end());
  this->EdgeBoundary.assign(m, 1);
  this->Adjacency.assign(s.Triangles.size(), 0ull);
  for (size_t g = 0; g < m;)
  {
    size_t h = g + 1;
    while (h < m && this->EdgeKeys[h].first == this->EdgeKeys[g].first)
    {
      ++h;
    }
    for (size_t i = g; i < h; ++i)
    {
      for (size_t j = i + 1; j < h; ++j)
      {
        this->MatchEdgePair(this->EdgeKeys[i].second, this->EdgeKeys[j].second);
      }
    }
    g = h;
  }
}

// Two directed edges on one undirected edge: opposite directions are interior to the region; two
// different stencil triangles on it are edge neighbours.
void StencilBuilder::MatchEdgePair(size_t ei, size_t ej)
{
  if (this->EdgeFrom[ei] == this->EdgeTo[ej] && this->EdgeTo[ei] == this->EdgeFrom[ej])
  {
    this->EdgeBoundary[ei] = this->EdgeBoundary[ej] = 0;
  }
  // Stencil triangle indices (edge / 3 - 1; T is 0).
  const size_t ti = ei / 3, tj = ej / 3;
  if (ti > 0 && tj > 0 && ti != tj)
  {
    this->Adjacency[ti - 1] |= 1ull << (tj - 1);
    this->Adjacency[tj - 1] |= 1ull << (ti - 1);
  }
}

// Connectivity and 3-cycles on the adjacency bit masks (at most 64 stencil triangles).
void StencilBuilder::ClassifyAdjacency(TriangleStencil& s) const
{
  const size_t n = s.Triangles.size();
  unsigned long long reached = 1ull, frontier = 1ull;
  while (frontier) // each round adds a triangle at least: at most n rounds
  {
    unsigned long long next = 0;
    for (size_t i = 0; i < n; ++i)
    {
      if (frontier & (1ull << i))
      {
        next |= this->Adjacency[i];
      }
    }
    frontier = next & ~reached;
    reached |= next;
  }
  const unsigned long long all = n == 64 ? ~0ull : ((1ull << n) - 1);
  s.Connected = reached == all;
  for (size_t i = 0; i < n && !s.Cyclic; ++i)
  {
    for (size_t j = i + 1; j < n; ++j)
    {
      if ((this->Adjacency[i] & (1ull << j)) && (this->Adjacency[i] & this->Adjacency[j]))
      {
        s.Cyclic = true;
        break;
      }
    }
  }
}

// The region's boundary as one simple loop into s.BoundaryPolygon (emptied when it is not one);
// touchesT: a boundary edge has an end at a vertex of T.
bool StencilBuilder::TraceBoundaryPolygon(TriangleStencil& s, bool& touchesT)
{
  // Boundary edges sorted by their start vertex: one loop needs exactly one leaving each vertex.
  const Index* tri = s.Vertices;
  const size_t m = this->EdgeFrom.size();
  touchesT = false;
  this->Outgoing.clear();
  for (size_t i = 0; i < m; ++i)
  {
    if (this->EdgeBoundary[i])
    {
      this->Outgoing.emplace_back(this->EdgeFrom[i], this->EdgeTo[i]);
      for (int k = 0; k < 3; ++k)
      {
        touchesT = touchesT || this->EdgeFrom[i] == tri[k] || this->EdgeTo[i] == tri[k];
      }
    }
  }
  const size_t boundaryCount = this->Outgoing.size();
  if (boundaryCount < 3)
  {
    return false; // closed region (the whole component) or degenerate
  }
  std::sort(this->Outgoing.begin(), this->Outgoing.end());
  bool simple = true;
  for (size_t i = 1; i < boundaryCount && simple; ++i)
  {
    simple = this->Outgoing[i].first != this->Outgoing[i - 1].first; // else pinched
  }
  // Walk the boundary from the first edge found: with one edge leaving each vertex, getting back
  // to the start after exactly boundaryCount steps means one simple loop through all of them.
  Index v = InvalidIndex;
  for (size_t i = 0; i < m && v == InvalidIndex; ++i)
  {
    v = this->EdgeBoundary[i] ? this->EdgeFrom[i] : InvalidIndex;
  }
  const Index start = v;
  for (size_t step = 0; step < boundaryCount && simple; ++step)
  {
    s.BoundaryPolygon.push_back(v);
    const auto it = std::lower_bound(this->Outgoing.begin(), this->Outgoing.end(), std::make_pair(v, std::numeric_limits<Index>::min()));
    if (it == this->Outgoing.end() || it->first != v)
    {
      simple = false;
      break;
    }
    v = it->second;
    if (v == start && step + 1 < boundaryCount)
    {
      simple = false;
    }
  }
  simple = simple && v == start && s.BoundaryPolygon.size() == boundaryCount;
  if (!simple)
  {
    s.BoundaryPolygon.clear();
  }
  return simple;
}

CollapsibleStatus StencilBuilder::CheckCollapsible(const EditableMesh& mesh, const TriangleStencil& s,
  const Vec3& p, const Vec3& normal, const CollapseOptions* meshOptions, const CollapsibleOptions& options,
  EditableMesh::CheckScratch* check)
{
  if (s.Triangle == InvalidIndex || !mesh.IsTriangleAlive(s.Triangle))
  {
    return CollapsibleStatus::DeadTriangle;
  }
  if (s.Cyclic)
  {
    return CollapsibleStatus::CyclicStencil;
  }
  if (!s.Complete || s.Neighbors.size() != 3)
  {
    return CollapsibleStatus::IncompleteStencil;
  }
  for (Index q : s.OppositeVertices)
  {
    if (!options.AllowNewCycles && mesh.VertexDegree(q) == 4)
    {
      return CollapsibleStatus::CreatesCycle;
    }
  }
  // Star-shaped with respect to p seen along the normal: every boundary edge must have the
  // projection of p strictly on its left, i.e. every new triangle (p, x, y) keeps T's orientation.
  const size_t n = s.BoundaryPolygon.size();
  auto starShaped = [&](const Vec3& direction) {
    for (size_t i = 0; i < n; ++i)
    {
      const Vec3 x = mesh.Point(s.BoundaryPolygon[i]) - p;
      const Vec3 y = mesh.Point(s.BoundaryPolygon[(i + 1) % n]) - p;
      const double area = Dot(Cross(x, y), direction);
      if (!(area > 1e-12 * (Dot(x, x) + Dot(y, y))))
      {
        return false;
      }
    }
    return true;
  };
  if (!starShaped(normal))
  {
    bool ok = false;
    if (options.StencilPlaneFallback)
    {
      Vec3 mean = mesh.TriangleNormal(s.Triangle);
      mean = mesh.TriangleArea(s.Triangle) * mean;
      for (Index x : s.Triangles)
      {
        mean = mean + mesh.TriangleArea(x) * mesh.TriangleNormal(x);
      }
      ok = Norm(mean) > 0 && starShaped(Normalized(mean));
    }
    if (!ok)
    {
      return CollapsibleStatus::NotStarShaped;
    }
  }
  if (meshOptions &&
    (check ? mesh.CheckCollapse(s.Vertices, 3, p, *meshOptions, *check) : mesh.CheckCollapse(s.Vertices, 3, p, *meshOptions)) !=
      CollapseStatus::Ok)
  {
    return CollapsibleStatus::MeshCheckFailed;
  }
  return CollapsibleStatus::Ok;
}
} // namespace slod
