// SPDX-License-Identifier: BSD-3-Clause
#include "slodZeroLengthEdges.h"

#include "slodEditableMesh.h"
#include "slodInputPreparation.h"
#include "slodUnionFind.h"

#include <algorithm>

namespace slod
{
namespace
{
// The edges (a, b), a < b, whose ends have the same coordinates, once each, in ascending order.
std::vector<std::uint64_t> ZeroLengthEdges(const TriangleMesh& mesh)
{
  std::vector<std::uint64_t> edges;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index a = tri[k], b = tri[(k + 1) % 3];
      if (a != b && mesh.Point(a) == mesh.Point(b))
      {
        edges.push_back(EdgeKey(a, b));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// A collapse that moves nothing cannot fold or thin a triangle: only the topology can refuse it
// (CheckCollapse tests the topology first, so a geometric status means the topology passed).
bool TopologyAllows(CollapseStatus status)
{
  return status == CollapseStatus::Ok || status == CollapseStatus::Flip || status == CollapseStatus::Degenerate ||
    status == CollapseStatus::BadShape;
}

template <typename T>
void KeepLive(std::vector<T>& values, const std::vector<unsigned char>& live)
{
  size_t kept = 0;
  for (size_t i = 0; i < values.size(); ++i)
  {
    if (live[i])
    {
      values[kept++] = values[i];
    }
  }
  values.resize(kept);
}

// The merged mesh: live vertices in their old order, live triangles in theirs; the maps follow.
void CompactMerged(const EditableMesh& edit, TriangleMesh& mesh, const ZeroLengthEdgeMaps& maps)
{
  const Index nv = edit.NumberOfPoints(), nt = edit.NumberOfTriangles();
  std::vector<unsigned char> liveVertex(static_cast<size_t>(nv)), liveTriangle(static_cast<size_t>(nt));
  std::vector<Index> oldToNew(size_t(nv), InvalidIndex);
  TriangleMesh merged;
  for (Index v = 0; v < nv; ++v)
  {
    liveVertex[v] = edit.IsVertexAlive(v) ? 1 : 0;
    oldToNew[v] = liveVertex[v] ? merged.AddPoint(edit.Point(v)) : InvalidIndex;
  }
  for (Index t = 0; t < nt; ++t)
  {
    liveTriangle[t] = edit.IsTriangleAlive(t) ? 1 : 0;
    if (liveTriangle[t])
    {
      const Index* tri = edit.Triangle(t);
      merged.AddTriangle(oldToNew[tri[0]], oldToNew[tri[1]], oldToNew[tri[2]]);
    }
  }
  mesh = std::move(merged);
  KeepLive(*maps.VertexToInputPoint, liveVertex);
  for (std::vector<unsigned char>* flags : { maps.NonManifoldFlags, maps.BorderFlags })
  {
    if (flags)
    {
      KeepLive(*flags, liveVertex);
    }
  }
  if (maps.TriangleToInputCell && !maps.TriangleToInputCell->empty())
  {
    KeepLive(*maps.TriangleToInputCell, liveTriangle);
  }
}
} // namespace

Index CollapseZeroLengthEdges(TriangleMesh& mesh, const ZeroLengthEdgeMaps& maps)
{
  const std::vector<std::uint64_t> edges = ZeroLengthEdges(mesh);
  if (edges.empty())
  {
    return 0;
  }
  const std::vector<unsigned char> computed = maps.NonManifoldFlags ? std::vector<unsigned char>() : NonManifoldVertexFlags(mesh);
  const std::vector<unsigned char>& nonManifold = maps.NonManifoldFlags ? *maps.NonManifoldFlags : computed;
  EditableMesh edit(mesh);
  CollapseOptions options;
  options.LockedVertices = nonManifold.data();
  options.BoundaryVertices = maps.BorderFlags ? maps.BorderFlags->data() : nullptr;
  // The vertex each one went into: the root of its set, the smallest member, which is the end
  // every collapse keeps.
  UnionFind merged(mesh.NumberOfPoints());
  const std::vector<Index>& inputPoint = *maps.VertexToInputPoint;
  Index count = 0;
  for (std::uint64_t key : edges)
  {
    const Index a = merged.Find(static_cast<Index>(key >> 32)), b = merged.Find(static_cast<Index>(key & 0xffffffffu));
    if (a == b || (maps.MayMerge && !maps.MayMerge(inputPoint[a], inputPoint[b])))
    {
      continue;
    }
    const Index pair[2] = { std::min(a, b), std::max(a, b) };
    if (!TopologyAllows(edit.CheckCollapse(pair, 2, edit.Point(pair[0]), options)))
    {
      continue;
    }
    edit.Collapse(pair, 2, pair[0], edit.Point(pair[0]));
    merged.Union(pair[0], pair[1]);
    if (maps.BorderFlags)
    {
      (*maps.BorderFlags)[pair[0]] |= (*maps.BorderFlags)[pair[1]];
    }
    ++count;
  }
  if (count > 0)
  {
    CompactMerged(edit, mesh, maps);
  }
  return count;
}
} // namespace slod
