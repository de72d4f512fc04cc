// SPDX-License-Identifier: BSD-3-Clause
#include "slodMeshTopology.h"

#include "slodHugePages.h"

#include "slodUnionFind.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <utility>

namespace slod
{
namespace
{
// Prefix sums turn per-bucket counts into CSR offsets (size n+1).
void CountsToOffsets(std::vector<Index>& offsets)
{
  Index running = 0;
  for (Index& o : offsets)
  {
    const Index c = o;
    o = running;
    running += c;
  }
}

Index FindRoot(std::vector<Index>& parent, Index x)
{
  while (parent[x] != x)
  {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Half-edges (id 3*t + k) bucketed by their smaller vertex: halfOffsets (np + 1 entries) and
// halfEdges, assigned within their capacity.
void BucketHalfEdges(
  const std::vector<Index>& tris, Index np, std::vector<Index>& halfOffsets, std::vector<Index>& halfEdges)
{
  halfOffsets.assign(size_t(np) + 1, 0);
  for (size_t i = 0; i < tris.size(); ++i)
  {
    const Index a = tris[i], b = tris[i - i % 3 + (i % 3 + 1) % 3];
    ++halfOffsets[std::min(a, b)];
  }
  CountsToOffsets(halfOffsets);
  AssignOnHugePages(halfEdges, tris.size(), Index(0));
  std::vector<Index> fill(halfOffsets.begin(), halfOffsets.end() - 1);
  for (size_t i = 0; i < tris.size(); ++i)
  {
    const Index a = tris[i], b = tris[i - i % 3 + (i % 3 + 1) % 3];
    halfEdges[fill[std::min(a, b)]++] = static_cast<Index>(i);
  }
}
} // namespace

void MeshTopology::Build(const TriangleMesh& mesh)
{
  this->Mesh = &mesh;
  this->NumPoints = mesh.NumberOfPoints();
  this->NumTriangles = mesh.NumberOfTriangles();
  const Index np = this->NumPoints;
  const Index nt = this->NumTriangles;
  const std::vector<Index>& tris = mesh.Triangles;

  // Vertex -> triangles.
  // The arrays sized by the triangles on huge pages: fewer first-touch page faults (session 32).
  AssignOnHugePages(this->VertexOffsets, size_t(np) + 1, Index(0));
  for (Index v : tris)
  {
    ++this->VertexOffsets[v];
  }
  CountsToOffsets(this->VertexOffsets);
  AssignOnHugePages(this->VertexTriangles, tris.size(), Index(0));
  {
    std::vector<Index> fill(this->VertexOffsets.begin(), this->VertexOffsets.end() - 1);
    for (Index t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->VertexTriangles[fill[tris[3 * size_t(t) + k]]++] = t;
      }
    }
  }

  // Unique edges: bucket half-edges by their smaller vertex, dedupe with a per-vertex stamp. The
  // buckets use the room of EdgeTriangles (3 per triangle too, filled once they are done): a
  // topology built again allocates no array for them (vtkHoleBumpRemoval's passes, session 36).
  std::vector<Index> halfOffsets, halfEdges(std::move(this->EdgeTriangles));
  BucketHalfEdges(tris, np, halfOffsets, halfEdges);
  this->EdgeVertices.clear();
  ReserveOnHugePages(this->EdgeVertices, tris.size()); // about 1.5 edges per triangle, two indices each
  AssignOnHugePages(this->TriangleEdges, tris.size(), InvalidIndex);
  std::vector<Index> stamp(np, InvalidIndex), stampEdge(np, InvalidIndex);
  for (Index u = 0; u < np; ++u)
  {
    for (Index h = halfOffsets[u]; h < halfOffsets[u + 1]; ++h)
    {
      const size_t i = size_t(halfEdges[h]);
      const Index a = tris[i], b = tris[i - i % 3 + (i % 3 + 1) % 3];
      const Index w = std::max(a, b);
      if (stamp[w] != u)
      {
        stamp[w] = u;
        stampEdge[w] = static_cast<Index>(this->EdgeVertices.size() / 2);
        this->EdgeVertices.push_back(u);
        this->EdgeVertices.push_back(w);
      }
      this->TriangleEdges[i] = stampEdge[w];
    }
  }
  const Index ne = this->NumberOfEdges();
  this->EdgeTriangles.swap(halfEdges);

  // Edge -> triangles.
  this->EdgeOffsets.assign(size_t(ne) + 1, 0);
  for (Index e : this->TriangleEdges)
  {
    ++this->EdgeOffsets[e];
  }
  CountsToOffsets(this->EdgeOffsets);
  AssignOnHugePages(this->EdgeTriangles, tris.size(), Index(0));
  {
    std::vector<Index> fill(this->EdgeOffsets.begin(), this->EdgeOffsets.end() - 1);
    for (size_t i = 0; i < tris.size(); ++i)
    {
      this->EdgeTriangles[fill[this->TriangleEdges[i]]++] = static_cast<Index>(i / 3);
    }
  }

  // Valence and vertex classification.
  this->ValenceOf.assign(np, 0);
  this->VertexFlags.assign(np, 0);
  for (Index e = 0; e < ne; ++e)
  {
    const Index a = this->EdgeVertex(e, 0), b = this->EdgeVertex(e, 1);
    ++this->ValenceOf[a];
    ++this->ValenceOf[b];
    const Index count = this->EdgeTriangleCount(e);
    if (count == 1)
    {
      this->VertexFlags[a] |= BoundaryFlag;
      this->VertexFlags[b] |= BoundaryFlag;
    }
    else if (count > 2)
    {
      this->VertexFlags[a] |= NonManifoldFlag;
      this->VertexFlags[b] |= NonManifoldFlag;
    }
  }
  // A vertex whose triangles form several fans (a "bow tie") is non-manifold too.
  // For one fan, triangles = link edges and link vertices = triangles (closed) or +1 (open),
  // and a walk from one triangle reaches all of them.
  std::vector<Index> ring, fan;
  for (Index v = 0; v < np; ++v)
  {
    if (this->VertexDegree(v) == 0 || (this->VertexFlags[v] & NonManifoldFlag))
    {
      continue;
    }
    if (!this->OrderedOneRing(mesh, v, ring, fan) || Index(fan.size()) != this->VertexDegree(v))
    {
      this->VertexFlags[v] |= NonManifoldFlag;
    }
  }

  this->BuildComponents();
}

void MeshTopology::BuildComponents() const
{
  const Index nt = this->NumTriangles;
  const Index ne = this->NumberOfEdges();
  // Edge-connected components.
  std::vector<Index> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  for (Index e = 0; e < ne; ++e)
  {
    const Index* begin = this->EdgeTrianglesBegin(e);
    for (const Index* t = begin + 1; t < this->EdgeTrianglesEnd(e); ++t)
    {
      const Index ra = FindRoot(parent, *begin), rb = FindRoot(parent, *t);
      if (ra != rb)
      {
        parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  this->TriangleComponent.assign(nt, InvalidIndex);
  std::vector<Index> rootLabel(nt, InvalidIndex);
  this->ComponentCount = 0;
  for (Index t = 0; t < nt; ++t)
  {
    const Index r = FindRoot(parent, t);
    if (rootLabel[r] == InvalidIndex)
    {
      rootLabel[r] = this->ComponentCount++;
    }
    this->TriangleComponent[t] = rootLabel[r];
  }
  this->ComponentsStale = false;
}

void MeshTopology::ReleaseUpdateBuffers()
{
  this->Buffers = Spare();
}

void MeshTopology::Update(
  const std::vector<Index>& previousTriangles, const std::vector<unsigned char>& removed, const TriangleMesh& mesh)
{
  const Index nto = this->NumTriangles;
  const Index np = this->NumPoints;
  const Index ntn = mesh.NumberOfTriangles();
  Index removedCount = 0;
  for (const unsigned char r : removed)
  {
    removedCount += r != 0;
  }
  if (mesh.NumberOfPoints() != np || this->VertexOffsets.size() != size_t(np) + 1 ||
    (!removed.empty() && (removed.size() != size_t(nto) || previousTriangles.size() < 3 * size_t(nto))) ||
    ntn < nto - removedCount)
  {
    this->Build(mesh); // not an edit of the indexed mesh
    this->UpdateWork = MeshTopologyUpdateWork();
    this->UpdateWork.LocalIncidences = 3 * std::int64_t(ntn);
    return;
  }
  Spare& b = this->Buffers;
  // New triangle ids: the kept triangles keep their order, the appended ones follow.
  b.NewId.resize(size_t(nto));
  Index kept = 0;
  for (Index t = 0; t < nto; ++t)
  {
    b.NewId[t] = !removed.empty() && removed[t] ? InvalidIndex : kept++;
  }
  // Touched vertices: those of the removed and of the appended triangles. Only their incidences,
  // edges, valences and flags can differ from the previous topology's.
  if (b.Touched.size() != size_t(np))
  {
    b.Touched.assign(size_t(np), 0);
  }
  std::vector<Index> touched;
  auto touch = [&](Index v) {
    if (!b.Touched[v])
    {
      b.Touched[v] = 1;
      touched.push_back(v);
    }
  };
  for (Index t = 0; t < nto && removedCount > 0; ++t)
  {
    if (removed[t])
    {
      for (int k = 0; k < 3; ++k)
      {
        touch(previousTriangles[3 * size_t(t) + k]);
      }
    }
  }
  for (size_t i = 3 * size_t(kept); i < mesh.Triangles.size(); ++i)
  {
    touch(mesh.Triangles[i]);
  }
  std::sort(touched.begin(), touched.end());
  this->UpdateWork = MeshTopologyUpdateWork();
  this->UpdateWork.RemovedTriangles = removedCount;
  this->UpdateWork.AppendedTriangles = ntn - kept;
  this->UpdateWork.TouchedVertices = static_cast<std::int64_t>(touched.size());
  for (const Index v : touched)
  {
    this->UpdateWork.LocalIncidences += this->VertexDegree(v);
  }
  this->UpdateVertexTriangles(previousTriangles, removed, mesh, touched);
  this->UpdateEdges(mesh);
  this->UpdateVertexFlags(mesh, touched);
  for (const Index v : touched)
  {
    b.Touched[v] = 0;
  }
  this->NumTriangles = ntn;
  this->Mesh = &mesh;
  this->ComponentsStale = true;
}

void MeshTopology::UpdateVertexTriangles(const std::vector<Index>& previousTriangles,
  const std::vector<unsigned char>& removed, const TriangleMesh& mesh, const std::vector<Index>& touched)
{
  Spare& b = this->Buffers;
  const Index np = this->NumPoints;
  const Index nto = this->NumTriangles;
  const Index first = static_cast<Index>(mesh.NumberOfTriangles() - this->UpdateWork.AppendedTriangles);
  std::vector<Index>& offsets = b.VertexOffsets;
  AssignOnHugePages(offsets, size_t(np) + 1, Index(0));
  for (Index v = 0; v < np; ++v)
  {
    offsets[v] = this->VertexDegree(v);
  }
  for (Index t = 0; t < nto && this->UpdateWork.RemovedTriangles > 0; ++t)
  {
    for (int k = 0; k < 3 && removed[t]; ++k)
    {
      --offsets[previousTriangles[3 * size_t(t) + k]];
    }
  }
  for (size_t i = 3 * size_t(first); i < mesh.Triangles.size(); ++i)
  {
    ++offsets[mesh.Triangles[i]];
  }
  CountsToOffsets(offsets);
  // Each list: its kept triangles renumbered (still ascending), then the appended ones.
  std::vector<Index>& lists = b.VertexTriangles;
  AssignOnHugePages(lists, size_t(offsets[np]), Index(0));
  for (Index v = 0; v < np; ++v)
  {
    Index write = offsets[v];
    for (const Index* t = this->VertexTrianglesBegin(v); t != this->VertexTrianglesEnd(v); ++t)
    {
      const Index id = b.NewId[*t];
      if (id != InvalidIndex)
      {
        lists[write++] = id;
      }
    }
  }
  // The appended triangles from each touched list's end backwards: they come out ascending.
  std::vector<Index> end(touched.size());
  for (size_t i = 0; i < touched.size(); ++i)
  {
    end[i] = offsets[touched[i] + 1];
  }
  for (Index t = mesh.NumberOfTriangles() - 1; t >= first; --t)
  {
    for (int k = 2; k >= 0; --k)
    {
      const Index v = mesh.Triangles[3 * size_t(t) + k];
      const size_t i = size_t(std::lower_bound(touched.begin(), touched.end(), v) - touched.begin());
      lists[--end[i]] = t;
    }
  }
  this->UpdateWork.CarriedEntries += static_cast<std::int64_t>(this->VertexTriangles.size());
  this->VertexOffsets.swap(offsets);
  this->VertexTriangles.swap(lists);
  for (const Index v : touched)
  {
    this->UpdateWork.LocalIncidences += this->VertexDegree(v);
  }
}

void MeshTopology::UpdateEdges(const TriangleMesh& mesh)
{
  Spare& b = this->Buffers;
  const Index np = this->NumPoints;
  const Index nto = this->NumTriangles;
  const Index oldEdges = this->NumberOfEdges();
  const std::vector<Index>& tris = mesh.Triangles;
  const size_t appended = size_t(this->UpdateWork.AppendedTriangles);
  std::vector<Index>& vertices = b.EdgeVertices;
  vertices.clear();
  ReserveOnHugePages(vertices, this->EdgeVertices.size() + 6 * appended);
  std::vector<Index>& offsets = b.EdgeOffsets;
  offsets.clear();
  ReserveOnHugePages(offsets, size_t(oldEdges) + 1 + 3 * appended);
  std::vector<Index>& lists = b.EdgeTriangles;
  AssignOnHugePages(lists, tris.size(), Index(0));
  std::vector<Index>& edgeOf = b.TriangleEdges;
  AssignOnHugePages(edgeOf, tris.size(), InvalidIndex);
  b.EdgeShift.resize(size_t(np));
  if (b.Stamp.size() != size_t(np))
  {
    b.Stamp.assign(size_t(np), InvalidIndex);
    b.StampEdge.assign(size_t(np), InvalidIndex);
  }
  // Edges by smaller vertex u, each u's in the order of their first half-edge, as Build numbers
  // them. An untouched u keeps its edges and their triangles (renumbered); a touched u's are
  // found again from its triangles, which list its half-edges in half-edge order.
  std::vector<std::pair<Index, Index>> halves; // (edge, triangle) of a touched u's half-edges
  std::vector<Index> fill;
  Index oldEdge = 0, write = 0;
  for (Index u = 0; u < np; ++u)
  {
    const Index oldBegin = oldEdge;
    while (oldEdge < oldEdges && this->EdgeVertices[2 * size_t(oldEdge)] == u)
    {
      ++oldEdge;
    }
    const Index newBegin = static_cast<Index>(vertices.size() / 2);
    if (!b.Touched[u])
    {
      b.EdgeShift[u] = newBegin - oldBegin;
      for (Index e = oldBegin; e < oldEdge; ++e)
      {
        vertices.push_back(u);
        vertices.push_back(this->EdgeVertices[2 * size_t(e) + 1]);
        offsets.push_back(write);
        for (const Index* t = this->EdgeTrianglesBegin(e); t != this->EdgeTrianglesEnd(e); ++t)
        {
          lists[write++] = b.NewId[*t];
        }
      }
      continue;
    }
    halves.clear();
    Index previous = InvalidIndex;
    for (const Index* t = this->VertexTrianglesBegin(u); t != this->VertexTrianglesEnd(u); ++t)
    {
      if (*t == previous)
      {
        continue; // u twice in one (degenerate) triangle
      }
      previous = *t;
      for (int k = 0; k < 3; ++k)
      {
        const Index a = tris[3 * size_t(*t) + k], c = tris[3 * size_t(*t) + (k + 1) % 3];
        if (std::min(a, c) != u)
        {
          continue;
        }
        const Index w = std::max(a, c);
        if (b.Stamp[w] != u)
        {
          b.Stamp[w] = u;
          b.StampEdge[w] = static_cast<Index>(vertices.size() / 2);
          vertices.push_back(u);
          vertices.push_back(w);
        }
        edgeOf[3 * size_t(*t) + k] = b.StampEdge[w];
        halves.emplace_back(b.StampEdge[w], *t);
      }
    }
    const Index count = static_cast<Index>(vertices.size() / 2) - newBegin;
    fill.assign(size_t(count) + 1, 0);
    for (const auto& h : halves)
    {
      ++fill[h.first - newBegin];
      b.Stamp[vertices[2 * size_t(h.first) + 1]] = InvalidIndex; // clean for the next update
    }
    CountsToOffsets(fill);
    for (Index j = 0; j < count; ++j)
    {
      offsets.push_back(write + fill[j]);
    }
    for (const auto& h : halves)
    {
      lists[write + fill[h.first - newBegin]++] = h.second;
    }
    write += static_cast<Index>(halves.size());
    this->UpdateWork.LocalIncidences += static_cast<std::int64_t>(halves.size());
  }
  offsets.push_back(write);
  // The half-edges of untouched vertices: their edge shifted with its smaller vertex's edges.
  for (Index t = 0; t < nto; ++t)
  {
    const Index id = b.NewId[t];
    for (int k = 0; k < 3 && id != InvalidIndex; ++k)
    {
      const Index a = tris[3 * size_t(id) + k], c = tris[3 * size_t(id) + (k + 1) % 3];
      const Index u = std::min(a, c);
      if (!b.Touched[u])
      {
        edgeOf[3 * size_t(id) + k] = this->TriangleEdges[3 * size_t(t) + k] + b.EdgeShift[u];
      }
    }
  }
  this->UpdateWork.CarriedEntries += static_cast<std::int64_t>(
    this->EdgeVertices.size() + this->EdgeOffsets.size() + this->EdgeTriangles.size() + this->TriangleEdges.size());
  this->EdgeVertices.swap(vertices);
  this->EdgeOffsets.swap(offsets);
  this->EdgeTriangles.swap(lists);
  this->TriangleEdges.swap(edgeOf);
}

void MeshTopology::UpdateVertexFlags(const TriangleMesh& mesh, const std::vector<Index>& touched)
{
  // As Build: valence and border / non-manifold flags from the incident edges, then the fan test.
  std::vector<Index> incident;
  for (const Index v : touched)
  {
    incident.clear();
    for (const Index* t = this->VertexTrianglesBegin(v); t != this->VertexTrianglesEnd(v); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index e = this->TriangleEdge(*t, k);
        if (this->EdgeVertex(e, 0) == v || this->EdgeVertex(e, 1) == v)
        {
          incident.push_back(e);
        }
      }
    }
    std::sort(incident.begin(), incident.end());
    incident.erase(std::unique(incident.begin(), incident.end()), incident.end());
    Index valence = 0;
    unsigned char flags = 0;
    for (const Index e : incident)
    {
      valence += this->EdgeVertex(e, 0) == this->EdgeVertex(e, 1) ? 2 : 1;
      const Index count = this->EdgeTriangleCount(e);
      flags |= count == 1 ? BoundaryFlag : (count > 2 ? NonManifoldFlag : 0);
    }
    this->ValenceOf[v] = valence;
    this->VertexFlags[v] = flags;
  }
  std::vector<Index> ring, fan;
  for (const Index v : touched)
  {
    if (this->VertexDegree(v) == 0 || (this->VertexFlags[v] & NonManifoldFlag))
    {
      continue;
    }
    if (!this->OrderedOneRing(mesh, v, ring, fan) || Index(fan.size()) != this->VertexDegree(v))
    {
      this->VertexFlags[v] |= NonManifoldFlag;
    }
    this->UpdateWork.LocalIncidences += this->VertexDegree(v);
  }
}

Index MeshTopology::FindEdge(Index u, Index v) const
{
  for (const Index* t = this->VertexTrianglesBegin(u); t != this->VertexTrianglesEnd(u); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index e = this->TriangleEdge(*t, k);
      const Index a = this->EdgeVertex(e, 0), b = this->EdgeVertex(e, 1);
      if ((a == u && b == v) || (a == v && b == u))
      {
        return e;
      }
    }
  }
  return InvalidIndex;
}

Index MeshTopology::EdgeNeighbor(Index t, int k) const
{
  const Index e = this->TriangleEdge(t, k);
  if (this->EdgeTriangleCount(e) != 2)
  {
    return InvalidIndex;
  }
  const Index* tt = this->EdgeTrianglesBegin(e);
  return tt[0] == t ? tt[1] : tt[0];
}

bool MeshTopology::OrderedOneRing(
  const TriangleMesh& mesh, Index v, std::vector<Index>& ring, std::vector<Index>& triangles) const
{
  ring.clear();
  triangles.clear();
  const Index degree = this->VertexDegree(v);
  if (degree == 0 || this->IsNonManifoldVertex(v))
  {
    return degree == 0;
  }
  // Corner of v in triangle t.
  auto corner = [&](Index t) {
    const Index* tri = mesh.Triangle(t);
    return tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
  };
  // Walk clockwise (across the edge before v) to find the start of an open fan.
  Index start = *this->VertexTrianglesBegin(v);
  if (this->IsBoundaryVertex(v))
  {
    // Across the edge (v, next).
    start = FanStart(start, degree, [&](Index t) { return this->EdgeNeighbor(t, corner(t)); });
  }
  // Walk counter-clockwise across the edge after v: ring[i] is the vertex after v in triangles[i].
  Index t = start;
  for (Index steps = 0; steps < degree; ++steps)
  {
    const Index* tri = mesh.Triangle(t);
    const int c = corner(t);
    ring.push_back(tri[(c + 1) % 3]);
    triangles.push_back(t);
    const Index next = this->EdgeNeighbor(t, (c + 2) % 3);
    if (next == InvalidIndex)
    {
      ring.push_back(tri[(c + 2) % 3]);
      break;
    }
    if (next == start)
    {
      break;
    }
    // The shared edge must run the other way in the neighbour (consistent orientation).
    t = next;
  }
  return true;
}

Index MeshTopology::BorderComponentCount() const
{
  UnionFind sets(this->NumPoints);
  std::vector<char> onBorder(size_t(this->NumPoints), 0);
  for (Index e = 0; e < this->NumberOfEdges(); ++e)
  {
    if (this->IsBoundaryEdge(e))
    {
      const Index a = this->EdgeVertex(e, 0), b = this->EdgeVertex(e, 1);
      onBorder[a] = onBorder[b] = 1;
      sets.Union(a, b);
    }
  }
  Index count = 0;
  for (Index v = 0; v < this->NumPoints; ++v)
  {
    count += onBorder[v] && sets.Find(v) == v ? 1 : 0;
  }
  return count;
}

std::vector<std::vector<Index>> MeshTopology::BoundaryLoops() const
{
  std::vector<std::vector<Index>> loops;
  if (!this->Mesh)
  {
    return loops;
  }
  const TriangleMesh& mesh = *this->Mesh;
  // Boundary half-edges a->b in triangle order; chain them by their start vertex.
  std::vector<Index> outOffsets(size_t(this->NumPoints) + 1, 0);
  std::vector<Index> halfTo;
  for (Index t = 0; t < this->NumTriangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (this->IsBoundaryEdge(this->TriangleEdge(t, k)))
      {
        ++outOffsets[mesh.Triangle(t)[k]];
      }
    }
  }
  CountsToOffsets(outOffsets);
  halfTo.resize(outOffsets.back());
  std::vector<Index> fill(outOffsets.begin(), outOffsets.end() - 1);
  for (Index t = 0; t < this->NumTriangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (this->IsBoundaryEdge(this->TriangleEdge(t, k)))
      {
        halfTo[fill[mesh.Triangle(t)[k]]++] = mesh.Triangle(t)[(k + 1) % 3];
      }
    }
  }
  std::vector<char> used(halfTo.size(), 0);
  for (Index v = 0; v < this->NumPoints; ++v)
  {
    for (Index h = outOffsets[v]; h < outOffsets[v + 1]; ++h)
    {
      if (used[h])
      {
        continue;
      }
      std::vector<Index> loop;
      Index cur = h, from = v;
      while (cur != InvalidIndex && !used[cur])
      {
        used[cur] = 1;
        loop.push_back(from);
        from = halfTo[cur];
        cur = InvalidIndex;
        for (Index g = outOffsets[from]; g < outOffsets[from + 1]; ++g)
        {
          if (!used[g])
          {
            cur = g;
            break;
          }
        }
      }
      loops.push_back(std::move(loop));
    }
  }
  return loops;
}

MeshStatistics MeshTopology::Statistics(const TriangleMesh& mesh) const
{
  MeshStatistics s;
  s.Triangles = this->NumTriangles;
  s.Edges = this->NumberOfEdges();
  for (Index v = 0; v < this->NumPoints; ++v)
  {
    if (this->VertexDegree(v) > 0)
    {
      ++s.Vertices;
      s.NonManifoldVertices += this->IsNonManifoldVertex(v) ? 1 : 0;
    }
  }
  for (Index e = 0; e < s.Edges; ++e)
  {
    const Index count = this->EdgeTriangleCount(e);
    s.BoundaryEdges += count == 1 ? 1 : 0;
    s.NonManifoldEdges += count > 2 ? 1 : 0;
    if (count == 2)
    {
      // Both triangles must traverse the edge in opposite directions.
      const Index a = this->EdgeVertex(e, 0);
      int forward = 0;
      for (const Index* t = this->EdgeTrianglesBegin(e); t != this->EdgeTrianglesEnd(e); ++t)
      {
        const Index* tri = mesh.Triangle(*t);
        for (int k = 0; k < 3; ++k)
        {
          if (this->TriangleEdge(*t, k) == e && tri[k] == a)
          {
            ++forward;
          }
        }
      }
      s.InconsistentlyOrientedEdges += forward != 1 ? 1 : 0;
    }
  }
  for (Index t = 0; t < this->NumTriangles; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
      IsDegenerate(mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2])))
    {
      ++s.DegenerateTriangles;
    }
  }
  s.Components = this->NumberOfComponents();
  s.BoundaryLoops = this->BorderComponentCount();
  s.EulerCharacteristic = static_cast<long long>(s.Vertices) - s.Edges + s.Triangles;
  const long long twiceGenus = 2LL * s.Components - s.EulerCharacteristic - s.BoundaryLoops;
  if (s.NonManifoldEdges == 0 && s.NonManifoldVertices == 0 && s.InconsistentlyOrientedEdges == 0 &&
    twiceGenus >= 0 && twiceGenus % 2 == 0)
  {
    s.Genus = twiceGenus / 2;
  }
  return s;
}

MeshStatistics ComputeMeshStatistics(const TriangleMesh& mesh)
{
  MeshTopology topology(mesh);
  return topology.Statistics(mesh);
}

double MeanAbsoluteCurvature(const TriangleMesh& mesh, const MeshTopology& topology, double creaseAngle)
{
  // The edges' terms (two normals and an atan2 each: a third of a second on a 2M-triangle scan)
  // are computed over threads, then summed in edge order: the same sum, bit for bit, as one loop.
  const Index ne = topology.NumberOfEdges();
  std::vector<double> terms(static_cast<size_t>(ne), 0.0);
  vtkSMPTools::For(0, vtkIdType(ne), 16384, [&](vtkIdType first, vtkIdType last) {
    for (Index e = Index(first); e < Index(last); ++e)
    {
      if (topology.EdgeTriangleCount(e) != 2)
      {
        continue;
      }
      const Index* t = topology.EdgeTrianglesBegin(e);
      const Vec3 n0 = Normalized(mesh.TriangleAreaVector(t[0]));
      const Vec3 n1 = Normalized(mesh.TriangleAreaVector(t[1]));
      const double angle = std::atan2(Norm(Cross(n0, n1)), Dot(n0, n1));
      if (!(angle > creaseAngle)) // as the serial loop did, NaN included
      {
        terms[size_t(e)] =
          angle * Norm(mesh.Point(topology.EdgeVertex(e, 1)) - mesh.Point(topology.EdgeVertex(e, 0)));
      }
    }
  });
  double bending = 0;
  for (const double term : terms)
  {
    bending += term;
  }
  const double area = mesh.TotalArea();
  return area > 0 ? bending / (2 * area) : 0.0;
}

namespace
{
// The vertex of triangle `tri` that is not on edge (a, b).
Index ThirdVertex(const Index* tri, Index a, Index b)
{
  return tri[0] != a && tri[0] != b ? tri[0] : (tri[1] != a && tri[1] != b ? tri[1] : tri[2]);
}
}

double NoisyBendShare(const TriangleMesh& mesh, const MeshTopology& topology, double angle, double planeDistance)
{
  // One O(1) test per edge, over threads; the counts are integers, so their sum does not depend
  // on the split.
  const double cosine = std::cos(angle);
  const Index ne = topology.NumberOfEdges();
  std::atomic<long long> interior{ 0 }, noisy{ 0 };
  vtkSMPTools::For(0, vtkIdType(ne), 16384, [&](vtkIdType first, vtkIdType last) {
    long long inner = 0, bends = 0;
    for (Index e = Index(first); e < Index(last); ++e)
    {
      if (topology.EdgeTriangleCount(e) != 2)
      {
        continue;
      }
      ++inner;
      const Index* t = topology.EdgeTrianglesBegin(e);
      const Vec3 n0 = Normalized(mesh.TriangleAreaVector(t[0]));
      const Vec3 n1 = Normalized(mesh.TriangleAreaVector(t[1]));
      if (!(Dot(n0, n1) < cosine))
      {
        continue;
      }
      const Index a = topology.EdgeVertex(e, 0), b = topology.EdgeVertex(e, 1);
      const Vec3 p = mesh.Point(a);
      const double d0 = std::fabs(Dot(n1, mesh.Point(ThirdVertex(mesh.Triangle(t[0]), a, b)) - p));
      const double d1 = std::fabs(Dot(n0, mesh.Point(ThirdVertex(mesh.Triangle(t[1]), a, b)) - p));
      bends += d0 <= planeDistance && d1 <= planeDistance;
    }
    interior += inner;
    noisy += bends;
  });
  return interior > 0 ? double(noisy) / double(interior) : 0.0;
}
} // namespace slod
