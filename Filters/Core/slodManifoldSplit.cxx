// SPDX-License-Identifier: BSD-3-Clause
#include "slodManifoldSplit.h"

#include "slodUnionFind.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace slod
{
namespace
{
// Corners: 3 per triangle; corner 3t + k is vertex k of triangle t.
Index CornerOf(const TriangleMesh& mesh, Index t, Index v)
{
  const Index* tri = mesh.Triangle(t);
  const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
  return 3 * t + k;
}

bool UsesForward(const Index* tri, Index u, Index v)
{
  return (tri[0] == u && tri[1] == v) || (tri[1] == u && tri[2] == v) || (tri[2] == u && tri[0] == v);
}

Index ThirdVertex(const Index* tri, Index u, Index v)
{
  return tri[0] != u && tri[0] != v ? tri[0] : (tri[1] != u && tri[1] != v ? tri[1] : tri[2]);
}

struct EdgeFan
{
  double Angle;
  Index Triangle;
  bool Forward; // uses the edge from its smaller to its larger vertex
  bool operator<(const EdgeFan& o) const
  {
    return this->Angle < o.Angle || (this->Angle == o.Angle && this->Triangle < o.Triangle);
  }
};

// The triangles around edge e in counter-clockwise order about the axis from its first to its
// second vertex.
std::vector<EdgeFan> SortAroundEdge(const TriangleMesh& mesh, const MeshTopology& topology, Index e)
{
  const Index u = topology.EdgeVertex(e, 0), v = topology.EdgeVertex(e, 1);
  const Vec3 origin = mesh.Point(u);
  const Vec3 axis = Normalized(mesh.Point(v) - origin);
  const Vec3 first = AnyOrthogonal(axis);
  const Vec3 second = Cross(axis, first);
  std::vector<EdgeFan> fans;
  for (const Index* t = topology.EdgeTrianglesBegin(e); t != topology.EdgeTrianglesEnd(e); ++t)
  {
    const Index* tri = mesh.Triangle(*t);
    const Vec3 d = mesh.Point(ThirdVertex(tri, u, v)) - origin;
    fans.push_back({ std::atan2(Dot(d, second), Dot(d, first)), *t, UsesForward(tri, u, v) });
  }
  std::sort(fans.begin(), fans.end());
  return fans;
}

// Pairs of triangles around a non-manifold edge, each enclosing a wedge of the solid: a triangle
// that uses the edge backwards has its normal on its clockwise side, so the wedge to its
// counter-clockwise neighbour is inside. Empty when the orientations do not alternate.
std::vector<std::pair<Index, Index>> PairAroundEdge(const TriangleMesh& mesh, const MeshTopology& topology, Index e)
{
  std::vector<std::pair<Index, Index>> pairs;
  if (topology.EdgeTriangleCount(e) % 2 != 0)
  {
    return pairs;
  }
  const std::vector<EdgeFan> fans = SortAroundEdge(mesh, topology, e);
  const size_t n = fans.size();
  for (size_t i = 0; i < n; ++i)
  {
    if (fans[i].Forward == fans[(i + 1) % n].Forward || fans[i].Angle == fans[(i + 1) % n].Angle)
    {
      return pairs; // not alternating, or two sheets in one plane: no reliable pairing
    }
  }
  const size_t start = fans[0].Forward ? 1 : 0; // the first backward triangle
  for (size_t i = 0; i < n; i += 2)
  {
    pairs.emplace_back(fans[(start + i) % n].Triangle, fans[(start + i + 1) % n].Triangle);
  }
  return pairs;
}

void JoinCorners(const TriangleMesh& mesh, Index a, Index b, Index u, Index v, UnionFind& corners)
{
  corners.Union(CornerOf(mesh, a, u), CornerOf(mesh, b, u));
  corners.Union(CornerOf(mesh, a, v), CornerOf(mesh, b, v));
}

// Corners that share a vertex and a fan are joined across every manifold edge, every pair of a
// resolved non-manifold edge, and all triangles of an unresolved one.
UnionFind JoinFans(const TriangleMesh& mesh, const MeshTopology& topology, ManifoldSplitResult& result)
{
  UnionFind corners(3 * mesh.NumberOfTriangles());
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    const Index u = topology.EdgeVertex(e, 0), v = topology.EdgeVertex(e, 1);
    const Index* begin = topology.EdgeTrianglesBegin(e);
    const Index count = topology.EdgeTriangleCount(e);
    if (count == 2)
    {
      JoinCorners(mesh, begin[0], begin[1], u, v, corners);
      continue;
    }
    if (count < 2)
    {
      continue;
    }
    const std::vector<std::pair<Index, Index>> pairs = PairAroundEdge(mesh, topology, e);
    ++(pairs.empty() ? result.EdgesLeft : result.EdgesSplit);
    for (const auto& pair : pairs)
    {
      JoinCorners(mesh, pair.first, pair.second, u, v, corners);
    }
    for (Index i = 1; pairs.empty() && i < count; ++i)
    {
      JoinCorners(mesh, begin[0], begin[i], u, v, corners);
    }
  }
  return corners;
}
} // namespace

ManifoldSplitResult SplitNonManifold(const TriangleMesh& mesh, const MeshTopology& topology)
{
  ManifoldSplitResult result;
  UnionFind corners = JoinFans(mesh, topology, result);
  result.Mesh.Points = mesh.Points;
  result.Mesh.Triangles = mesh.Triangles;
  result.VertexSource.resize(size_t(mesh.NumberOfPoints()));
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    result.VertexSource[v] = v;
  }
  // Per vertex, the fan of its first triangle keeps it; every other fan gets a copy.
  std::vector<Index> cornerVertex(mesh.Triangles.size(), InvalidIndex);
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    bool copied = false;
    for (const Index* t = topology.VertexTrianglesBegin(v); t != topology.VertexTrianglesEnd(v); ++t)
    {
      const Index root = corners.Find(CornerOf(mesh, *t, v));
      if (cornerVertex[root] == InvalidIndex)
      {
        const bool first = t == topology.VertexTrianglesBegin(v);
        cornerVertex[root] = first ? v : result.Mesh.AddPoint(mesh.Point(v));
        if (!first)
        {
          result.VertexSource.push_back(v);
          copied = true;
        }
      }
      result.Mesh.Triangles[CornerOf(mesh, *t, v)] = cornerVertex[root];
    }
    result.VerticesSplit += copied ? 1 : 0;
  }
  return result;
}
} // namespace slod
