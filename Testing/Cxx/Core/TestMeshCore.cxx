// SPDX-License-Identifier: BSD-3-Clause
// Shared mesh core: adjacency, statistics, editing with the link condition, quadrics,
// polygon triangulation and input preparation on known shapes and bad inputs.
#include "TestSupport.h"

#include "slodEditableMesh.h"
#include "slodGroupByKey.h"
#include "slodHugePages.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPolygonTriangulation.h"
#include "slodPointAttributes.h"
#include "slodQuadric.h"

#include "vtkCell.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <sstream>
#include <limits>
#include <map>
#include <random>
#include <string>

using namespace slod;
using namespace slodtest;

TEST(MeshTopology, Tetrahedron)
{
  const MeshStatistics s = ComputeMeshStatistics(Tetrahedron());
  EXPECT_EQ(s.Vertices, 4);
  EXPECT_EQ(s.Edges, 6);
  EXPECT_EQ(s.Triangles, 4);
  EXPECT_EQ(s.EulerCharacteristic, 2);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.BoundaryEdges, 0);
  EXPECT_EQ(s.Components, 1);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
}

TEST(MeshTopology, TorusHasGenusOne)
{
  const TriangleMesh torus = Torus(24, 12);
  const MeshStatistics s = ComputeMeshStatistics(torus);
  EXPECT_EQ(s.EulerCharacteristic, 0);
  EXPECT_EQ(s.Genus, 1);
  EXPECT_EQ(s.BoundaryLoops, 0);
  MeshTopology topology(torus);
  for (Index v = 0; v < torus.NumberOfPoints(); ++v)
  {
    ASSERT_EQ(topology.Valence(v), 6);
    ASSERT_FALSE(topology.IsBoundaryVertex(v));
  }
}

TEST(MeshTopology, SphereSource)
{
  const MeshStatistics s = ComputeMeshStatistics(Sphere(16, 12));
  EXPECT_EQ(s.EulerCharacteristic, 2);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.NonManifoldVertices, 0);
  EXPECT_EQ(s.DegenerateTriangles, 0);
}

TEST(MeshTopology, OpenDiskHasOneBoundaryLoop)
{
  const TriangleMesh disk = Disk(4, 10);
  MeshTopology topology(disk);
  const MeshStatistics s = topology.Statistics(disk);
  EXPECT_EQ(s.EulerCharacteristic, 1);
  EXPECT_EQ(s.BoundaryLoops, 1);
  EXPECT_EQ(s.BoundaryEdges, 10);
  EXPECT_EQ(s.Genus, 0);
  const auto loops = topology.BoundaryLoops();
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 10u);
  // Ordered one-ring of the centre: 10 neighbours, closed.
  std::vector<Index> ring, fan;
  ASSERT_TRUE(topology.OrderedOneRing(disk, 0, ring, fan));
  EXPECT_EQ(ring.size(), 10u);
  EXPECT_EQ(fan.size(), 10u);
  for (size_t i = 0; i < ring.size(); ++i)
  {
    EXPECT_EQ(ring[i], Index(1 + i)); // counter-clockwise
  }
  // A border vertex: open ring, one more neighbour than triangles.
  const Index border = 1 + 3 * 10;
  ASSERT_TRUE(topology.IsBoundaryVertex(border));
  ASSERT_TRUE(topology.OrderedOneRing(disk, border, ring, fan));
  EXPECT_EQ(ring.size(), fan.size() + 1);
}

TEST(MeshTopology, TwoComponents)
{
  TriangleMesh far = Sphere(8, 8);
  for (size_t i = 0; i < far.Points.size(); i += 3)
  {
    far.Points[i] += 10;
  }
  const TriangleMesh both = Concatenate(Torus(12, 8), far);
  MeshTopology topology(both);
  const MeshStatistics s = topology.Statistics(both);
  EXPECT_EQ(s.Components, 2);
  EXPECT_EQ(s.EulerCharacteristic, 2); // 0 + 2
  EXPECT_EQ(s.Genus, 1);               // summed genus
  const auto& labels = topology.TriangleComponents();
  EXPECT_EQ(labels.front(), 0);
  EXPECT_EQ(labels.back(), 1);
}

TEST(MeshTopology, NonManifoldFan)
{
  const TriangleMesh fan = NonManifoldFan(3);
  MeshTopology topology(fan);
  const MeshStatistics s = topology.Statistics(fan);
  EXPECT_EQ(s.NonManifoldEdges, 1);
  EXPECT_EQ(s.NonManifoldVertices, 2);
  EXPECT_EQ(s.Genus, -1); // undefined
  EXPECT_TRUE(topology.IsNonManifoldEdge(topology.FindEdge(0, 1)));
}

TEST(MeshTopology, BowTieVertexIsNonManifold)
{
  TriangleMesh m;
  m.Points = { 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0 };
  m.Triangles = { 0, 1, 2, 0, 3, 4 };
  MeshTopology topology(m);
  EXPECT_TRUE(topology.IsNonManifoldVertex(0));
  EXPECT_EQ(topology.Statistics(m).NonManifoldEdges, 0);
}

namespace
{
// Every array of two topologies, entry for entry (what any caller can read).
void ExpectSameTopology(const MeshTopology& a, const MeshTopology& b, const TriangleMesh& mesh, const char* what)
{
  ASSERT_EQ(a.NumberOfPoints(), b.NumberOfPoints()) << what;
  ASSERT_EQ(a.NumberOfTriangles(), b.NumberOfTriangles()) << what;
  ASSERT_EQ(a.NumberOfEdges(), b.NumberOfEdges()) << what;
  int differences = 0;
  for (Index v = 0; v < a.NumberOfPoints(); ++v)
  {
    differences += !std::equal(a.VertexTrianglesBegin(v), a.VertexTrianglesEnd(v), b.VertexTrianglesBegin(v),
      b.VertexTrianglesEnd(v));
    differences += a.IsBoundaryVertex(v) != b.IsBoundaryVertex(v);
    differences += a.IsNonManifoldVertex(v) != b.IsNonManifoldVertex(v);
    differences += a.Valence(v) != b.Valence(v);
  }
  for (Index e = 0; e < a.NumberOfEdges(); ++e)
  {
    differences += a.EdgeVertex(e, 0) != b.EdgeVertex(e, 0) || a.EdgeVertex(e, 1) != b.EdgeVertex(e, 1);
    differences += !std::equal(a.EdgeTrianglesBegin(e), a.EdgeTrianglesEnd(e), b.EdgeTrianglesBegin(e),
      b.EdgeTrianglesEnd(e));
  }
  for (Index t = 0; t < a.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      differences += a.TriangleEdge(t, k) != b.TriangleEdge(t, k);
    }
  }
  EXPECT_EQ(differences, 0) << what;
  EXPECT_EQ(a.NumberOfComponents(), b.NumberOfComponents()) << what;
  EXPECT_EQ(a.TriangleComponents(), b.TriangleComponents()) << what;
  EXPECT_EQ(a.BoundaryLoops(), b.BoundaryLoops()) << what;
  const MeshStatistics sa = a.Statistics(mesh), sb = b.Statistics(mesh);
  EXPECT_EQ(sa.Edges, sb.Edges) << what;
  EXPECT_EQ(sa.BoundaryLoops, sb.BoundaryLoops) << what;
  EXPECT_EQ(sa.NonManifoldVertices, sb.NonManifoldVertices) << what;
  EXPECT_EQ(sa.Components, sb.Components) << what;
  EXPECT_EQ(sa.EulerCharacteristic, sb.EulerCharacteristic) << what;
}
} // namespace

// Session 45 (issue 10): MeshTopology::Update carries a topology over to its mesh edited (triangles
// removed, their order kept, and triangles appended), as hole-bump removal's passes do, and must
// give exactly Build's arrays (edge numbering, triangle lists, flags, component labels): the
// filter's outputs depend on them. Chained edits of a torus with isolated extra points: random
// removals and refills, two rings cut (two components), two triangles joining them again, a third
// triangle on an edge (non-manifold), a separate triangle, a triangle with a repeated vertex, a bow
// tie. Each update's local work is at most a fixed multiple of the changed triangles times the
// largest vertex degree, and an edit that changes nothing touches nothing.
TEST(MeshTopology, UpdateAfterAnEditEqualsABuildOfTheEditedMesh)
{
  const int major = 40, minor = 16;
  TriangleMesh mesh = Torus(major, minor);
  const Index torusPoints = mesh.NumberOfPoints();
  for (int i = 0; i < 6; ++i)
  {
    mesh.AddPoint({ 3.0 + i, 0.0, 0.0 }); // unused until a separate triangle takes them
  }
  MeshTopology updated(mesh);
  std::mt19937 random(45);
  int round = 0;
  auto edit = [&](const std::function<bool(Index)>& remove, const std::vector<std::array<Index, 3>>& add) {
    TriangleMesh next;
    next.Points = mesh.Points;
    std::vector<unsigned char> removed(size_t(mesh.NumberOfTriangles()), 0);
    std::vector<Index> removedTriangles;
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      removed[t] = remove(t) ? 1 : 0;
      const Index* tri = mesh.Triangle(t);
      if (removed[t])
      {
        removedTriangles.insert(removedTriangles.end(), tri, tri + 3);
      }
      else
      {
        next.AddTriangle(tri[0], tri[1], tri[2]);
      }
    }
    for (const auto& tri : add)
    {
      next.AddTriangle(tri[0], tri[1], tri[2]);
    }
    const Index before = MaximumVertexDegree(updated);
    const std::vector<Index> previous = mesh.Triangles;
    mesh = next;
    updated.Update(previous, removed, mesh);
    const std::string what = "round " + std::to_string(++round);
    ExpectSameTopology(updated, MeshTopology(mesh), mesh, what.c_str());
    const MeshTopologyUpdateWork& work = updated.LastUpdateWork();
    const std::int64_t changed = std::int64_t(removedTriangles.size() / 3 + add.size());
    EXPECT_EQ(work.RemovedTriangles + work.AppendedTriangles, changed) << what;
    EXPECT_LE(work.LocalIncidences, 15 * std::int64_t(std::max(before, MaximumVertexDegree(updated))) * changed) << what;
    return removedTriangles;
  };
  // Random removals, refilled in reverse order (the appended triangles differ in order).
  for (int k = 0; k < 3; ++k)
  {
    std::vector<unsigned char> pick(size_t(mesh.NumberOfTriangles()));
    for (auto& p : pick)
    {
      p = random() % 50 == 0;
    }
    const std::vector<Index> gone = edit([&](Index t) { return pick[t] != 0; }, {});
    std::vector<std::array<Index, 3>> refill;
    for (size_t i = gone.size(); i >= 3; i -= 3)
    {
      refill.push_back({ gone[i - 3], gone[i - 2], gone[i - 1] });
    }
    edit([](Index) { return false; }, refill);
  }
  // Nothing changed: nothing touched.
  edit([](Index) { return false; }, {});
  EXPECT_EQ(updated.LastUpdateWork().TouchedVertices, 0);
  EXPECT_EQ(updated.LastUpdateWork().LocalIncidences, 0);
  // Two rings cut (ring i: the triangles between vertex columns i and i + 1, wherever the refills
  // put them): two components; then two triangles join them across a cut.
  const Index cutA = 5, cutB = 25;
  auto inRing = [&](Index t, Index i) {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] >= torusPoints || !(tri[k] / minor == i || tri[k] / minor == (i + 1) % major))
      {
        return false;
      }
    }
    return true;
  };
  edit([&](Index t) { return inRing(t, cutA) || inRing(t, cutB); }, {});
  EXPECT_EQ(updated.NumberOfComponents(), 2);
  const Index a = cutA * minor, b = (cutA + 1) * minor;
  edit([](Index) { return false; }, { { a, b, Index(b + 1) }, { a, Index(b + 1), Index(a + 1) } });
  EXPECT_EQ(updated.NumberOfComponents(), 1);
  // A third triangle on an edge, a separate triangle, a repeated vertex, a bow tie at a vertex.
  const Index* first = mesh.Triangle(0);
  const Index far = Index(20 * minor + 8);
  edit([](Index t) { return t % 97 == 3; },
    { { first[0], first[1], far }, { torusPoints, Index(torusPoints + 1), Index(torusPoints + 2) },
      { Index(torusPoints + 3), Index(torusPoints + 3), Index(torusPoints + 4) },
      { far, Index(torusPoints + 4), Index(torusPoints + 5) } });
  EXPECT_GT(updated.Statistics(mesh).NonManifoldEdges, 0);
  EXPECT_GT(updated.Statistics(mesh).NonManifoldVertices, 0);
  // And those edits removed again.
  const Index count = mesh.NumberOfTriangles();
  edit([&](Index t) { return t >= count - 4; }, {});
}

// A border is counted as its connected boundary edges: two triangles whose shared edge runs the
// same way in both (inconsistent orientation, as next to a non-manifold edge of a noisy scan) have
// one border cycle of four edges, whatever the numbering, although their boundary half-edges do not
// chain into one loop.
TEST(MeshTopology, BorderCountDoesNotDependOnOrientationNorNumbering)
{
  TriangleMesh m;
  m.Points = { 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0 };
  m.Triangles = { 0, 1, 2, 0, 1, 3 };
  EXPECT_EQ(MeshTopology(m).Statistics(m).BoundaryLoops, 1);
  EXPECT_EQ(MeshTopology(m).Statistics(m).InconsistentlyOrientedEdges, 1);
  const Index relabel[4] = { 3, 2, 0, 1 };
  for (Index& v : m.Triangles)
  {
    v = relabel[v];
  }
  std::rotate(m.Triangles.begin(), m.Triangles.begin() + 3, m.Triangles.end()); // the other triangle first
  EXPECT_EQ(MeshTopology(m).Statistics(m).BoundaryLoops, 1);
  // A second, separate triangle is a second border.
  m.Points.insert(m.Points.end(), { 5, 0, 0, 6, 0, 0, 5, 1, 0 });
  m.Triangles.insert(m.Triangles.end(), { 4, 5, 6 });
  EXPECT_EQ(MeshTopology(m).Statistics(m).BoundaryLoops, 2);
}

namespace
{
// Collapses the first collapsible triangle repeatedly, checking validity after each step.
int CollapseTrianglesGreedily(EditableMesh& mesh, int steps, std::vector<CollapseRecord>* records = nullptr)
{
  int done = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles() && done < steps; ++t)
  {
    if (!mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = mesh.Triangle(t);
    const Index set[3] = { tri[0], tri[1], tri[2] };
    const Vec3 centroid = (1.0 / 3) * (mesh.Point(set[0]) + mesh.Point(set[1]) + mesh.Point(set[2]));
    if (mesh.CheckCollapse(set, 3, centroid) != CollapseStatus::Ok)
    {
      continue;
    }
    CollapseRecord record;
    mesh.Collapse(set, 3, set[0], centroid, &record);
    if (records)
    {
      records->push_back(record);
    }
    ++done;
  }
  return done;
}
} // namespace

TEST(EditableMesh, TriangleCollapsesKeepTopology)
{
  for (const TriangleMesh& input : { Torus(30, 14), Sphere(24, 20), Disk(6, 16) })
  {
    const MeshStatistics before = ComputeMeshStatistics(input);
    EditableMesh mesh(input);
    const int done = CollapseTrianglesGreedily(mesh, 1000000);
    EXPECT_GT(done, 10);
    ASSERT_TRUE(mesh.CheckInvariants());
    TriangleMesh out;
    mesh.Extract(out);
    const MeshStatistics after = ComputeMeshStatistics(out);
    EXPECT_EQ(after.Genus, before.Genus);
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
    EXPECT_EQ(after.NonManifoldEdges, 0);
    EXPECT_EQ(after.NonManifoldVertices, 0);
    EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
    EXPECT_EQ(out.NumberOfTriangles(), mesh.NumberOfLiveTriangles());
    EXPECT_EQ(out.NumberOfPoints(), mesh.NumberOfLiveVertices()); // no vertex left without triangles
    EXPECT_LT(out.NumberOfTriangles(), input.NumberOfTriangles());
  }
}

namespace
{
// The live triangles around v, in the order ForEachTriangle gives them.
std::vector<Index> Fan(const EditableMesh& mesh, Index v)
{
  std::vector<Index> fan;
  mesh.ForEachTriangle(v, [&](Index t) { fan.push_back(t); });
  return fan;
}
} // namespace

TEST(EditableMesh, ReferenceRoomFactorCompactsInPlaceInTheBlocksOrder)
{
  // The same edge collapses on a mesh without a room limit and on one limited to 1.25 times its
  // references: the limited one holds less room, and its compactions (many, since the merged
  // vertices' new blocks add far more than a quarter of the references) leave every fan in the
  // order of the unlimited one, which rebuilt its blocks in triangle order once they doubled (the
  // limited one at the same collapse).
  const TriangleMesh input = Torus(160, 60);
  EditableMesh free(input), limited;
  limited.SetReferenceRoomFactor(1.25);
  limited.Reset(input);
  const size_t references = 3 * size_t(input.NumberOfTriangles());
  const size_t freeStart = free.MemoryBytes();
  EXPECT_LE(limited.MemoryBytes() + references / 2 * sizeof(Index), freeStart);
  size_t appended = 0, largest = 0;
  const Index goal = input.NumberOfTriangles() / 5;
  for (Index step = 0; step < 6 * input.NumberOfTriangles() && free.NumberOfLiveTriangles() > goal; ++step)
  {
    const Index t = (5 * step) % input.NumberOfTriangles();
    if (!free.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = free.Triangle(t);
    const Index set[2] = { tri[0], tri[1] };
    const Vec3 middle = 0.5 * (free.Point(set[0]) + free.Point(set[1]));
    if (free.CheckCollapse(set, 2, middle) != CollapseStatus::Ok)
    {
      continue;
    }
    ASSERT_EQ(limited.CheckCollapse(set, 2, middle), CollapseStatus::Ok);
    free.Collapse(set, 2, set[0], middle);
    limited.Collapse(set, 2, set[0], middle);
    appended += Fan(free, set[0]).size();
    largest = std::max(largest, limited.MemoryBytes());
  }
  // Enough for several compactions at 1.25 and a rebuild of the unlimited mesh (at twice its
  // references).
  EXPECT_LT(free.NumberOfLiveTriangles(), 2 * input.NumberOfTriangles() / 3);
  EXPECT_GT(appended, 3 * references / 2);
  EXPECT_LE(largest + references / 2 * sizeof(Index), freeStart);
  ASSERT_TRUE(limited.CheckInvariants());
  for (Index v = 0; v < free.NumberOfPoints(); ++v)
  {
    ASSERT_EQ(free.IsVertexAlive(v), limited.IsVertexAlive(v));
    if (free.IsVertexAlive(v))
    {
      ASSERT_EQ(Fan(free, v), Fan(limited, v)) << "vertex " << v;
    }
  }
}

TEST(EditableMesh, LinkConditionRejectsTetrahedronCollapse)
{
  EditableMesh mesh(Tetrahedron());
  const Index edge[2] = { 0, 1 };
  EXPECT_NE(mesh.CheckCollapse(edge, 2, mesh.Point(0)), CollapseStatus::Ok);
  const Index face[3] = { 0, 1, 2 };
  EXPECT_NE(mesh.CheckCollapse(face, 3, mesh.Point(0)), CollapseStatus::Ok);
}

TEST(EditableMesh, FlipIsRejected)
{
  // Moving the centre of a flat disk outside its ring turns triangles over.
  EditableMesh mesh(Disk(2, 8));
  const Index edge[2] = { 0, 1 };
  EXPECT_EQ(mesh.CheckCollapse(edge, 2, Vec3{ 5, 0, 0 }), CollapseStatus::Flip);
  EXPECT_EQ(mesh.CheckCollapse(edge, 2, mesh.Point(1)), CollapseStatus::Ok);
}

TEST(EditableMesh, UndoRestoresExactly)
{
  const TriangleMesh input = Torus(20, 10);
  EditableMesh mesh(input);
  std::vector<CollapseRecord> records;
  CollapseTrianglesGreedily(mesh, 60, &records);
  ASSERT_EQ(records.size(), 60u);
  for (auto it = records.rbegin(); it != records.rend(); ++it)
  {
    mesh.Undo(*it);
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  TriangleMesh out;
  std::vector<Index> newToOld;
  mesh.Extract(out, &newToOld);
  ASSERT_EQ(out.NumberOfTriangles(), input.NumberOfTriangles());
  ASSERT_EQ(out.NumberOfPoints(), input.NumberOfPoints());
  for (Index t = 0; t < out.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(newToOld[out.Triangle(t)[k]], input.Triangle(t)[k]);
    }
  }
  for (Index v = 0; v < out.NumberOfPoints(); ++v)
  {
    ASSERT_EQ(out.Point(v), input.Point(newToOld[v]));
  }
}

TEST(EditableMesh, FlipEdgeAndUndoInterleavedWithCollapses)
{
  // A tetrahedron's opposite vertices are always joined: no flip.
  EditableMesh tetra(Tetrahedron());
  EXPECT_FALSE(tetra.FlipEdge(0, 1));
  EXPECT_TRUE(tetra.CheckInvariants());

  const TriangleMesh input = Torus(20, 10);
  EditableMesh mesh(input);
  const MeshStatistics before = ComputeMeshStatistics(input);
  // Flip one edge and check the new diagonal replaced the old one.
  const Index* t0 = input.Triangle(0);
  FlipRecord first;
  ASSERT_TRUE(mesh.FlipEdge(t0[0], t0[1], &first));
  EXPECT_EQ(mesh.EdgeTriangleCount(first.X, first.Y), 0);
  EXPECT_EQ(mesh.EdgeTriangleCount(first.Q, first.Z), 2);
  EXPECT_TRUE(mesh.CheckInvariants());
  // Interleave collapses and flips, then undo everything newest first.
  struct Step
  {
    bool IsFlip;
    CollapseRecord Collapse;
    FlipRecord Flip;
  };
  std::vector<Step> steps;
  steps.push_back({ true, {}, first });
  for (int round = 0; round < 20; ++round)
  {
    std::vector<CollapseRecord> records;
    CollapseTrianglesGreedily(mesh, 2, &records);
    for (const CollapseRecord& r : records)
    {
      steps.push_back({ false, r, {} });
    }
    for (Index t = 0; t < mesh.NumberOfTriangles(); t += 7)
    {
      if (mesh.IsTriangleAlive(t))
      {
        const Index* tri = mesh.Triangle(t);
        FlipRecord f;
        if (mesh.FlipEdge(tri[1], tri[2], &f))
        {
          steps.push_back({ true, {}, f });
          break;
        }
      }
    }
    ASSERT_TRUE(mesh.CheckInvariants());
  }
  TriangleMesh middle;
  mesh.Extract(middle);
  const MeshStatistics during = ComputeMeshStatistics(middle);
  EXPECT_EQ(during.Genus, before.Genus);
  EXPECT_EQ(during.NonManifoldEdges, 0);
  EXPECT_EQ(during.InconsistentlyOrientedEdges, 0);
  for (auto it = steps.rbegin(); it != steps.rend(); ++it)
  {
    if (it->IsFlip)
    {
      mesh.Undo(it->Flip);
    }
    else
    {
      mesh.Undo(it->Collapse);
    }
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  TriangleMesh out;
  std::vector<Index> newToOld;
  mesh.Extract(out, &newToOld);
  ASSERT_EQ(out.NumberOfTriangles(), input.NumberOfTriangles());
  for (Index t = 0; t < out.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(newToOld[out.Triangle(t)[k]], input.Triangle(t)[k]);
    }
  }
}

TEST(Quadric, MinimizerOfThreePlanesIsTheirCorner)
{
  Quadric q = Quadric::FromPointNormal({ 1, 2, 3 }, { 1, 0, 0 });
  q += Quadric::FromPointNormal({ 1, 2, 3 }, { 0, 1, 0 });
  q += Quadric::FromPointNormal({ 1, 2, 3 }, Normalized({ 0, 1, 1 }));
  Vec3 p;
  ASSERT_TRUE(q.Minimize(p));
  EXPECT_NEAR(p[0], 1, 1e-12);
  EXPECT_NEAR(p[1], 2, 1e-12);
  EXPECT_NEAR(p[2], 3, 1e-12);
  EXPECT_NEAR(q.Evaluate(p), 0, 1e-12);
  EXPECT_NEAR(q.Evaluate({ 2, 2, 3 }), 1, 1e-12);
  // Two parallel planes: singular.
  Quadric flat = Quadric::FromPointNormal({ 0, 0, 0 }, { 0, 0, 1 });
  flat += Quadric::FromPointNormal({ 0, 0, 1 }, { 0, 0, 1 });
  EXPECT_FALSE(flat.Minimize(p));
  EXPECT_NEAR(flat.Evaluate({ 0, 0, 0.5 }), 0.5, 1e-12);
}

TEST(PolygonTriangulation, NonConvexPolygonIsCovered)
{
  // An L-shaped hexagon: 4 triangles, total area 3, all counter-clockwise.
  const std::vector<Vec3> polygon = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 }, { 0, 2, 0 } };
  const auto result = TriangulatePolygon(polygon, PolygonNormal(polygon));
  ASSERT_EQ(result.Triangles.size(), 4u);
  EXPECT_FALSE(result.UsedFallback);
  double area = 0;
  for (const auto& t : result.Triangles)
  {
    const Vec3 n = Cross(polygon[t[1]] - polygon[t[0]], polygon[t[2]] - polygon[t[0]]);
    EXPECT_GT(n[2], 0);
    area += 0.5 * n[2];
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
}

namespace
{
vtkSmartPointer<vtkPolyData> MakePolyData(const std::vector<double>& xyz, const std::vector<std::vector<vtkIdType>>& polys,
  const std::vector<std::vector<vtkIdType>>& lines = {})
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  for (size_t i = 0; i < xyz.size(); i += 3)
  {
    points->InsertNextPoint(xyz[i], xyz[i + 1], xyz[i + 2]);
  }
  vtkNew<vtkCellArray> cells, lineCells;
  for (const auto& c : polys)
  {
    cells->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  }
  for (const auto& c : lines)
  {
    lineCells->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  }
  pd->SetPoints(points);
  pd->SetPolys(cells);
  pd->SetLines(lineCells);
  return pd;
}
} // namespace

TEST(InputPreparation, EmptyInputGivesEmptyMesh)
{
  vtkNew<vtkPolyData> empty;
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(empty, {}, mesh, origin);
  EXPECT_TRUE(report.Valid);
  EXPECT_EQ(mesh.NumberOfTriangles(), 0);
  EXPECT_TRUE(report.Warnings().empty());
}

TEST(InputPreparation, NaNIsRejected)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto pd = MakePolyData({ 0, 0, 0, 1, 0, 0, nan, 1, 0 }, { { 0, 1, 2 } });
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
  EXPECT_FALSE(report.Valid);
  EXPECT_NE(report.Error.find("NaN"), std::string::npos);
  EXPECT_EQ(report.NonFinitePoints, 1);
}

// Point ids outside the point array (too large or negative, in polygons or strips) make the input
// unusable: an error naming the cell, never a read outside the array.
TEST(InputPreparation, OutOfRangeCellIdsAreRejected)
{
  const std::vector<double> points{ 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
  for (vtkIdType bad : { vtkIdType(4), vtkIdType(1000000), vtkIdType(-1) })
  {
    for (bool strip : { false, true })
    {
      SCOPED_TRACE(std::to_string(bad) + (strip ? " strip" : " polygon"));
      auto pd = MakePolyData(points, { { 0, 1, 2 } });
      vtkNew<vtkCellArray> cells;
      const vtkIdType ids[4] = { 1, 3, 2, bad };
      cells->InsertNextCell(strip ? 4 : 3, strip ? ids : ids + 1);
      if (!strip)
      {
        cells->InsertNextCell(3, ids + 1);
        cells->ReplaceCellAtId(1, 3, std::vector<vtkIdType>{ 1, bad, 2 }.data());
        pd->SetPolys(cells);
      }
      else
      {
        pd->SetStrips(cells);
      }
      TriangleMesh mesh;
      std::vector<Index> origin;
      const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
      EXPECT_FALSE(report.Valid);
      EXPECT_NE(report.Error.find(std::to_string(bad)), std::string::npos) << report.Error;
      EXPECT_EQ(mesh.NumberOfTriangles(), 0);
    }
  }
  // Polygons without points.
  vtkNew<vtkPolyData> noPoints;
  vtkNew<vtkCellArray> cells;
  const vtkIdType tri[3] = { 0, 1, 2 };
  cells->InsertNextCell(3, tri);
  noPoints->SetPolys(cells);
  TriangleMesh mesh;
  std::vector<Index> origin;
  EXPECT_FALSE(PrepareTriangleMesh(noPoints, {}, mesh, origin).Valid);
}

TEST(InputPreparation, PolygonsLinesDuplicatesDegenerates)
{
  // A quad, a triangle beside it, a degenerate triangle, the same triangle repeated with the same
  // winding, and a line.
  auto pd = MakePolyData({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0 },
    { { 0, 1, 2, 3 }, { 1, 4, 2 }, { 0, 0, 1 }, { 4, 2, 1 } }, { { 0, 2 } });
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(report.TriangulatedPolygons, 1);
  EXPECT_EQ(report.IgnoredLineCells, 1);
  EXPECT_EQ(report.MergedPoints, 0);
  EXPECT_EQ(report.RemovedDegenerateTriangles, 1);
  EXPECT_EQ(report.RemovedDuplicateTriangles, 1);
  EXPECT_EQ(mesh.NumberOfTriangles(), 3);
  EXPECT_EQ(mesh.NumberOfPoints(), 5);
  EXPECT_FALSE(report.Warnings().empty());
  // Each mesh vertex maps back to an input point with the same coordinates.
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    double p[3];
    pd->GetPoint(origin[v], p);
    EXPECT_EQ(mesh.Point(v), (Vec3{ p[0], p[1], p[2] }));
  }
}

TEST(InputPreparation, InconsistentOrientationIsRepaired)
{
  TriangleMesh sphere = Sphere(12, 10);
  // Flip a few triangles.
  for (Index t = 0; t < 5; ++t)
  {
    std::swap(sphere.Triangles[3 * t + 1], sphere.Triangles[3 * t + 2]);
  }
  EXPECT_GT(ComputeMeshStatistics(sphere).InconsistentlyOrientedEdges, 0);
  auto pd = ToPolyData(sphere);
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
  EXPECT_EQ(report.FlippedTriangles, 5);
  EXPECT_EQ(ComputeMeshStatistics(mesh).InconsistentlyOrientedEdges, 0);
}

TEST(InputPreparation, NonManifoldEdgesAreReported)
{
  auto pd = ToPolyData(NonManifoldFan(3));
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
  EXPECT_TRUE(report.Valid);
  EXPECT_EQ(report.NonManifoldEdges, 1);
}

// --- lean input preparation (qtc session 2) ---
// The preparation's counts agree with MeshTopology's statistics of the prepared mesh, including
// inputs whose orientation needed repair (shuffled meshes), holes and pinched vertices.
TEST(InputPreparation, CountsMatchMeshStatistics)
{
  for (const char* name : { "cube-shuffled", "blobby-shuffled", "elephant-with-holes", "mech-holes-shark" })
  {
    SCOPED_TRACE(name);
    auto pd = LoadTestMesh(name);
    TriangleMesh mesh;
    std::vector<Index> origin;
    const PreparationReport report = PrepareTriangleMesh(pd, {}, mesh, origin);
    ASSERT_TRUE(report.Valid);
    const MeshStatistics stats = ComputeMeshStatistics(mesh);
    EXPECT_EQ(report.NonManifoldEdges, stats.NonManifoldEdges);
    EXPECT_EQ(report.NonManifoldVertices, stats.NonManifoldVertices);
    if (report.NonOrientableComponents == 0)
    {
      EXPECT_EQ(stats.InconsistentlyOrientedEdges, 0);
    }
    ASSERT_EQ(origin.size(), size_t(mesh.NumberOfPoints()));
    for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
    {
      double p[3];
      pd->GetPoint(origin[v], p);
      EXPECT_EQ(mesh.Point(v), (Vec3{ p[0], p[1], p[2] }));
    }
  }
  // A bow tie: two fans at one vertex.
  auto bowTie = MakePolyData({ 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0 }, { { 0, 1, 2 }, { 0, 3, 4 } });
  TriangleMesh mesh;
  std::vector<Index> origin;
  const PreparationReport report = PrepareTriangleMesh(bowTie, {}, mesh, origin);
  EXPECT_EQ(report.NonManifoldVertices, 1);
  EXPECT_EQ(report.NonManifoldEdges, 0);
}

namespace
{
// Closed cones of n sides (apex, ring, base centre), `count` of them sharing the apex at point 0:
// no border or non-manifold edge at the apex, so only its fan walk tells that two cones pinch it.
vtkSmartPointer<vtkPolyData> ConesSharingApex(int n, int count)
{
  std::vector<double> xyz{ 0, 0, 0 };
  std::vector<std::vector<vtkIdType>> polys;
  for (int c = 0; c < count; ++c)
  {
    const double side = c == 0 ? 1.0 : -1.0;
    const vtkIdType ring = static_cast<vtkIdType>(xyz.size() / 3);
    for (int i = 0; i < n; ++i)
    {
      const double angle = 2 * vtkMath::Pi() * i / n;
      xyz.insert(xyz.end(), { std::cos(angle), std::sin(angle), side });
    }
    const vtkIdType centre = ring + n;
    xyz.insert(xyz.end(), { 0, 0, side });
    for (int i = 0; i < n; ++i)
    {
      const vtkIdType a = ring + i, b = ring + (i + 1) % n;
      polys.push_back(side > 0 ? std::vector<vtkIdType>{ 0, a, b } : std::vector<vtkIdType>{ 0, b, a });
      polys.push_back(side > 0 ? std::vector<vtkIdType>{ centre, b, a } : std::vector<vtkIdType>{ centre, a, b });
    }
  }
  return MakePolyData(xyz, polys);
}
} // namespace

// The interior-vertex walk of the preparation (its own star read once, up to 32 triangles) and
// the general walk (larger stars) agree with MeshTopology's count on pinched and manifold apexes.
TEST(InputPreparation, PinchedClosedFansAreNonManifold)
{
  for (int n : { 3, 12, 40 })
  {
    for (int count : { 1, 2 })
    {
      SCOPED_TRACE(std::to_string(count) + " cones of " + std::to_string(n) + " sides");
      TriangleMesh mesh;
      std::vector<Index> origin;
      const PreparationReport report = PrepareTriangleMesh(ConesSharingApex(n, count), {}, mesh, origin);
      ASSERT_TRUE(report.Valid);
      EXPECT_EQ(report.NonManifoldVertices, count - 1);
      EXPECT_EQ(report.NonManifoldEdges, 0);
      EXPECT_EQ(ComputeMeshStatistics(mesh).NonManifoldVertices, count - 1);
      const auto apex = std::find(origin.begin(), origin.end(), 0);
      ASSERT_NE(apex, origin.end());
      EXPECT_EQ(NonManifoldVertexFlags(mesh)[apex - origin.begin()], count == 2 ? 1 : 0);
    }
  }
}

// The edge classification and the fan walks of the preparation run in parallel over the vertices:
// on a noisy scan (border, non-manifold edges and pinched vertices) with every seventh triangle
// reversed (so the orientation is repaired), the prepared mesh, the per-vertex flags and the counts
// are the same for 1, 2 and 8 threads, and the counts are MeshTopology's.
TEST(InputPreparation, SameReportForOneTwoAndEightThreads)
{
  vtkSmartPointer<vtkPolyData> scan = NoisyScanIsosurface(40, 3);
  std::vector<std::vector<vtkIdType>> cells = CellPointIds(scan->GetPolys());
  for (size_t c = 0; c < cells.size(); c += 7)
  {
    std::reverse(cells[c].begin(), cells[c].end());
  }
  vtkNew<vtkCellArray> polys;
  for (const auto& cell : cells)
  {
    polys->InsertNextCell(static_cast<vtkIdType>(cell.size()), cell.data());
  }
  vtkNew<vtkPolyData> input;
  input->SetPoints(scan->GetPoints());
  input->SetPolys(polys);
  std::vector<TriangleMesh> meshes;
  std::vector<PreparationReport> reports;
  std::vector<std::vector<unsigned char>> flags;
  ForOneTwoAndEightThreads([&](int) {
    meshes.emplace_back();
    std::vector<Index> origin;
    reports.push_back(PrepareTriangleMesh(input, {}, meshes.back(), origin));
    flags.push_back(NonManifoldVertexFlags(meshes.back()));
  });
  ASSERT_EQ(reports.size(), 3u);
  const MeshStatistics statistics = ComputeMeshStatistics(meshes[0]);
  ASSERT_GT(reports[0].FlippedTriangles, 0) << "the orientation repair did not run";
  ASSERT_GT(reports[0].NonManifoldEdges, 0);
  ASSERT_GT(reports[0].NonManifoldVertices, reports[0].NonManifoldEdges) << "no pinched vertex";
  ASSERT_GT(statistics.BoundaryEdges, 0);
  EXPECT_EQ(reports[0].NonManifoldEdges, statistics.NonManifoldEdges);
  EXPECT_EQ(reports[0].NonManifoldVertices, statistics.NonManifoldVertices);
  EXPECT_EQ(flags[0], reports[0].NonManifoldVertexFlags);
  for (size_t i = 1; i < reports.size(); ++i)
  {
    EXPECT_EQ(meshes[0].Triangles, meshes[i].Triangles) << i;
    EXPECT_EQ(reports[0].FlippedTriangles, reports[i].FlippedTriangles) << i;
    EXPECT_EQ(reports[0].NonManifoldEdges, reports[i].NonManifoldEdges) << i;
    EXPECT_EQ(reports[0].NonManifoldVertices, reports[i].NonManifoldVertices) << i;
    EXPECT_EQ(reports[0].NonManifoldVertexFlags, reports[i].NonManifoldVertexFlags) << i;
    EXPECT_EQ(reports[0].BoundaryVertexFlags, reports[i].BoundaryVertexFlags) << i;
    EXPECT_EQ(flags[0], flags[i]) << i;
  }
}

namespace
{
// Every triangle of `triangles` with its own three copies of its corners (as an STL file has them).
vtkSmartPointer<vtkPolyData> Soup(const std::vector<double>& xyz, const std::vector<std::vector<vtkIdType>>& triangles)
{
  std::vector<double> points;
  std::vector<std::vector<vtkIdType>> cells;
  for (const auto& tri : triangles)
  {
    cells.push_back({});
    for (vtkIdType v : tri)
    {
      cells.back().push_back(static_cast<vtkIdType>(points.size() / 3));
      points.insert(points.end(), { xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2] });
    }
  }
  return MakePolyData(points, cells);
}

MeshStatistics Prepared(vtkPolyData* pd, PreparationReport& report)
{
  TriangleMesh mesh;
  std::vector<Index> origin;
  report = PrepareTriangleMesh(pd, {}, mesh, origin);
  return ComputeMeshStatistics(mesh);
}
} // namespace

// Coincident points are merged only where they seal an open border: a triangle soup (every edge
// cut open) becomes the closed surface it describes; -0 and +0 are the same point.
TEST(InputPreparation, CoincidentPointsSealOpenBorders)
{
  const std::vector<double> octahedron{ 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1 };
  const std::vector<std::vector<vtkIdType>> faces{ { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 },
    { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
  auto soup = Soup(octahedron, faces);
  soup->GetPoints()->SetPoint(1, -0.0, 1, -0.0); // the first copy of vertex 2, with -0
  PreparationReport report;
  const MeshStatistics stats = Prepared(soup, report);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(report.MergedPoints, 24 - 6);
  EXPECT_EQ(stats.Vertices, 6);
  EXPECT_EQ(stats.BoundaryEdges, 0);
  EXPECT_EQ(stats.NonManifoldEdges, 0);
  EXPECT_EQ(stats.EulerCharacteristic, 2);
  // A copy that differs by 1e-7 is another point: that seam stays open.
  soup->GetPoints()->SetPoint(0, 1, 1e-7, 0);
  const MeshStatistics open = Prepared(soup, report);
  EXPECT_EQ(report.MergedPoints, 24 - 7);
  EXPECT_EQ(open.BoundaryLoops, 1);
}

// A texture seam: the octahedron soup with texture coordinates that differ between its two halves
// (the triangles around vertex 3 against those around vertex 2), as a sphere's texture seam. The
// copies of a vertex on the seam are never welded across it (each half keeps its coordinates: the
// seam is a border of two loops), while copies with equal coordinates still merge.
TEST(InputPreparation, AttributeSeamsAreNotWelded)
{
  const std::vector<double> octahedron{ 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1 };
  const std::vector<std::vector<vtkIdType>> faces{ { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 },
    { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
  auto soup = Soup(octahedron, faces);
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TextureCoordinates");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(soup->GetNumberOfPoints());
  tcoords->Fill(0.5);
  soup->GetPointData()->SetTCoords(tcoords);
  PreparationReport report;
  MeshStatistics stats = Prepared(soup, report);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(report.MergedPoints, 24 - 6);
  EXPECT_EQ(report.AttributeSeamPoints, 0);
  EXPECT_EQ(stats.BoundaryEdges, 0);
  // Triangles 2, 3, 6, 7 (soup points 6-11 and 18-23) are the half around vertex 3.
  for (vtkIdType p : { 6, 7, 8, 9, 10, 11, 18, 19, 20, 21, 22, 23 })
  {
    tcoords->SetComponent(p, 0, 1.0);
  }
  stats = Prepared(soup, report);
  EXPECT_EQ(report.AttributeSeamPoints, 4); // vertices 0, 1, 4 and 5 are on the seam
  EXPECT_EQ(stats.Vertices, 10);
  EXPECT_EQ(report.MergedPoints, 24 - 10);
  EXPECT_EQ(stats.Components, 2);
  EXPECT_EQ(stats.BoundaryLoops, 2);
  EXPECT_EQ(stats.BoundaryEdges, 8);
  EXPECT_EQ(stats.NonManifoldVertices, 0);
}

// Two closed surfaces touching at one point (cow.off has such a pair) and a sheet touching itself
// stay as they are: merging would make a non-manifold vertex and change the Euler characteristic.
TEST(InputPreparation, CoincidentPointsAwayFromBordersStayApart)
{
  // Two tetrahedra whose apexes coincide (points 3 and 7).
  auto pd = MakePolyData({ 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 0, 0, 1 },
    { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 2, 0, 3 }, { 4, 5, 6 }, { 4, 7, 5 }, { 5, 7, 6 }, { 6, 7, 4 } });
  PreparationReport report;
  const MeshStatistics stats = Prepared(pd, report);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(report.MergedPoints, 0);
  EXPECT_EQ(report.CoincidentPointsKeptApart, 1);
  EXPECT_EQ(stats.Vertices, 8);
  EXPECT_EQ(stats.NonManifoldVertices, 0);
  EXPECT_EQ(stats.EulerCharacteristic, 4);
  EXPECT_FALSE(report.Warnings().empty());
}

namespace
{
Index ZeroLengthEdgeCount(const TriangleMesh& mesh)
{
  Index count = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      count += mesh.Point(tri[k]) == mesh.Point(tri[(k + 1) % 3]) ? 1 : 0;
    }
  }
  return count;
}
} // namespace

// Marching cubes' vertices at a sample equal to the iso-value: several coincident points joined by
// edges of length zero. Kept as they are by default; with CollapseZeroLengthEdges every such edge
// is collapsed (a sphere allows each), the surface's shape and topology unchanged and the maps to
// the input's points and cells still right.
TEST(InputPreparation, ZeroLengthEdgesCollapseOnlyWhenAsked)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::SphereThroughSamples(24, 81.0);
  PreparationOptions options;
  TriangleMesh plain, merged;
  std::vector<Index> plainPoints, mergedPoints, plainCells, mergedCells;
  const PreparationReport plainReport = PrepareTriangleMesh(input, options, plain, plainPoints, &plainCells);
  options.CollapseZeroLengthEdges = true;
  const PreparationReport report = PrepareTriangleMesh(input, options, merged, mergedPoints, &mergedCells);
  ASSERT_TRUE(plainReport.Valid && report.Valid);
  const MeshStatistics before = ComputeMeshStatistics(plain), after = ComputeMeshStatistics(merged);
  ASSERT_GT(ZeroLengthEdgeCount(plain), 0);
  ASSERT_GT(before.DegenerateTriangles, 0);
  EXPECT_EQ(plainReport.CollapsedZeroLengthEdges, 0);
  EXPECT_GT(report.CollapsedZeroLengthEdges, 0);
  EXPECT_EQ(ZeroLengthEdgeCount(merged), 0);
  EXPECT_EQ(after.DegenerateTriangles, 0);
  EXPECT_EQ(merged.NumberOfPoints(), plain.NumberOfPoints() - report.CollapsedZeroLengthEdges);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.Components, before.Components);
  EXPECT_EQ(after.BoundaryEdges, 0);
  EXPECT_EQ(after.NonManifoldVertices, 0);
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
  EXPECT_NEAR(merged.TotalArea(), plain.TotalArea(), 1e-12 * plain.TotalArea());
  EXPECT_EQ(report.NonManifoldVertexFlags.size(), size_t(merged.NumberOfPoints()));
  EXPECT_EQ(report.BoundaryVertexFlags.size(), size_t(merged.NumberOfPoints()));
  ASSERT_EQ(mergedPoints.size(), size_t(merged.NumberOfPoints()));
  for (Index v = 0; v < merged.NumberOfPoints(); ++v)
  {
    double p[3];
    input->GetPoint(mergedPoints[v], p);
    ASSERT_EQ(merged.Point(v), (Vec3{ p[0], p[1], p[2] }));
  }
  // Each triangle is its input cell with a corner at most replaced by a coincident point.
  ASSERT_EQ(mergedCells.size(), size_t(merged.NumberOfTriangles()));
  for (Index t = 0; t < merged.NumberOfTriangles(); ++t)
  {
    std::vector<Vec3> corners, cell;
    for (int k = 0; k < 3; ++k)
    {
      double p[3];
      input->GetPoint(input->GetCell(mergedCells[t])->GetPointId(k), p);
      cell.push_back(Vec3{ p[0], p[1], p[2] });
      corners.push_back(merged.Point(merged.Triangle(t)[k]));
    }
    std::sort(corners.begin(), corners.end());
    std::sort(cell.begin(), cell.end());
    ASSERT_EQ(corners, cell);
  }
}

// A triangle and its mirror image are two sides of a closed sheet: both are kept; an exact repeat
// (same winding) is removed.
TEST(InputPreparation, MirrorTrianglesAreKeptRepeatsRemoved)
{
  auto pd = MakePolyData({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 2, 0 } });
  PreparationReport report;
  const MeshStatistics stats = Prepared(pd, report);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(report.RemovedDuplicateTriangles, 1);
  EXPECT_EQ(stats.Triangles, 2);
  EXPECT_EQ(stats.BoundaryEdges, 0);
  EXPECT_EQ(stats.EulerCharacteristic, 2);
}

TEST(PointAttributes, CarriedThroughMergesWithTypes)
{
  vtkNew<vtkPointData> input;
  vtkNew<vtkFloatArray> temperature;
  temperature->SetName("Temperature");
  vtkNew<vtkIntArray> label;
  label->SetName("Label");
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  for (int i = 0; i < 4; ++i)
  {
    temperature->InsertNextValue(10.0f * i);
    label->InsertNextValue(i);
  }
  normals->InsertNextTuple3(1, 0, 0);
  normals->InsertNextTuple3(0, 1, 0);
  normals->InsertNextTuple3(0, 0, 1);
  normals->InsertNextTuple3(0, 0, 1);
  input->AddArray(temperature);
  input->AddArray(label);
  input->SetNormals(normals);

  PointAttributes attributes;
  attributes.Load(input, { 3, 0, 1 }); // rows: input points 3, 0, 1
  EXPECT_EQ(attributes.GetNumberOfArrays(), 3);
  const Index sources[2] = { 1, 2 };
  const double weights[2] = { 1, 1 };
  attributes.Merge(1, sources, weights, 2); // row 1 := mean of input points 0 and 1
  const Index added = attributes.AddInterpolated(sources, weights, 2);
  EXPECT_EQ(added, 3);

  vtkNew<vtkPointData> output;
  attributes.Store(output, { 0, 1 });
  auto* t = vtkFloatArray::SafeDownCast(output->GetArray("Temperature"));
  ASSERT_NE(t, nullptr);
  EXPECT_FLOAT_EQ(t->GetValue(0), 30.0f);
  EXPECT_FLOAT_EQ(t->GetValue(1), 5.0f);
  ASSERT_NE(vtkIntArray::SafeDownCast(output->GetArray("Label")), nullptr);
  ASSERT_NE(output->GetNormals(), nullptr);
  double n[3];
  output->GetNormals()->GetTuple(1, n);
  EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-12); // averaged and renormalised
  EXPECT_NEAR(n[1], std::sqrt(0.5), 1e-12);
  int normalsIndex = -1;
  output->GetAbstractArray("Normals", normalsIndex);
  EXPECT_EQ(output->IsArrayAnAttribute(normalsIndex), vtkDataSetAttributes::NORMALS) << "role lost";
}

// VTK's conventions: integer arrays are rounded, never fractional; ids (global ids, vtkIdType
// arrays) are labels taken from the heaviest source, whatever the order of the sources.
TEST(PointAttributes, IdsAreTakenFromTheHeaviestSourceAndIntegersRounded)
{
  vtkNew<vtkPointData> input;
  vtkNew<vtkIntArray> label;
  label->SetName("Label");
  vtkNew<vtkIntArray> global;
  global->SetName("Global");
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("Ids");
  for (int i = 0; i < 3; ++i)
  {
    label->InsertNextValue(i);           // 0, 1, 2
    global->InsertNextValue(100 + 400 * i); // 100, 500, 900: an average would be none of them
    ids->InsertNextValue(200 + 400 * i);
  }
  input->AddArray(label);
  input->SetGlobalIds(global);
  input->AddArray(ids);
  PointAttributes attributes;
  attributes.Load(input, { 0, 1, 2 });
  const Index sources[3] = { 0, 1, 2 };
  const double heaviestFirst[3] = { 0.5, 0.3, 0.2 }, heaviestInMiddle[3] = { 0.1, 0.6, 0.3 };
  const Index first = attributes.AddInterpolated(sources, heaviestFirst, 3);
  const Index middle = attributes.AddInterpolated(sources, heaviestInMiddle, 3);
  vtkNew<vtkPointData> output;
  attributes.Store(output, { first, middle });
  ASSERT_NE(output->GetGlobalIds(), nullptr) << "global ids left out (VTK's default for interpolation)";
  EXPECT_EQ(output->GetGlobalIds()->GetComponent(0, 0), 100);
  EXPECT_EQ(output->GetGlobalIds()->GetComponent(1, 0), 500);
  ASSERT_NE(output->GetArray("Ids"), nullptr) << "vtkIdType array left out (VTK never interpolates them)";
  EXPECT_EQ(output->GetArray("Ids")->GetDataType(), VTK_ID_TYPE);
  EXPECT_EQ(output->GetArray("Ids")->GetComponent(0, 0), 200);
  EXPECT_EQ(output->GetArray("Ids")->GetComponent(1, 0), 600);
  ASSERT_NE(vtkIntArray::SafeDownCast(output->GetArray("Label")), nullptr);
  EXPECT_EQ(output->GetArray("Label")->GetComponent(0, 0), 1); // 0.3 * 1 + 0.2 * 2 = 0.7, rounded
  EXPECT_EQ(output->GetArray("Label")->GetComponent(1, 0), 1); // 0.6 + 0.6 = 1.2
}

// Each prepared triangle names the input cell it comes from: vtkPolyData numbers vertices and
// lines first, then polygons, then strips; a triangulated polygon or strip gives all its triangles
// its own id, and removed triangles leave no entry.
TEST(InputPreparation, EachTriangleNamesItsInputCell)
{
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 12; ++i)
  {
    points->InsertNextPoint(i % 4, i / 4, 0.1 * (i % 3)); // a 4 x 3 grid, gently bent
  }
  vtkNew<vtkPolyData> input;
  input->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys, strips;
  const vtkIdType vertex[1] = { 0 }, line[2] = { 0, 1 };
  verts->InsertNextCell(1, vertex);                  // cell 0
  lines->InsertNextCell(2, line);                    // cell 1
  const vtkIdType quad[4] = { 0, 1, 5, 4 }, triangle[3] = { 1, 2, 6 }, repeated[3] = { 2, 2, 6 };
  const vtkIdType pentagon[5] = { 2, 3, 7, 11, 10 };
  polys->InsertNextCell(4, quad);                    // cell 2: two triangles
  polys->InsertNextCell(3, repeated);                // cell 3: removed (repeated vertex)
  polys->InsertNextCell(3, triangle);                // cell 4
  polys->InsertNextCell(5, pentagon);                // cell 5: three triangles
  const vtkIdType strip[5] = { 4, 8, 5, 9, 6 };
  strips->InsertNextCell(5, strip);                  // cell 6: three triangles
  input->SetVerts(verts);
  input->SetLines(lines);
  input->SetPolys(polys);
  input->SetStrips(strips);
  TriangleMesh mesh;
  std::vector<Index> vertexToInput, triangleToCell;
  const PreparationReport report = PrepareTriangleMesh(input, PreparationOptions(), mesh, vertexToInput, &triangleToCell);
  ASSERT_TRUE(report.Valid);
  EXPECT_EQ(triangleToCell, (std::vector<Index>{ 2, 2, 4, 5, 5, 5, 6, 6, 6 }));
  ASSERT_EQ(static_cast<Index>(triangleToCell.size()), mesh.NumberOfTriangles());
  // Each triangle's corners are points of its cell.
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    vtkIdType n;
    const vtkIdType* ids;
    input->GetCellPoints(triangleToCell[t], n, ids);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_NE(std::find(ids, ids + n, vertexToInput[mesh.Triangle(t)[k]]), ids + n) << "triangle " << t;
    }
  }
}

TEST(EditableMesh, BorderEarIsNotCollapsedAway)
{
  // An ear (a, x, b) below the interior edge (a, b): collapsing (a, b) would leave x without
  // triangles and shorten the border loop through x, so it is refused.
  TriangleMesh m;
  const Index a = m.AddPoint({ 0, 0, 0 }), b = m.AddPoint({ 1, 0, 0 }), x = m.AddPoint({ 0.5, -1, 0 });
  const Index y = m.AddPoint({ 0.5, 1, 0 }), z = m.AddPoint({ -0.5, 1, 0 }), w = m.AddPoint({ 1.5, 1, 0 });
  m.AddTriangle(a, x, b);
  m.AddTriangle(a, b, y);
  m.AddTriangle(a, y, z);
  m.AddTriangle(b, w, y);
  EditableMesh mesh(m);
  const Index edge[2] = { a, b };
  const CollapseStatus status = mesh.CheckCollapse(edge, 2, 0.5 * (m.Point(a) + m.Point(b)));
  EXPECT_TRUE(status == CollapseStatus::BoundaryChange || status == CollapseStatus::IsolatedVertex) << ToString(status);
  // Along the border edge (a, x) the collapse is fine.
  const Index borderEdge[2] = { a, x };
  EXPECT_EQ(mesh.CheckCollapse(borderEdge, 2, m.Point(a)), CollapseStatus::Ok);
}

// Session 30: the link test lists the survivors and the two-member triangles of a set for the
// isolated-vertex and geometry tests, up to 64 survivors; larger fans take the full scans. A
// closed bipyramid and an open cone (its rim a border) with 8 and 100 rim vertices give the same
// answers for the same operations on both sides of that capacity, with the mesh's marks and with
// a scratch table: an apex-rim edge is fine, apex and bottom (two fans) are refused, moving the
// apex through the bottom or beyond the far rim folds triangles (also found by the set trial's own
// geometry code), merging two rim vertices of the open cone that are not neighbours is refused.
TEST(EditableMesh, LargeFansGiveTheAnswersOfSmallOnes)
{
  for (const bool open : { false, true })
  {
    for (const int n : { 8, 100 })
    {
      TriangleMesh m;
      const Index top = m.AddPoint({ 0, 0, 1 }), bottom = m.AddPoint({ 0, 0, -1 });
      std::vector<Index> rim;
      for (int i = 0; i < n; ++i)
      {
        const double a = 2 * vtkMath::Pi() * i / n;
        rim.push_back(m.AddPoint({ std::cos(a), std::sin(a), 0 }));
      }
      for (int i = 0; i < n; ++i)
      {
        m.AddTriangle(top, rim[i], rim[(i + 1) % n]);
        if (!open)
        {
          m.AddTriangle(bottom, rim[(i + 1) % n], rim[i]);
        }
      }
      EditableMesh mesh(m);
      EditableMesh::CheckScratch scratch;
      const auto check = [&](const Index* set, int count, const Vec3& p) {
        const CollapseStatus marks = mesh.CheckCollapse(set, count, p);
        EXPECT_EQ(marks, mesh.CheckCollapse(set, count, p, CollapseOptions(), scratch)) << n;
        return marks;
      };
      const Index spoke[2] = { top, rim[0] };
      EXPECT_EQ(check(spoke, 2, m.Point(top)), CollapseStatus::Ok) << "n " << n << " open " << open;
      EXPECT_EQ(check(spoke, 2, Vec3{ 0, 0, -3 }), CollapseStatus::Flip) << "n " << n << " open " << open;
      // Beyond the rim vertex opposite rim[0]: the triangles there fold, far down the 100-gon's fan.
      const Vec3 across = 3.0 * m.Point(rim[n / 2 + 1]) - 2.0 * m.Point(top);
      const CollapseStatus folded = check(spoke, 2, across);
      EXPECT_TRUE(folded == CollapseStatus::Flip || folded == CollapseStatus::Degenerate) << ToString(folded);
      // The trial's own geometry code (no lists) agrees at every point.
      EditableMesh::SetTrial trial;
      mesh.PrepareTrial(spoke, 2, CollapseOptions(), trial);
      for (const Vec3& p : { m.Point(top), Vec3{ 0, 0, -3 }, across, m.Point(rim[0]) })
      {
        EXPECT_EQ(mesh.CheckCollapse(spoke, 2, p) == CollapseStatus::Ok,
          mesh.CheckTrial(p, CollapseOptions(), trial, nullptr) == CollapseStatus::Ok)
          << n;
      }
      if (!open)
      {
        const Index poles[2] = { top, bottom };
        EXPECT_EQ(check(poles, 2, Vec3{ 0, 0, 0 }), CollapseStatus::NonManifold) << n;
      }
      else
      {
        const Index apart[2] = { rim[0], rim[n / 2] };
        EXPECT_NE(check(apart, 2, m.Point(rim[0])), CollapseStatus::Ok) << n;
      }
    }
  }
}

// BoundaryVertexFlags (all vertices in one pass, the fans' corners matched on the stack; session
// 43) gives IsBoundaryVertex of every vertex: on a noisy scan isosurface (borders, handles,
// non-manifold edges) before and after collapses (dead vertices and triangles, merged fans), a
// torus (no border) and open and closed fans of 8 and 100 triangles (more than the stack holds:
// IsBoundaryVertex itself), with the mesh's marks and with its table.
TEST(EditableMesh, BoundaryVertexFlagsAreIsBoundaryVertexOfEveryVertex)
{
  std::vector<TriangleMesh> inputs{ ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16) };
  for (const bool open : { false, true })
  {
    for (const int n : { 8, 100 })
    {
      TriangleMesh m;
      const Index top = m.AddPoint({ 0, 0, 1 }), bottom = m.AddPoint({ 0, 0, -1 });
      for (int i = 0; i < n; ++i)
      {
        const double a = 2 * vtkMath::Pi() * i / n;
        m.AddPoint({ std::cos(a), std::sin(a), 0 });
      }
      for (int i = 0; i < n; ++i)
      {
        m.AddTriangle(top, 2 + i, 2 + (i + 1) % n);
        if (!open)
        {
          m.AddTriangle(bottom, 2 + (i + 1) % n, 2 + i);
        }
      }
      inputs.push_back(m);
    }
  }
  size_t borders = 0, interior = 0;
  for (const TriangleMesh& input : inputs)
  {
    for (const bool marks : { true, false })
    {
      EditableMesh mesh;
      mesh.SetVertexLinkMarks(marks);
      mesh.Reset(input);
      for (const int steps : { 0, input.NumberOfTriangles() / 20 })
      {
        CollapseTrianglesGreedily(mesh, steps);
        std::vector<unsigned char> flags{ 7 }; // (replaced whole)
        mesh.BoundaryVertexFlags(flags);
        ASSERT_EQ(flags.size(), size_t(mesh.NumberOfPoints()));
        for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
        {
          ASSERT_EQ(flags[size_t(v)], mesh.IsBoundaryVertex(v) ? 1 : 0)
            << "vertex " << v << " of " << mesh.NumberOfPoints() << ", " << steps << " collapses";
          borders += flags[size_t(v)];
          interior += 1 - flags[size_t(v)];
        }
      }
    }
  }
  EXPECT_GT(borders, 100u);
  EXPECT_GT(interior, 1000u);
}

// The mean absolute curvature: about 1/R on a sphere (the discrete sum converges to it), exactly
// 1/s of it when the mesh is scaled by s, zero on a flat grid.
TEST(MeshTopology, MeanAbsoluteCurvatureOfSphereAndPlane)
{
  slod::TriangleMesh sphere = slodtest::Sphere(64, 64); // radius 0.5
  const double curvature = slod::MeanAbsoluteCurvature(sphere, slod::MeshTopology(sphere));
  EXPECT_NEAR(curvature, 2.0, 0.05);
  for (slod::Index v = 0; v < sphere.NumberOfPoints(); ++v)
  {
    sphere.SetPoint(v, 3.0 * sphere.Point(v));
  }
  EXPECT_NEAR(slod::MeanAbsoluteCurvature(sphere, slod::MeshTopology(sphere)), curvature / 3.0, 1e-9 * curvature);
  const slod::TriangleMesh grid = slodtest::Grid(10, 10);
  EXPECT_EQ(slod::MeanAbsoluteCurvature(grid, slod::MeshTopology(grid)), 0.0);
}

// With a crease angle, edges bent by more than it are left out (issue 15, session 25: SPBM's
// thickness bound): a tetrahedron (every edge bent by about 109 degrees) is all creases, the
// fine sphere (every edge bent by a few degrees) has none.
TEST(MeshTopology, MeanAbsoluteCurvatureWithoutCreases)
{
  const double creaseAngle = slod::Radians(60.0);
  const slod::TriangleMesh tetrahedron = slodtest::Tetrahedron();
  EXPECT_GT(slod::MeanAbsoluteCurvature(tetrahedron, slod::MeshTopology(tetrahedron)), 0.0);
  EXPECT_EQ(slod::MeanAbsoluteCurvature(tetrahedron, slod::MeshTopology(tetrahedron), creaseAngle), 0.0);
  const slod::TriangleMesh sphere = slodtest::Sphere(64, 64);
  const slod::MeshTopology topology(sphere);
  EXPECT_EQ(slod::MeanAbsoluteCurvature(sphere, topology, creaseAngle), slod::MeanAbsoluteCurvature(sphere, topology));
}

// Session 41 (issue 10): a bend counts as noise when it is sharper than the angle while the two
// triangles stay within the plane distance of each other's plane. A grid whose vertices alternate
// a little up and down bends at many of its edges; the same grid with the jitter 100 times larger
// bends as sharply at the same edges but beyond the plane distance; a fine sphere bends little.
TEST(MeshTopology, NoisyBendShareCountsSharpButShallowBends)
{
  const double angle = slod::Radians(20.0);
  auto jittered = [](double amplitude) {
    slod::TriangleMesh grid = slodtest::Grid(40, 40);
    for (slod::Index v = 0; v < grid.NumberOfPoints(); ++v)
    {
      slod::Vec3 p = grid.Point(v);
      p[2] = (v % 3 == 0 ? amplitude : (v % 3 == 1 ? -amplitude : 0.0));
      grid.SetPoint(v, p);
    }
    return grid;
  };
  const slod::TriangleMesh noisy = jittered(0.01), rough = jittered(1.0);
  const double planeDistance = 0.05; // above the noisy grid's full height (0.02)
  const double noisyShare = slod::NoisyBendShare(noisy, slod::MeshTopology(noisy), angle, planeDistance);
  EXPECT_GT(noisyShare, 0.1); // the edges between differently jittered vertices bend
  EXPECT_LE(noisyShare, 1.0);
  EXPECT_EQ(slod::NoisyBendShare(rough, slod::MeshTopology(rough), angle, planeDistance), 0.0);
  // The rough grid bends at the same edges, which count once the plane distance covers them.
  EXPECT_EQ(slod::NoisyBendShare(rough, slod::MeshTopology(rough), angle, 100 * planeDistance), noisyShare);
  const slod::TriangleMesh sphere = slodtest::Sphere(64, 64);
  EXPECT_EQ(slod::NoisyBendShare(sphere, slod::MeshTopology(sphere), angle, planeDistance), 0.0);
  const slod::TriangleMesh tetrahedron = slodtest::Tetrahedron();
  EXPECT_EQ(slod::NoisyBendShare(tetrahedron, slod::MeshTopology(tetrahedron), angle, planeDistance), 0.0);
}

// CheckCollapse with a caller's CheckScratch (its own link marks) gives the answer of the mesh's
// own marks, also when many threads check overlapping sets at once (every edge and triangle of a
// noisy scan isosurface, with its borders and non-manifold edges, after some collapses; and of a
// torus): the statuses of all sets, in parallel with 4 threads, equal the sequential ones.
TEST(EditableMesh, CheckScratchGivesTheAnswerOfTheMeshMarksConcurrently)
{
  for (const TriangleMesh& input : { ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16) })
  {
    EditableMesh mesh(input);
    CollapseTrianglesGreedily(mesh, input.NumberOfTriangles() / 20);
    std::vector<unsigned char> border(size_t(mesh.NumberOfPoints()));
    for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
    {
      border[size_t(v)] = mesh.IsVertexAlive(v) && mesh.IsBoundaryVertex(v) ? 1 : 0;
    }
    CollapseOptions options;
    options.BoundaryVertices = border.data();
    // Sets: per live triangle its three edges (at the midpoint) and itself (at the centroid).
    std::vector<std::array<Index, 3>> sets;
    std::vector<int> counts;
    std::vector<Vec3> points;
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      if (!mesh.IsTriangleAlive(t))
      {
        continue;
      }
      const Index* tri = mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        sets.push_back({ tri[k], tri[(k + 1) % 3], InvalidIndex });
        counts.push_back(2);
        points.push_back(0.5 * (mesh.Point(tri[k]) + mesh.Point(tri[(k + 1) % 3])));
      }
      sets.push_back({ tri[0], tri[1], tri[2] });
      counts.push_back(3);
      points.push_back((1.0 / 3) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2])));
    }
    std::vector<CollapseStatus> sequential(sets.size()), concurrent(sets.size());
    for (size_t i = 0; i < sets.size(); ++i)
    {
      sequential[i] = mesh.CheckCollapse(sets[i].data(), counts[i], points[i], options);
    }
    vtkSMPThreadLocal<EditableMesh::CheckScratch> scratch;
    vtkSMPTools::LocalScope(vtkSMPTools::Config{ 4 }, [&]() {
      vtkSMPTools::For(0, vtkIdType(sets.size()), 1, [&](vtkIdType begin, vtkIdType end) {
        EditableMesh::CheckScratch& own = scratch.Local();
        for (vtkIdType i = begin; i < end; ++i)
        {
          concurrent[size_t(i)] = mesh.CheckCollapse(sets[size_t(i)].data(), counts[size_t(i)], points[size_t(i)], options, own);
        }
      });
    });
    size_t ok = 0, nonManifold = 0;
    for (size_t i = 0; i < sets.size(); ++i)
    {
      ASSERT_EQ(sequential[i], concurrent[i]) << "set " << i << ": " << ToString(sequential[i]) << " vs " << ToString(concurrent[i]);
      ok += sequential[i] == CollapseStatus::Ok ? 1 : 0;
      nonManifold += sequential[i] == CollapseStatus::NonManifold ? 1 : 0;
    }
    EXPECT_GT(ok, sets.size() / 4);          // the link walk ran to its end
    EXPECT_GT(nonManifold, 20u); // and refused (a link test that never fails proves nothing)
  }
}

// Without the per-vertex link marks (SetVertexLinkMarks(false), the hierarchy's setting: 12 bytes
// per vertex less) the mesh answers as with them: the same greedy collapses (each decided by
// CheckCollapse) give the same triangles, and then every vertex has the same border flag and
// neighbours (in the same order), and every edge and triangle of the mesh the same CheckCollapse
// status, with and without border flags given (without, the check asks IsBoundaryVertex).
TEST(EditableMesh, WithoutVertexLinkMarksTheAnswersAreTheSame)
{
  const TriangleMesh inputs[2] = { ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16) };
  for (const TriangleMesh& input : inputs)
  {
    EditableMesh marked(input), unmarked;
    unmarked.SetVertexLinkMarks(false);
    unmarked.Reset(input);
    EXPECT_LE(unmarked.MemoryBytes() + 12 * size_t(input.NumberOfPoints()) - 4096 * 12, marked.MemoryBytes());
    CollapseTrianglesGreedily(marked, input.NumberOfTriangles() / 20);
    CollapseTrianglesGreedily(unmarked, input.NumberOfTriangles() / 20);
    ASSERT_EQ(marked.NumberOfLiveTriangles(), unmarked.NumberOfLiveTriangles());
    ASSERT_LT(marked.NumberOfLiveTriangles(), input.NumberOfTriangles());
    std::vector<unsigned char> border(size_t(marked.NumberOfPoints()));
    std::vector<Index> a, b;
    size_t borders = 0;
    for (Index v = 0; v < marked.NumberOfPoints(); ++v)
    {
      ASSERT_EQ(marked.IsVertexAlive(v), unmarked.IsVertexAlive(v));
      if (!marked.IsVertexAlive(v))
      {
        continue;
      }
      border[size_t(v)] = marked.IsBoundaryVertex(v) ? 1 : 0;
      ASSERT_EQ(border[size_t(v)] != 0, unmarked.IsBoundaryVertex(v)) << "vertex " << v;
      borders += border[size_t(v)];
      marked.Neighbors(v, a);
      unmarked.Neighbors(v, b);
      ASSERT_EQ(a, b) << "vertex " << v;
    }
    size_t ok = 0, refused = 0;
    for (const unsigned char* flags : std::array<const unsigned char*, 2>{ nullptr, border.data() })
    {
      CollapseOptions options;
      options.BoundaryVertices = flags;
      for (Index t = 0; t < marked.NumberOfTriangles(); ++t)
      {
        if (!marked.IsTriangleAlive(t))
        {
          continue;
        }
        const Index* tri = marked.Triangle(t);
        ASSERT_TRUE(std::equal(tri, tri + 3, unmarked.Triangle(t)));
        for (int count : { 2, 3 })
        {
          for (int k = 0; k < (count == 2 ? 3 : 1); ++k)
          {
            const Index set[3] = { tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3] };
            Vec3 p{ 0, 0, 0 };
            for (int i = 0; i < count; ++i)
            {
              p = p + (1.0 / count) * marked.Point(set[i]);
            }
            const CollapseStatus expected = marked.CheckCollapse(set, count, p, options);
            ASSERT_EQ(expected, unmarked.CheckCollapse(set, count, p, options)) << "triangle " << t;
            ok += expected == CollapseStatus::Ok ? 1 : 0;
            refused += expected == CollapseStatus::NonManifold || expected == CollapseStatus::BoundaryChange ? 1 : 0;
          }
        }
      }
    }
    EXPECT_GT(ok, 100u);
    EXPECT_GT(refused, 20u); // (a link test that never fails proves nothing)
    EXPECT_EQ(borders > 0, &input == &inputs[0]); // the scan has borders, the torus none
  }
}

namespace
{
// f(t, edge, u, v) for each edge (tri[k], tri[k + 1]) of every live triangle t, u and v its ends'
// points; then g(t, tri) for the triangle itself.
template <typename EdgeFunctor, typename TriangleFunctor>
void ForEachLiveEdgeAndTriangle(const EditableMesh& mesh, EdgeFunctor&& f, TriangleFunctor&& g)
{
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (!mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index edge[2] = { tri[k], tri[(k + 1) % 3] };
      f(t, k, edge, mesh.Point(edge[0]), mesh.Point(edge[1]));
    }
    g(t, tri);
  }
}
} // namespace

// A set prepared once and checked at several points (the hierarchy's FindEdgeCollapse tries up to
// three per edge) is accepted at exactly the points CheckCollapse accepts, with the mesh's marks
// and with a scratch's; the points include flips (beyond an end), degenerate ones and valid ones.
TEST(EditableMesh, SetTrialAcceptsWhereCheckCollapseDoesAtEveryPoint)
{
  for (const TriangleMesh& input : { ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16) })
  {
    EditableMesh mesh(input);
    CollapseTrianglesGreedily(mesh, input.NumberOfTriangles() / 20);
    for (const double minimumAngle : { 0.0, 0.2 })
    {
      CollapseOptions options;
      options.MinimumNormalDot = 0.5;
      options.MinimumAngle = minimumAngle;
      options.GeometryFirst = true;
      EditableMesh::SetTrial trial;
      EditableMesh::CheckScratch scratch;
      std::map<CollapseStatus, size_t> seen;
      size_t agreements = 0;
      ForEachLiveEdgeAndTriangle(
        mesh,
        [&](Index t, int k, const Index* edge, const Vec3& u, const Vec3& v) {
          const Vec3 points[5] = { u + 2.5 * (v - u), 0.5 * (u + v), u, v, u - 1.5 * (v - u) };
          mesh.PrepareTrial(edge, 2, options, trial);
          for (const Vec3& p : points)
          {
            const CollapseStatus expected = mesh.CheckCollapse(edge, 2, p, options);
            const CollapseStatus marks = mesh.CheckTrial(p, options, trial, nullptr);
            const CollapseStatus own = mesh.CheckTrial(p, options, trial, &scratch);
            ASSERT_EQ(expected == CollapseStatus::Ok, marks == CollapseStatus::Ok)
              << "triangle " << t << " edge " << k << ": " << ToString(expected) << " vs " << ToString(marks);
            ASSERT_EQ(marks, own);
            ++seen[expected];
            ++agreements;
          }
        },
        [](Index, const Index*) {});
      EXPECT_GT(agreements, 1000u);
      EXPECT_GT(seen[CollapseStatus::Ok], agreements / 10); // accepted points
      EXPECT_GT(seen[CollapseStatus::Flip], 20u);           // refused by the geometry
      if (minimumAngle > 0)
      {
        EXPECT_GT(seen[CollapseStatus::BadShape], 0u);
      }
    }
  }
}

// Session 42 (issue 12): a caller's SurvivorTest (the collapse hierarchy's orientation against M0)
// is asked last, only when every other test of the check passed, once per surviving triangle, with
// the area vector of that triangle with its corner moved to the point, bit for bit as computed here;
// its refusal makes the check answer Flip, and it changes no other answer. The same through
// PrepareTrial / CheckTrial. Every edge (three points) and triangle (centroid) of a noisy scan
// isosurface, a torus and a sphere whose poles have 64 triangles (more survivors than a chunk:
// the vectors are then computed again), with the geometry first and last.
namespace
{
struct RecordingSurvivorTest final : SurvivorTest
{
  bool Accept = true;
  mutable int Calls = 0;
  mutable std::vector<std::pair<Index, Vec3>> Asked;
  bool Keeps(const Index* triangles, const Vec3* vectors, int n) const override
  {
    ++this->Calls;
    for (int i = 0; i < n; ++i)
    {
      this->Asked.emplace_back(triangles[i], vectors[i]);
    }
    return this->Accept;
  }
  std::vector<std::pair<Index, Vec3>> Sorted() const
  {
    std::vector<std::pair<Index, Vec3>> asked = this->Asked;
    std::sort(asked.begin(), asked.end());
    return asked;
  }
  void Clear() const
  {
    this->Calls = 0;
    this->Asked.clear();
  }
};

// The survivors of merging the set at p with their moved area vectors, sorted.
std::vector<std::pair<Index, Vec3>> MovedSurvivors(const EditableMesh& mesh, const Index* set, int count, const Vec3& p)
{
  std::vector<std::pair<Index, Vec3>> survivors;
  mesh.ForEachSurvivingTriangle(set, count, [&](Index t, int corner) {
    const Index* tri = mesh.Triangle(t);
    Vec3 q[3] = { mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]) };
    q[corner] = p;
    survivors.emplace_back(t, Cross(q[1] - q[0], q[2] - q[0]));
  });
  std::sort(survivors.begin(), survivors.end());
  return survivors;
}
} // namespace

TEST(EditableMesh, SurvivorTestIsAskedLastWithEachSurvivorsMovedAreaVector)
{
  const TriangleMesh inputs[3] = { ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16), Sphere(64, 64) };
  size_t asked = 0, refusedBefore = 0, overChunk = 0, trialsAsked = 0;
  for (const TriangleMesh& input : inputs)
  {
    EditableMesh mesh(input);
    CollapseTrianglesGreedily(mesh, input.NumberOfTriangles() / 20);
    std::vector<unsigned char> border(size_t(mesh.NumberOfPoints()));
    for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
    {
      border[size_t(v)] = mesh.IsVertexAlive(v) && mesh.IsBoundaryVertex(v) ? 1 : 0;
    }
    for (const bool geometryFirst : { false, true })
    {
      CollapseOptions plain;
      plain.MinimumNormalDot = 0.2;
      plain.GeometryFirst = geometryFirst;
      plain.BoundaryVertices = border.data();
      RecordingSurvivorTest accepting, refusing;
      refusing.Accept = false;
      CollapseOptions accept = plain, refuse = plain;
      accept.Survivors = &accepting;
      refuse.Survivors = &refusing;
      const auto check = [&](const Index* set, int count, const Vec3& p) {
        const CollapseStatus expected = mesh.CheckCollapse(set, count, p, plain);
        accepting.Clear();
        ASSERT_EQ(mesh.CheckCollapse(set, count, p, accept), expected);
        if (expected != CollapseStatus::Ok)
        {
          ASSERT_EQ(accepting.Calls, 0) << ToString(expected); // (refused before it)
          ++refusedBefore;
        }
        else
        {
          const std::vector<std::pair<Index, Vec3>> survivors = MovedSurvivors(mesh, set, count, p);
          ASSERT_EQ(accepting.Sorted(), survivors);
          overChunk += survivors.size() > 32 ? 1 : 0;
          ++asked;
        }
        ASSERT_EQ(mesh.CheckCollapse(set, count, p, refuse), expected == CollapseStatus::Ok ? CollapseStatus::Flip : expected);
      };
      EditableMesh::SetTrial trial;
      ForEachLiveEdgeAndTriangle(
        mesh,
        [&](Index, int, const Index* edge, const Vec3& u, const Vec3& v) {
          mesh.PrepareTrial(edge, 2, accept, trial);
          for (const Vec3& p : { 0.5 * (u + v), u, u - 1.5 * (v - u) })
          {
            check(edge, 2, p);
            const CollapseStatus expected = mesh.CheckCollapse(edge, 2, p, plain);
            accepting.Clear();
            ASSERT_EQ(mesh.CheckTrial(p, accept, trial, nullptr) == CollapseStatus::Ok, expected == CollapseStatus::Ok);
            const std::vector<std::pair<Index, Vec3>> none, survivors =
              expected == CollapseStatus::Ok ? MovedSurvivors(mesh, edge, 2, p) : none;
            ASSERT_EQ(accepting.Sorted(), survivors);
            trialsAsked += accepting.Calls > 0 ? 1 : 0;
          }
        },
        [&](Index, const Index* tri) {
          check(tri, 3, (1.0 / 3) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2])));
        });
    }
  }
  EXPECT_GT(asked, 10000u);        // passed every other test
  EXPECT_GT(refusedBefore, 10000u); // refused by another test: not asked
  EXPECT_GT(overChunk, 10u);       // the poles' edges: the vectors computed again
  EXPECT_GT(trialsAsked, 10000u);
}

// Session 28: GroupByKey (the adjacency lists of the preparation stages, in parallel) gives the
// serial counting sort's lists for 1, 2 and 8 threads: items with three keys each (a triangle's
// vertices, the value the triangle id), left-out items, empty groups, and groups large enough for
// the sort of high valence; an editable mesh's blocks built in parallel and serially are the same.
TEST(GroupByKey, ParallelListsAreTheSerialOnesForAnyThreadCount)
{
  std::mt19937 random(28);
  const Index groups = 50000, items = 3 * 400000;
  std::vector<Index> keys(static_cast<size_t>(items));
  for (Index& key : keys)
  {
    const unsigned r = random() % 100;
    // Left out, a few groups of valence > 32, and the last ten groups empty.
    key = r < 3 ? Index(-1) : (r < 8 ? Index(random() % 20) : Index(random() % (groups - 10)));
  }
  auto keyOf = [&](Index i) { return keys[size_t(i)]; };
  auto valueOf = [](Index i) { return i / 3; };
  auto group = [&](bool parallel, std::vector<Index>& first, std::vector<Index>& count, std::vector<Index>& grouped) {
    first.assign(size_t(groups), -7);
    count.assign(size_t(groups), 0);
    return GroupByKey(items, groups, keyOf, valueOf, first.data(), count.data(), grouped, parallel);
  };
  std::vector<Index> first, count, grouped;
  const Index total = group(false, first, count, grouped);
  EXPECT_EQ(size_t(total), grouped.size());
  EXPECT_GT(*std::max_element(count.begin(), count.end()), 32);
  EXPECT_GT(std::count(count.begin(), count.end(), 0), 0) << "no empty group";
  // The serial reference against its definition: each group's values in item order.
  for (Index g : { Index(0), Index(5), Index(100), groups - 1 })
  {
    std::vector<Index> expected;
    for (Index i = 0; i < items; ++i)
    {
      if (keys[size_t(i)] == g)
      {
        expected.push_back(i / 3);
      }
    }
    EXPECT_EQ(std::vector<Index>(grouped.begin() + first[g], grouped.begin() + first[g] + count[g]), expected) << g;
  }
  const TriangleMesh sphere = Sphere(400, 300); // several chunks of items; poles of valence 400
  const EditableMesh serialMesh(sphere); // serial by default
  slodtest::ForOneTwoAndEightThreads([&](int threads) {
    std::vector<Index> f, c, g;
    EXPECT_EQ(group(true, f, c, g), total) << threads;
    EXPECT_EQ(f, first) << threads;
    EXPECT_EQ(c, count) << threads;
    EXPECT_EQ(g, grouped) << threads;
    EditableMesh mesh;
    mesh.SetParallelRebuild(true);
    mesh.Reset(sphere);
    for (Index v = 0; v < sphere.NumberOfPoints(); ++v)
    {
      std::vector<Index> fan, serialFan;
      mesh.ForEachTriangle(v, [&](Index t) { fan.push_back(t); });
      serialMesh.ForEachTriangle(v, [&](Index t) { serialFan.push_back(t); });
      ASSERT_EQ(fan, serialFan) << threads << " threads, vertex " << v;
    }
  });
}

// Session 29: the large working arrays are advised for transparent huge pages before their first
// touch (fewer page faults and TLB misses in the set-up and the collapse loop). The advice is read
// back from the kernel: the mapping that holds an array carries the "hg" flag (MADV_HUGEPAGE) in
// /proc/self/smaps, and a plain vector's mapping, the control, does not.
namespace
{
// The VmFlags of the mapping that holds p ("" when not found or not Linux).
std::string MappingFlags(const void* p)
{
  std::ifstream smaps("/proc/self/smaps");
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line))
  {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    if (line.rfind("VmFlags:", 0) == 0)
    {
      if (inside)
      {
        return line.substr(8) + " ";
      }
    }
    else if (head >> std::hex >> begin >> dash >> end && dash == '-')
    {
      inside = begin <= at && at < end;
    }
  }
  return "";
}

bool HugePagesAvailable()
{
  std::ifstream enabled("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(enabled, modes);
  return modes.find("[always]") != std::string::npos || modes.find("[madvise]") != std::string::npos;
}
}

TEST(HugePages, LargeArraysAreAdvisedAndKeepTheirContents)
{
  // The helpers keep the vector semantics: contents kept by the reserve, values by the assign.
  std::vector<Index> kept(1000);
  for (size_t i = 0; i < kept.size(); ++i)
  {
    kept[i] = Index(7 * i);
  }
  const std::vector<Index> before = kept;
  const size_t n = 3 * HugePageBytes / sizeof(Index) + 5;
  ReserveOnHugePages(kept, n);
  EXPECT_GE(kept.capacity(), n);
  EXPECT_EQ(kept, before);
  std::vector<double> filled = MakeOnHugePages<double>(n, 2.5);
  ASSERT_EQ(filled.size(), n);
  EXPECT_EQ(std::count(filled.begin(), filled.end(), 2.5), std::ptrdiff_t(n));
  std::vector<double> copy;
  CopyOnHugePages(copy, filled);
  EXPECT_EQ(copy, filled);
  if (!HugePagesAvailable() || MappingFlags(filled.data()).empty())
  {
    GTEST_SKIP() << "transparent huge pages are off (or /proc/self/smaps unreadable): the advice is not observable";
  }
  EXPECT_NE(MappingFlags(filled.data() + n / 2).find(" hg "), std::string::npos) << MappingFlags(filled.data());
  EXPECT_NE(MappingFlags(kept.data() + n / 2).find(" hg "), std::string::npos) << MappingFlags(kept.data());
  std::vector<double> plain(n, 1.0);
  EXPECT_EQ(MappingFlags(plain.data() + n / 2).find(" hg "), std::string::npos) << "the control is advised too";
  // The editable mesh's arrays, which the collapse loop reads at random places (500 x 400 sphere:
  // 400,000 triangles, 4.8 MB of corners).
  const EditableMesh mesh(Sphere(500, 400));
  ASSERT_GT(size_t(mesh.NumberOfTriangles()) * 3 * sizeof(Index), 2 * HugePageBytes);
  EXPECT_NE(MappingFlags(mesh.Triangle(mesh.NumberOfTriangles() / 2)).find(" hg "), std::string::npos);
}
