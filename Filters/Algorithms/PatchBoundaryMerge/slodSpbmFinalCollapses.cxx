// SPDX-License-Identifier: BSD-3-Clause
#include "slodSpbmFinalCollapses.h"

#include "slodEditableMesh.h"
#include "slodIndexedHeap.h"
#include "slodMeshTopology.h"
#include "slodQuadric.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace slod
{
namespace
{
// The normal-turn bounds of the stages (cosines): the first keeps the level's shape where it can,
// the second lets the rough parts of a scan fold further before the target is given up.
constexpr double StageNormalDots[] = { 0.5, 0.0 };
// Planes through the border edges weigh this times the squared edge length: a border vertex moves
// along its border only, and only where the border is straight.
constexpr double BorderPlaneWeight = 4.0;
// Work bound: queue pops per stage at most this times the level's vertices (each pop either
// collapses, and then requeues the ring, or drops the vertex until a neighbour collapses).
constexpr long long PopsPerVertex = 32;

class FinalCollapser
{
public:
  FinalCollapser(const TriangleMesh& input, const SpbmLevel& level);
  // One stage with the given normal bound; returns false when its work bound stopped it.
  bool RunStage(double minimumNormalDot, Index target, SpbmFinalCollapseStatistics& statistics);
  Index LiveTriangles() const { return this->Mesh.NumberOfLiveTriangles(); }
  Index Vertices() const { return static_cast<Index>(this->InputOf.size()); }
  void WriteBack(SpbmLevel& level);

private:
  // The planes of `triangles` (over `mesh`) at their vertices; with `localOf`, the triangles are the
  // input's and only their vertices in the level take them (numbered by `localOf`).
  void AddPlanes(const TriangleMesh& mesh, const std::vector<Index>& triangles, const std::vector<Index>* localOf);
  void AddBorderPlanes(const TriangleMesh& levelMesh, const MeshTopology& topology);
  // The cheapest allowed target of u and its cost (InvalidIndex: none).
  std::pair<Index, double> Cheapest(Index u);
  void Requeue(Index u);
  bool Allowed(Index u, Index v) const;
  double Cost(Index u, Index v) const { return (this->Quadrics[u] + this->Quadrics[v]).Evaluate(this->Mesh.Point(v)); }
  bool TryCollapse(Index u, SpbmFinalCollapseStatistics& statistics);
  // The vertex v went to in the end; the walked path is shortened to it (path compression), so
  // resolving every curve vertex costs about one step each however long the collapse chains are.
  Index Resolve(Index v);

  EditableMesh Mesh;
  std::vector<Quadric> Quadrics;
  std::vector<unsigned char> Border, Locked;
  std::vector<Index> WentTo; // per vertex: the vertex it was collapsed into (InvalidIndex: alive)
  // The level's vertices: input id -> own (InvalidIndex: not in the level) and back.
  std::vector<Index> LocalOf, InputOf;
  IndexedHeap<double> Queue;
  CollapseOptions Options;
  std::vector<Index> Ring, RequeueRing, Scratch;
  std::vector<std::pair<double, Index>> Candidates;
};

FinalCollapser::FinalCollapser(const TriangleMesh& input, const SpbmLevel& level)
{
  // The level over its own vertices only, numbered in their input order (every tie, broken by
  // vertex id, breaks as over the input's numbering): its work follows the level, not the input
  // (a tenth of the input's vertices at 10%).
  this->LocalOf.assign(size_t(input.NumberOfPoints()), InvalidIndex);
  for (const Index v : level.Triangles)
  {
    this->LocalOf[size_t(v)] = 0;
  }
  TriangleMesh levelMesh;
  for (Index v = 0; v < input.NumberOfPoints(); ++v)
  {
    if (this->LocalOf[size_t(v)] != InvalidIndex)
    {
      this->LocalOf[size_t(v)] = static_cast<Index>(this->InputOf.size());
      this->InputOf.push_back(v);
      const Vec3 p = input.Point(v);
      levelMesh.Points.insert(levelMesh.Points.end(), p.begin(), p.end());
    }
  }
  levelMesh.Triangles.reserve(level.Triangles.size());
  for (const Index v : level.Triangles)
  {
    levelMesh.Triangles.push_back(this->LocalOf[size_t(v)]);
  }
  const MeshTopology topology(levelMesh);
  const Index n = levelMesh.NumberOfPoints();
  this->Border.assign(size_t(n), 0);
  this->Locked.assign(size_t(n), 0);
  for (Index v = 0; v < n; ++v)
  {
    this->Border[v] = topology.IsBoundaryVertex(v);
    // The link condition assumes one fan per vertex: non-manifold edges and pinch vertices stay.
    this->Locked[v] = topology.IsNonManifoldVertex(v);
  }
  this->Quadrics.assign(size_t(n), Quadric());
  this->AddPlanes(levelMesh, levelMesh.Triangles, nullptr);
  // The input's own planes at the kept vertices: the level's flat patches alone would call a
  // collapse free that moves the surface away from the input under them.
  this->AddPlanes(input, input.Triangles, &this->LocalOf);
  this->AddBorderPlanes(levelMesh, topology);
  this->WentTo.assign(size_t(n), InvalidIndex);
  this->Mesh.Reset(levelMesh);
  this->Options.AllowTopologyChange = false;
  this->Options.BoundaryVertices = this->Border.data();
  this->Options.LockedVertices = this->Locked.data();
  this->Options.GeometryFirst = true;
}

void FinalCollapser::AddPlanes(
  const TriangleMesh& mesh, const std::vector<Index>& triangles, const std::vector<Index>* localOf)
{
  for (size_t t = 0; t + 2 < triangles.size(); t += 3)
  {
    Index tri[3] = { triangles[t], triangles[t + 1], triangles[t + 2] };
    if (localOf)
    {
      // (The input's triangles away from the level's vertices, most of them, add nothing.)
      const Index* of = localOf->data();
      if (of[tri[0]] == InvalidIndex && of[tri[1]] == InvalidIndex && of[tri[2]] == InvalidIndex)
      {
        continue;
      }
    }
    Quadric q;
    if (!(TrianglePlaneQuadric(mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]), q) > 0))
    {
      continue;
    }
    for (Index v : tri)
    {
      v = localOf ? (*localOf)[size_t(v)] : v;
      if (v != InvalidIndex)
      {
        this->Quadrics[v] += q;
      }
    }
  }
}

void FinalCollapser::AddBorderPlanes(const TriangleMesh& levelMesh, const MeshTopology& topology)
{
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    if (!topology.IsBoundaryEdge(e))
    {
      continue;
    }
    const Index a = topology.EdgeVertex(e, 0), b = topology.EdgeVertex(e, 1);
    const Index* tri = levelMesh.Triangle(*topology.EdgeTrianglesBegin(e));
    const Vec3 p0 = levelMesh.Point(tri[0]);
    const Vec3 normal = Cross(levelMesh.Point(tri[1]) - p0, levelMesh.Point(tri[2]) - p0);
    Quadric q;
    if (BorderEdgeQuadric(levelMesh.Point(a), levelMesh.Point(b), Normalized(normal), BorderPlaneWeight, q))
    {
      this->Quadrics[a] += q;
      this->Quadrics[b] += q;
    }
  }
}

// A border vertex goes only along one of its border edges (its loop keeps its course); a locked
// vertex neither goes nor receives (CheckCollapse would refuse the set anyway).
bool FinalCollapser::Allowed(Index u, Index v) const
{
  if (this->Locked[u] || this->Locked[v])
  {
    return false;
  }
  return !this->Border[u] || this->Mesh.EdgeTriangleCount(u, v) == 1;
}

std::pair<Index, double> FinalCollapser::Cheapest(Index u)
{
  std::pair<Index, double> best(InvalidIndex, 0.0);
  if (this->Locked[u] || !this->Mesh.IsVertexAlive(u))
  {
    return best;
  }
  this->Mesh.Neighbors(u, this->Ring);
  for (const Index v : this->Ring)
  {
    if (!this->Allowed(u, v))
    {
      continue;
    }
    const double cost = this->Cost(u, v);
    if (best.first == InvalidIndex || cost < best.second || (cost == best.second && v < best.first))
    {
      best = { v, cost };
    }
  }
  return best;
}

void FinalCollapser::Requeue(Index u)
{
  const std::pair<Index, double> best = this->Cheapest(u);
  if (best.first == InvalidIndex)
  {
    this->Queue.Remove(u);
  }
  else
  {
    this->Queue.Set(u, best.second);
  }
}

// The allowed targets of u cheapest first; the first that keeps the topology and the normals wins.
bool FinalCollapser::TryCollapse(Index u, SpbmFinalCollapseStatistics& statistics)
{
  this->Candidates.clear();
  this->Mesh.Neighbors(u, this->Ring);
  for (const Index v : this->Ring)
  {
    if (this->Allowed(u, v))
    {
      this->Candidates.emplace_back(this->Cost(u, v), v);
    }
  }
  std::sort(this->Candidates.begin(), this->Candidates.end());
  for (const std::pair<double, Index>& candidate : this->Candidates)
  {
    const Index v = candidate.second;
    const Index pair[2] = { u, v };
    ++statistics.Attempts;
    const CollapseStatus status = this->Mesh.CheckCollapse(pair, 2, this->Mesh.Point(v), this->Options, this->Scratch);
    if (status != CollapseStatus::Ok)
    {
      ++statistics.Refused[static_cast<int>(status)];
      continue;
    }
    this->Mesh.Collapse(pair, 2, v, this->Mesh.Point(v), this->Scratch, nullptr);
    this->Quadrics[v] += this->Quadrics[u];
    this->WentTo[u] = v;
    ++statistics.Collapses;
    // Every former neighbour of u is now a neighbour of v, and only v's quadric changed: the
    // costs that moved are those of v and its ring.
    // (Requeue reuses Ring: the ring to walk goes in its own buffer, reused between collapses.)
    this->Mesh.Neighbors(v, this->RequeueRing);
    this->Requeue(v);
    for (const Index w : this->RequeueRing)
    {
      this->Requeue(w);
    }
    return true;
  }
  return false;
}

bool FinalCollapser::RunStage(double minimumNormalDot, Index target, SpbmFinalCollapseStatistics& statistics)
{
  this->Options.MinimumNormalDot = minimumNormalDot;
  const Index n = this->Mesh.NumberOfPoints();
  this->Queue.Reset(n);
  for (Index v = 0; v < n; ++v)
  {
    this->Requeue(v);
  }
  const long long maximumPops = PopsPerVertex * (static_cast<long long>(this->Mesh.NumberOfLiveVertices()) + 1);
  long long pops = 0;
  while (this->Mesh.NumberOfLiveTriangles() > target && !this->Queue.Empty())
  {
    if (++pops > maximumPops)
    {
      return false;
    }
    // Out of the queue either way: collapsed, or refused until a collapse next to it changes
    // its ring (TryCollapse requeues the ring).
    this->TryCollapse(this->Queue.Pop(), statistics);
  }
  return true;
}

Index FinalCollapser::Resolve(Index v)
{
  // Each step follows one collapse, so each walk is bounded by their number.
  Index root = v;
  while (this->WentTo[root] != InvalidIndex)
  {
    root = this->WentTo[root];
  }
  while (v != root)
  {
    const Index next = this->WentTo[v];
    this->WentTo[v] = root;
    v = next;
  }
  return root;
}

void FinalCollapser::WriteBack(SpbmLevel& level)
{
  // Triangles in their old order with their merged patch; patch ids renumbered densely.
  std::vector<Index> newPatch(size_t(level.NumberOfPatches), InvalidIndex);
  std::vector<Index> triangles, patches;
  for (Index t = 0; t < this->Mesh.NumberOfTriangles(); ++t)
  {
    if (this->Mesh.IsTriangleAlive(t))
    {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        triangles.push_back(this->InputOf[size_t(tri[k])]);
      }
      patches.push_back(level.TrianglePatch[t]);
      newPatch[level.TrianglePatch[t]] = 0;
    }
  }
  Index patchCount = 0;
  for (Index& p : newPatch)
  {
    p = p == InvalidIndex ? InvalidIndex : patchCount++;
  }
  for (Index& p : patches)
  {
    p = newPatch[p];
  }
  for (Index& p : level.MergedPatchOf)
  {
    p = p == InvalidIndex ? InvalidIndex : newPatch[p];
  }
  level.Triangles = std::move(triangles);
  level.TrianglePatch = std::move(patches);
  level.NumberOfPatches = patchCount;
  // Profile curves: a removed vertex becomes the one it went to (its edges did), repeats dropped.
  std::vector<Index> offsets(1, 0), vertices;
  for (size_t c = 0; c + 1 < level.CurveOffsets.size(); ++c)
  {
    const size_t start = vertices.size();
    for (Index i = level.CurveOffsets[c]; i < level.CurveOffsets[c + 1]; ++i)
    {
      // (A curve vertex outside the level's triangles stays itself, as it did.)
      const Index input = level.CurveVertices[i], local = this->LocalOf[size_t(input)];
      const Index v = local == InvalidIndex ? input : this->InputOf[size_t(this->Resolve(local))];
      if (vertices.size() == start || vertices.back() != v)
      {
        vertices.push_back(v);
      }
    }
    if (vertices.size() - start < 2)
    {
      vertices.resize(start);
      continue;
    }
    offsets.push_back(static_cast<Index>(vertices.size()));
  }
  level.CurveOffsets = std::move(offsets);
  level.CurveVertices = std::move(vertices);
}
} // namespace

void SpbmFinalCollapses(
  const TriangleMesh& mesh, Index target, SpbmLevel& level, SpbmFinalCollapseStatistics& statistics)
{
  statistics = SpbmFinalCollapseStatistics();
  statistics.StartTriangles = static_cast<Index>(level.TrianglePatch.size());
  const Index tolerance = SpbmFinalCollapseTolerance(target);
  if (target <= 0 || statistics.StartTriangles <= target + tolerance)
  {
    statistics.Reached = statistics.StartTriangles <= target + tolerance;
    return;
  }
  FinalCollapser collapser(mesh, level);
  statistics.Vertices = collapser.Vertices();
  for (const double normalDot : StageNormalDots)
  {
    ++statistics.Stages;
    if (!collapser.RunStage(normalDot, target, statistics))
    {
      statistics.WorkBoundReached = true;
    }
    if (collapser.LiveTriangles() <= target)
    {
      break;
    }
  }
  statistics.Reached = collapser.LiveTriangles() <= target + tolerance;
  collapser.WriteBack(level);
}
} // namespace slod
