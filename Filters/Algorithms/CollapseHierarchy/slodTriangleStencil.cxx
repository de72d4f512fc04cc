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
// with their vertex not in T. A live triangle is in the block of each of its vertices and holds
// them (EditableMesh's invariant), so one around tri[k] was seen before exactly when it holds an
// earlier vertex of T (no search of the list; one with a repeated vertex is searched for).
void GatherStencil(const EditableMesh& mesh, TriangleStencil& s)
{
  const Index* tri = s.Vertices;
  for (int k = 0; k < 3; ++k)
  {
    mesh.ForEachTriangle(tri[k], [&](Index x) {
      const Index* q = mesh.Triangle(x);
      bool seen = x == s.Triangle;
      for (int j = 0; j < k && !seen; ++j)
      {
        seen = q[0] == tri[j] || q[1] == tri[j] || q[2] == tri[j];
      }
      if (!seen && (q[0] == q[1] || q[1] == q[2] || q[0] == q[2]))
      {
        seen = std::find(s.Triangles.begin(), s.Triangles.end(), x) != s.Triangles.end();
      }
      if (!seen)
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
  this->Gather(mesh, t, s);
  this->Classify(mesh, s);
}

void StencilBuilder::Gather(const EditableMesh& mesh, Index t, TriangleStencil& s) const
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
}

void StencilBuilder::Classify(const EditableMesh& mesh, TriangleStencil& s)
{
  const size_t n = s.Triangles.size();
  if (s.Triangle == InvalidIndex || !mesh.IsTriangleAlive(s.Triangle) || n == 0 || n > 64)
  {
    // Dead, isolated triangle, or a neighbourhood too irregular to collapse (valence > ~60).
    return;
  }
  this->MatchRegionEdges(mesh, s);
  this->ClassifyAdjacency(s);
  bool touchesT = false;
  const bool simple = this->TraceBoundaryPolygon(s, touchesT);
  s.Complete = s.Connected && !s.Cyclic && simple && !touchesT;
}

// CheckCollapsible's answers that need no classification: a complete stencil has exactly three
// edge neighbours, and rule (2) reads only their opposite vertices.
bool StencilBuilder::FailsBeforeClassifying(
  const EditableMesh& mesh, const TriangleStencil& s, const CollapsibleOptions& options)
{
  if (s.Neighbors.size() != 3)
  {
    return true;
  }
  for (Index q : s.OppositeVertices)
  {
    if (!options.AllowNewCycles && mesh.VertexDegree(q) == 4)
    {
      return true;
    }
  }
  return false;
}

void StencilBuilder::KeyTable::Reset(size_t count)
{
  unsigned bits = 6;
  while ((size_t(1) << bits) < 2 * count)
  {
    ++bits;
  }
  const size_t size = size_t(1) << bits;
  if (this->Entries.size() < size || ++this->Stamp == 0)
  {
    this->Entries.assign(std::max(size, this->Entries.size()), Entry{ 0, -1, 0 });
    this->Stamp = 1;
  }
  this->Shift = 64 - bits;
}

inline std::int32_t& StencilBuilder::KeyTable::Find(std::uint64_t key, bool& inserted)
{
  const size_t mask = (size_t(1) << (64 - this->Shift)) - 1;
  size_t h = size_t((key * 0x9E3779B97F4A7C15ull) >> this->Shift);
  // (at most half full: Reset's count bounds the insertions)
  while (this->Entries[h].Stamp == this->Stamp && this->Entries[h].Key != key)
  {
    h = (h + 1) & mask;
  }
  Entry& entry = this->Entries[h];
  inserted = entry.Stamp != this->Stamp;
  if (inserted)
  {
    entry = Entry{ key, -1, this->Stamp };
  }
  return entry.Value;
}

// Two directed edges on one undirected edge: opposite directions are interior to the region; two
// different stencil triangles on it are edge neighbours.
inline void StencilBuilder::MatchEdgePair(size_t ei, size_t ej)
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

// Directed edges of the region S u {T} (T's first), grouped by undirected edge in a small hash
// table: two triangles are edge neighbours when they share an undirected edge (sharing two
// vertices is sharing that edge), and a directed edge is on the region's boundary when its
// reverse is not in the region. Each pair of directed edges on one undirected edge is matched
// once (MatchEdgePair: the result does not depend on the pairs' order). Fills EdgeFrom, EdgeTo,
// EdgeBoundary and the stencil triangles' Adjacency bit masks.
void StencilBuilder::MatchRegionEdges(const EditableMesh& mesh, const TriangleStencil& s)
{
  const size_t n = s.Triangles.size(), m = 3 * (n + 1);
  this->EdgeFrom.resize(m);
  this->EdgeTo.resize(m);
  for (size_t r = 0; r <= n; ++r)
  {
    const Index* q = mesh.Triangle(r == 0 ? s.Triangle : s.Triangles[r - 1]);
    for (size_t k = 0; k < 3; ++k)
    {
      this->EdgeFrom[3 * r + k] = q[k];
      this->EdgeTo[3 * r + k] = q[(k + 1) % 3];
    }
  }
  this->EdgeBoundary.assign(m, 1);
  this->Adjacency.assign(n, 0ull);
  this->NextOnEdge.resize(m);
  this->Edges.Reset(m);
  for (size_t i = 0; i < m; ++i)
  {
    const auto a = static_cast<std::uint32_t>(std::min(this->EdgeFrom[i], this->EdgeTo[i]));
    const auto b = static_cast<std::uint32_t>(std::max(this->EdgeFrom[i], this->EdgeTo[i]));
    bool inserted = false;
    std::int32_t& last = this->Edges.Find((static_cast<std::uint64_t>(a) << 32) | b, inserted);
    for (std::int32_t j = last; j >= 0; j = this->NextOnEdge[size_t(j)])
    {
      this->MatchEdgePair(size_t(j), i);
    }
    this->NextOnEdge[i] = last;
    last = static_cast<std::int32_t>(i);
  }
}

// Connectivity and 3-cycles on the adjacency bit masks (at most 64 stencil triangles), walking
// set bits only.
void StencilBuilder::ClassifyAdjacency(TriangleStencil& s) const
{
  const size_t n = s.Triangles.size();
  unsigned long long reached = 1ull, frontier = 1ull;
  while (frontier) // each round adds a triangle at least: at most n rounds
  {
    unsigned long long next = 0;
    for (unsigned long long bits = frontier; bits; bits &= bits - 1)
    {
      next |= this->Adjacency[size_t(__builtin_ctzll(bits))];
    }
    frontier = next & ~reached;
    reached |= next;
  }
  const unsigned long long all = n == 64 ? ~0ull : ((1ull << n) - 1);
  s.Connected = reached == all;
  // Three pairwise neighbours i < j (and a third common to both).
  for (size_t i = 0; i < n && !s.Cyclic; ++i)
  {
    const unsigned long long later = i == 63 ? 0ull : this->Adjacency[i] & (~0ull << (i + 1));
    for (unsigned long long bits = later; bits && !s.Cyclic; bits &= bits - 1)
    {
      s.Cyclic = (this->Adjacency[i] & this->Adjacency[size_t(__builtin_ctzll(bits))]) != 0;
    }
  }
}

// The region's boundary as one simple loop into s.BoundaryPolygon (emptied when it is not one);
// touchesT: a boundary edge has an end at a vertex of T.
bool StencilBuilder::TraceBoundaryPolygon(TriangleStencil& s, bool& touchesT)
{
  // Boundary edges by their start vertex: one loop needs exactly one leaving each vertex.
  const Index* tri = s.Vertices;
  const size_t m = this->EdgeFrom.size();
  touchesT = false;
  this->Outgoing.Reset(m);
  size_t boundaryCount = 0;
  bool simple = true;
  Index start = InvalidIndex;
  for (size_t i = 0; i < m; ++i)
  {
    if (this->EdgeBoundary[i])
    {
      ++boundaryCount;
      for (int k = 0; k < 3; ++k)
      {
        touchesT = touchesT || this->EdgeFrom[i] == tri[k] || this->EdgeTo[i] == tri[k];
      }
      start = start == InvalidIndex ? this->EdgeFrom[i] : start;
      bool inserted = false;
      std::int32_t& to = this->Outgoing.Find(static_cast<std::uint32_t>(this->EdgeFrom[i]), inserted);
      simple = simple && inserted; // else pinched
      to = this->EdgeTo[i];
    }
  }
  if (boundaryCount < 3)
  {
    return false; // closed region (the whole component) or degenerate
  }
  // Walk the boundary from the first edge found: with one edge leaving each vertex, getting back
  // to the start after exactly boundaryCount steps means one simple loop through all of them.
  Index v = start;
  for (size_t step = 0; step < boundaryCount && simple; ++step)
  {
    s.BoundaryPolygon.push_back(v);
    bool inserted = false;
    const std::int32_t to = this->Outgoing.Find(static_cast<std::uint32_t>(v), inserted);
    if (inserted)
    {
      simple = false; // (a vertex with no boundary edge leaving it; the entry is harmless)
      break;
    }
    v = to;
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
