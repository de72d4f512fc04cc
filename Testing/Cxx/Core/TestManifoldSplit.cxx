// SPDX-License-Identifier: BSD-3-Clause
// slod::SplitNonManifold: solids touching along an edge or at a vertex are separated into
// manifold sheets without opening a border; edges that cannot be paired are left alone; on a
// noisy scan-like isosurface every paired edge becomes manifold and positions are kept.
#include "TestSupport.h"

#include "slodManifoldSplit.h"
#include "slodMeshTopology.h"

#include <gtest/gtest.h>

#include <set>

using namespace slod;
using namespace slodtest;

namespace
{
// A tetrahedron over four existing vertices, every face oriented outwards (flipped when
// `inverted`).
void AddTetrahedron(TriangleMesh& mesh, Index a, Index b, Index c, Index d, bool inverted = false)
{
  const Vec3 centre = 0.25 * (mesh.Point(a) + mesh.Point(b) + mesh.Point(c) + mesh.Point(d));
  const Index faces[4][3] = { { a, b, c }, { a, b, d }, { a, c, d }, { b, c, d } };
  for (const auto& f : faces)
  {
    const Vec3 p = mesh.Point(f[0]), q = mesh.Point(f[1]), r = mesh.Point(f[2]);
    const Vec3 faceCentre = (1.0 / 3.0) * (p + q + r);
    const bool outward = Dot(Cross(q - p, r - p), faceCentre - centre) > 0;
    if (outward != inverted)
    {
      mesh.AddTriangle(f[0], f[1], f[2]);
    }
    else
    {
      mesh.AddTriangle(f[0], f[2], f[1]);
    }
  }
}

// Two tetrahedra touching along the edge 0-1 (the z axis), in opposite quadrants.
TriangleMesh TetrahedraSharingAnEdge(bool invertSecond = false)
{
  TriangleMesh mesh;
  for (const Vec3& p : { Vec3{ 0, 0, 0 }, Vec3{ 0, 0, 1 }, Vec3{ 1, 0, 0.5 }, Vec3{ 0, 1, 0.5 },
         Vec3{ -1, 0, 0.5 }, Vec3{ 0, -1, 0.5 } })
  {
    mesh.AddPoint(p);
  }
  AddTetrahedron(mesh, 0, 1, 2, 3);
  AddTetrahedron(mesh, 0, 1, 4, 5, invertSecond);
  return mesh;
}

MeshStatistics Stats(const TriangleMesh& mesh)
{
  return ComputeMeshStatistics(mesh);
}

std::set<Index> VerticesOf(const TriangleMesh& mesh, Index firstTriangle, Index count)
{
  std::set<Index> vertices;
  for (Index t = firstTriangle; t < firstTriangle + count; ++t)
  {
    vertices.insert(mesh.Triangle(t), mesh.Triangle(t) + 3);
  }
  return vertices;
}

// Two closed, manifold, consistently oriented tetrahedra, separated rather than joined: each of the
// two keeps its own four vertices (triangles 0-3 and 4-7).
void ExpectTwoSeparateTetrahedra(const TriangleMesh& mesh)
{
  const MeshStatistics after = Stats(mesh);
  EXPECT_EQ(after.NonManifoldEdges, 0);
  EXPECT_EQ(after.NonManifoldVertices, 0);
  EXPECT_EQ(after.BoundaryEdges, 0);
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(after.Components, 2);
  EXPECT_EQ(after.EulerCharacteristic, 4);
  EXPECT_EQ(after.Genus, 0);
  const std::set<Index> first = VerticesOf(mesh, 0, 4), second = VerticesOf(mesh, 4, 4);
  EXPECT_EQ(first.size(), 4u);
  EXPECT_EQ(second.size(), 4u);
  for (Index v : first)
  {
    EXPECT_EQ(second.count(v), 0u);
  }
}

// Same triangle count, and every corner at the position of the input corner it replaces.
void ExpectSamePositions(const TriangleMesh& input, const ManifoldSplitResult& split)
{
  ASSERT_EQ(split.Mesh.NumberOfTriangles(), input.NumberOfTriangles());
  ASSERT_EQ(split.VertexSource.size(), size_t(split.Mesh.NumberOfPoints()));
  for (size_t c = 0; c < input.Triangles.size(); ++c)
  {
    const Index v = split.Mesh.Triangles[c];
    ASSERT_EQ(split.VertexSource[v], input.Triangles[c]);
    ASSERT_EQ(split.Mesh.Point(v), input.Point(input.Triangles[c]));
  }
}
} // namespace

TEST(ManifoldSplit, TetrahedraTouchingAlongAnEdgeAreSeparated)
{
  const TriangleMesh input = TetrahedraSharingAnEdge();
  const MeshStatistics before = Stats(input);
  ASSERT_EQ(before.NonManifoldEdges, 1);
  ASSERT_EQ(before.EulerCharacteristic, 3); // 6 - 11 + 8

  const ManifoldSplitResult split = SplitNonManifold(input, MeshTopology(input));
  ExpectSamePositions(input, split);
  EXPECT_EQ(split.EdgesSplit, 1);
  EXPECT_EQ(split.EdgesLeft, 0);
  EXPECT_EQ(split.VerticesSplit, 2);
  ExpectTwoSeparateTetrahedra(split.Mesh);
}

TEST(ManifoldSplit, TetrahedraTouchingAtAVertexAreSeparated)
{
  TriangleMesh input;
  for (const Vec3& p : { Vec3{ 0, 0, 0 }, Vec3{ 1, 0, 0 }, Vec3{ 0, 1, 0 }, Vec3{ 0, 0, 1 }, Vec3{ -1, 0, 0 },
         Vec3{ 0, -1, 0 }, Vec3{ 0, 0, -1 } })
  {
    input.AddPoint(p);
  }
  AddTetrahedron(input, 0, 1, 2, 3);
  AddTetrahedron(input, 0, 4, 5, 6);
  ASSERT_EQ(Stats(input).NonManifoldVertices, 1);

  const ManifoldSplitResult split = SplitNonManifold(input, MeshTopology(input));
  ExpectSamePositions(input, split);
  EXPECT_EQ(split.EdgesSplit, 0);
  EXPECT_EQ(split.VerticesSplit, 1);
  ExpectTwoSeparateTetrahedra(split.Mesh);
}

TEST(ManifoldSplit, UnpairableEdgesAreLeftAlone)
{
  // Three triangles on one edge: an odd count.
  const TriangleMesh fan = NonManifoldFan(3);
  const ManifoldSplitResult odd = SplitNonManifold(fan, MeshTopology(fan));
  ExpectSamePositions(fan, odd);
  EXPECT_EQ(odd.EdgesSplit, 0);
  EXPECT_EQ(odd.EdgesLeft, 1);
  EXPECT_EQ(Stats(odd.Mesh).NonManifoldEdges, 1);
  EXPECT_EQ(Stats(odd.Mesh).BoundaryEdges, Stats(fan).BoundaryEdges);

  // Four triangles whose orientations do not alternate around the edge (one solid inverted).
  const TriangleMesh inverted = TetrahedraSharingAnEdge(/*invertSecond=*/true);
  const ManifoldSplitResult left = SplitNonManifold(inverted, MeshTopology(inverted));
  EXPECT_EQ(left.EdgesSplit, 0);
  EXPECT_EQ(left.EdgesLeft, 1);
  EXPECT_EQ(left.VerticesSplit, 0);
  EXPECT_EQ(Stats(left.Mesh).NonManifoldEdges, 1);
}

// A noisy scan-like isosurface with pinched vertices and non-manifold edges: the split leaves only
// the edges it reports as left, opens no border and keeps every position.
TEST(ManifoldSplit, NoisyScanBecomesManifoldWithoutNewBorders)
{
  const TriangleMesh input = ToTriangleMesh(NoisyScanIsosurface(40, 3));
  const MeshStatistics before = Stats(input);
  ASSERT_GT(before.NonManifoldEdges, 0);
  ASSERT_GT(before.NonManifoldVertices, 0);

  const ManifoldSplitResult split = SplitNonManifold(input, MeshTopology(input));
  ExpectSamePositions(input, split);
  const MeshStatistics after = Stats(split.Mesh);
  EXPECT_EQ(split.EdgesSplit + split.EdgesLeft, before.NonManifoldEdges);
  EXPECT_GT(split.EdgesSplit, 0);
  EXPECT_EQ(after.NonManifoldEdges, split.EdgesLeft);
  EXPECT_EQ(after.BoundaryEdges, before.BoundaryEdges);
  // A border through a pinched vertex is traced ambiguously before the split (as one loop or two);
  // after it every border vertex has exactly two border edges, so the loops are well defined and
  // never more.
  EXPECT_LE(after.BoundaryLoops, before.BoundaryLoops);
  const MeshTopology sheets(split.Mesh);
  std::vector<int> borderEdges(size_t(split.Mesh.NumberOfPoints()), 0);
  for (Index e = 0; e < sheets.NumberOfEdges(); ++e)
  {
    if (sheets.IsBoundaryEdge(e))
    {
      ++borderEdges[sheets.EdgeVertex(e, 0)];
      ++borderEdges[sheets.EdgeVertex(e, 1)];
    }
  }
  for (int count : borderEdges)
  {
    ASSERT_TRUE(count == 0 || count == 2);
  }
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
  if (split.EdgesLeft == 0)
  {
    EXPECT_EQ(after.NonManifoldVertices, 0);
  }
  // Splitting again finds nothing more to split.
  const ManifoldSplitResult again = SplitNonManifold(split.Mesh, MeshTopology(split.Mesh));
  EXPECT_EQ(again.EdgesSplit, 0);
  EXPECT_EQ(again.VerticesSplit, 0);
}
