// SPDX-License-Identifier: BSD-3-Clause
// Tests of the SPBM method: the shared patchification (disks, normal cones, chains, patch graph),
// the chain hierarchy (epsilon bound), the level generator and the vtkPatchBoundaryMerge filter
// (manifold, watertight, genus, original vertices only, PatchId, profile curves, reuse of the
// patchification across levels, quality against vtkQuadricDecimation / vtkDecimatePro).
#include "TestSupport.h"

#include "slodSpbmFinalCollapses.h"
#include "slodSpbmState.h"
#include "slodTriangleBVH.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPatchBoundaryMerge.h"
#include "slodPatchification.h"
#include "slodPolygonTriangulation.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkQuadricDecimation.h"
#include "vtkScanSurfaceSource.h"
#include "vtkSMPTools.h"
#include "vtkTriangleFilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <tuple>

using namespace slod;

namespace
{

struct PatchedMesh
{
  TriangleMesh Mesh;
  MeshTopology Topology;
  Patchification Patches;
};

std::unique_ptr<PatchedMesh> Patch(const TriangleMesh& mesh, const PatchificationParameters& parameters = {})
{
  auto result = std::make_unique<PatchedMesh>();
  result->Mesh = mesh;
  result->Topology.Build(result->Mesh);
  result->Patches.Build(result->Mesh, result->Topology, parameters);
  return result;
}

// The triangles of each patch as their own (compact) mesh.
std::vector<TriangleMesh> PatchMeshes(const PatchedMesh& pm)
{
  std::vector<TriangleMesh> patches(size_t(pm.Patches.NumberOfPatches()));
  std::vector<Index> local(size_t(pm.Mesh.NumberOfPoints()), InvalidIndex);
  std::vector<Index> stampOf(size_t(pm.Mesh.NumberOfPoints()), InvalidIndex);
  std::vector<std::vector<Index>> members(patches.size());
  for (Index t = 0; t < pm.Mesh.NumberOfTriangles(); ++t)
  {
    members[pm.Patches.TrianglePatches()[t]].push_back(t);
  }
  for (size_t p = 0; p < patches.size(); ++p)
  {
    for (const Index t : members[p])
    {
      Index ids[3];
      for (int k = 0; k < 3; ++k)
      {
        const Index v = pm.Mesh.Triangle(t)[k];
        if (stampOf[v] != Index(p))
        {
          stampOf[v] = Index(p);
          local[v] = patches[p].AddPoint(pm.Mesh.Point(v));
        }
        ids[k] = local[v];
      }
      patches[p].AddTriangle(ids[0], ids[1], ids[2]);
    }
  }
  return patches;
}

void ExpectPatchesAreDisks(const PatchedMesh& pm)
{
  const std::vector<TriangleMesh> patches = PatchMeshes(pm);
  std::vector<Index> loop;
  for (size_t p = 0; p < patches.size(); ++p)
  {
    const MeshStatistics st = ComputeMeshStatistics(patches[p]);
    ASSERT_EQ(st.EulerCharacteristic, 1) << "patch " << p;
    ASSERT_EQ(st.BoundaryLoops, 1) << "patch " << p;
    ASSERT_EQ(st.Components, 1) << "patch " << p;
    ASSERT_EQ(st.NonManifoldVertices, 0) << "patch " << p;
    ASSERT_EQ(st.NonManifoldEdges, 0) << "patch " << p;
    ASSERT_TRUE(pm.Patches.PatchBoundaryLoop(Index(p), loop)) << "patch " << p;
    ASSERT_EQ(Index(loop.size()), st.BoundaryEdges) << "patch " << p; // the chains are its whole boundary
  }
}

// Samples of the input's every vertex coordinate, for the "original vertices only" check.
std::set<std::tuple<double, double, double>> CoordinateSet(vtkPolyData* pd)
{
  std::set<std::tuple<double, double, double>> set;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    set.emplace(float(x[0]), float(x[1]), float(x[2]));
  }
  return set;
}

MeshStatistics StatisticsOf(vtkPolyData* pd)
{
  return ComputeMeshStatistics(slodtest::ToTriangleMesh(pd));
}

// Raw statistics (no preparation: merging or reorienting would hide defects).
MeshStatistics RawStatistics(vtkPolyData* pd)
{
  TriangleMesh mesh;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    mesh.AddPoint({ x[0], x[1], x[2] });
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    EXPECT_EQ(ids->GetNumberOfIds(), 3);
    if (ids->GetNumberOfIds() == 3)
    {
      mesh.AddTriangle(Index(ids->GetId(0)), Index(ids->GetId(1)), Index(ids->GetId(2)));
    }
  }
  return ComputeMeshStatistics(mesh);
}

// A level generated over `mesh`: closed, manifold, consistently oriented, genus 0.
void ExpectClosedGenusZeroLevel(const TriangleMesh& mesh, const SpbmLevel& level)
{
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = level.Triangles;
  out.RemoveUnusedPoints();
  const MeshStatistics st = ComputeMeshStatistics(out);
  EXPECT_EQ(st.BoundaryEdges, 0);
  EXPECT_EQ(st.NonManifoldEdges, 0);
  EXPECT_EQ(st.NonManifoldVertices, 0);
  EXPECT_EQ(st.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(st.Genus, 0);
}

void ExpectValidClosedOutput(vtkPolyData* input, vtkPolyData* output, long long genus)
{
  const MeshStatistics st = RawStatistics(output);
  EXPECT_GT(st.Triangles, 0);
  EXPECT_EQ(st.BoundaryEdges, 0);
  EXPECT_EQ(st.NonManifoldEdges, 0);
  EXPECT_EQ(st.NonManifoldVertices, 0);
  EXPECT_EQ(st.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(st.DegenerateTriangles, 0);
  EXPECT_EQ(st.Components, 1);
  EXPECT_EQ(st.Genus, genus);
  EXPECT_EQ(st.Vertices, output->GetNumberOfPoints()); // no unused points
  // PatchId per cell.
  vtkDataArray* patchId = output->GetCellData()->GetArray("PatchId");
  ASSERT_NE(patchId, nullptr);
  EXPECT_EQ(patchId->GetNumberOfTuples(), output->GetNumberOfCells());
  // Original vertices only.
  const auto original = CoordinateSet(input);
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    double x[3];
    output->GetPoint(i, x);
    ASSERT_TRUE(original.count({ float(x[0]), float(x[1]), float(x[2]) })) << "point " << i << " is not an input vertex";
  }
}

vtkSmartPointer<vtkPolyData> RunFilter(vtkPolyData* input, vtkIdType target, vtkPatchBoundaryMerge* filter = nullptr)
{
  vtkSmartPointer<vtkPatchBoundaryMerge> own;
  if (!filter)
  {
    own = vtkSmartPointer<vtkPatchBoundaryMerge>::New();
    filter = own;
  }
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(target);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(filter->GetOutput());
  return out;
}

// The same cells (point ids, in order) in `a` and `b`.
void ExpectSameCells(vtkPolyData* a, vtkPolyData* b)
{
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  vtkNew<vtkIdList> ia, ib;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    a->GetCellPoints(c, ia);
    b->GetCellPoints(c, ib);
    ASSERT_EQ(ia->GetNumberOfIds(), ib->GetNumberOfIds()) << "cell " << c;
    for (vtkIdType k = 0; k < ia->GetNumberOfIds(); ++k)
    {
      ASSERT_EQ(ia->GetId(k), ib->GetId(k)) << "cell " << c;
    }
  }
}
} // namespace

// ---------------------------------------------------------------------------------------------
// Patchification
TEST(Patchification, SphereTorusAndFandiskPatchesAreDisks)
{
  for (const TriangleMesh& mesh : { slodtest::Sphere(48, 48), slodtest::Torus(64, 24),
         slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk")),
         slodtest::ToTriangleMesh(slodtest::LoadTestMesh("bunny00")) })
  {
    auto pm = Patch(mesh);
    EXPECT_GT(pm->Patches.NumberOfPatches(), 1);
    EXPECT_LT(pm->Patches.NumberOfPatches(), mesh.NumberOfTriangles() / 4);
    Index covered = 0;
    for (Index p = 0; p < pm->Patches.NumberOfPatches(); ++p)
    {
      covered += pm->Patches.PatchTriangleCount(p);
    }
    EXPECT_EQ(covered, mesh.NumberOfTriangles());
    for (const Index p : pm->Patches.TrianglePatches())
    {
      ASSERT_NE(p, InvalidIndex);
    }
    ExpectPatchesAreDisks(*pm);
  }
}

TEST(Patchification, NormalConesWithinTolerance)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  PatchificationParameters parameters;
  auto pm = Patch(mesh, parameters);
  // Triangles joining through one edge are within 25 degrees of the running patch normal and
  // those closing a notch within 90: the final cone is bounded by the two-edge angle, and the
  // area-weighted mean deviation stays below the one-edge angle.
  std::vector<double> weighted(size_t(pm->Patches.NumberOfPatches()), 0.0);
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index p = pm->Patches.TrianglePatches()[t];
    const Vec3 n = Normalized(mesh.TriangleAreaVector(t));
    const double angle = std::acos(std::max(-1.0, std::min(1.0, Dot(n, pm->Patches.PatchNormal(p))))) * 180 / Pi;
    ASSERT_LE(angle, parameters.TwoEdgePatchAngle) << "triangle " << t;
    weighted[p] += angle * mesh.TriangleArea(t);
  }
  for (Index p = 0; p < pm->Patches.NumberOfPatches(); ++p)
  {
    EXPECT_LE(weighted[p] / pm->Patches.PatchArea(p), parameters.OneEdgePatchAngle) << "patch " << p;
  }
  // The sharp feature lines of the CAD model are patch boundaries: no patch holds two triangles
  // meeting at more than 60 degrees across an edge.
  MeshTopology& topo = pm->Topology;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index n = topo.EdgeNeighbor(t, k);
      if (n != InvalidIndex && pm->Patches.TrianglePatches()[n] == pm->Patches.TrianglePatches()[t])
      {
        const double d = Dot(Normalized(mesh.TriangleAreaVector(t)), Normalized(mesh.TriangleAreaVector(n)));
        EXPECT_GT(d, std::cos(60 * Pi / 180)) << t << " " << n;
      }
    }
  }
}

TEST(Patchification, ZeroToleranceGivesCoplanarPatches)
{
  // With zero angular tolerance only exactly coplanar neighbours share a patch.
  PatchificationParameters parameters;
  parameters.OneEdgePatchAngle = parameters.OneEdgeNeighborAngle = 0;
  parameters.TwoEdgePatchAngle = parameters.TwoEdgeNeighborAngle = 0;
  const TriangleMesh mesh = slodtest::Sphere(12, 12);
  auto pm = Patch(mesh, parameters);
  EXPECT_GE(pm->Patches.NumberOfPatches(), mesh.NumberOfTriangles() / 2);
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Vec3 n = Normalized(mesh.TriangleAreaVector(t));
    EXPECT_GT(Dot(n, pm->Patches.PatchNormal(pm->Patches.TrianglePatches()[t])), 1 - 1e-9);
  }
  ExpectPatchesAreDisks(*pm);
}

TEST(Patchification, FlatGridIsOnePatchWithBorderChains)
{
  const TriangleMesh mesh = slodtest::Grid(10, 10);
  auto pm = Patch(mesh);
  ASSERT_EQ(pm->Patches.NumberOfPatches(), 1);
  EXPECT_EQ(pm->Patches.NumberOfChains(), 3); // a closed loop is cut in three
  for (Index c = 0; c < pm->Patches.NumberOfChains(); ++c)
  {
    EXPECT_EQ(pm->Patches.ChainRightPatch(c), InvalidIndex);
  }
  std::vector<Index> loop;
  ASSERT_TRUE(pm->Patches.PatchBoundaryLoop(0, loop));
  EXPECT_EQ(loop.size(), 40u);
}

// Issue 10 (session 24): a noisy flat surface. Every vertex of a 40 x 40 grid is moved off the
// plane by up to a fifth of the grid spacing (a fixed pseudo-random pattern), so neighbouring
// triangles differ by tens of degrees, as on a scan isosurface. With the cones alone the patches
// stay small; with NoiseTolerance above the noise amplitude (and the plane distance above it too)
// triangles within the noise of the patch's plane join, the grid becomes a few large disks, and
// no vertex of a patch is farther from its plane than the plane distance allows.
TriangleMesh NoisyGrid(int n, double amplitude)
{
  TriangleMesh mesh = slodtest::Grid(n, n);
  unsigned state = 12345u;
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    state = state * 1664525u + 1013904223u; // LCG: the same noise on every platform
    mesh.Points[3 * size_t(v) + 2] = amplitude * (2.0 * double(state >> 8) / double(1u << 24) - 1.0);
  }
  return mesh;
}

TEST(Patchification, NoiseToleranceGrowsPatchesOverNoise)
{
  constexpr int N = 40;
  constexpr double Amplitude = 0.2 / N;
  const TriangleMesh mesh = NoisyGrid(N, Amplitude);
  PatchificationParameters cones;
  cones.MaximumPlaneDistance = 3 * Amplitude;
  auto without = Patch(mesh, cones);
  PatchificationParameters tolerant = cones;
  tolerant.NoiseTolerance = 2 * Amplitude;
  auto with = Patch(mesh, tolerant);
  ExpectPatchesAreDisks(*with);
  // Premise: the noise breaks the cones (the old behaviour: many small patches).
  EXPECT_GT(without->Patches.NumberOfPatches(), mesh.NumberOfTriangles() / 20);
  EXPECT_LE(with->Patches.NumberOfPatches() * 10, without->Patches.NumberOfPatches());
  // A patch within the plane distance of its running plane, measured against the final plane (the
  // running one moved while it grew): twice the distance plus the noise bounds it.
  std::vector<Vec3> centroid(size_t(with->Patches.NumberOfPatches()), Vec3{ 0, 0, 0 });
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index p = with->Patches.TrianglePatches()[t];
    const Index* tri = mesh.Triangle(t);
    const Vec3 c = (1.0 / 3.0) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2]));
    centroid[p] = centroid[p] + (mesh.TriangleArea(t) / with->Patches.PatchArea(p)) * c;
  }
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index p = with->Patches.TrianglePatches()[t];
    for (int k = 0; k < 3; ++k)
    {
      const double off = std::fabs(Dot(mesh.Point(mesh.Triangle(t)[k]) - centroid[p], with->Patches.PatchNormal(p)));
      ASSERT_LE(off, 2 * cones.MaximumPlaneDistance + Amplitude) << "triangle " << t;
    }
  }
}

// Issue 15 (session 35): NoiseToleranceJoins counts the candidates the noise tolerance admitted
// against the angle tests, which is what tells a scan from a smooth surface: on a grid noisy by
// up to half its spacing at least a quarter of the triangles (session 35's ScanNoiseJoinShare; the
// filter no longer decides by it since session 36, the counter stays a measure of the growth),
// none without the tolerance; on a finely tessellated sphere with the same plane distance and
// tolerance (relative to its size) next to none, since its neighbouring triangles pass the angle
// tests anyway.
TEST(Patchification, NoiseToleranceJoinsTellNoiseFromCurvature)
{
  const double amplitude = 0.5 / 40;
  const TriangleMesh noisy = NoisyGrid(40, amplitude);
  const TriangleMesh sphere = slodtest::Sphere(64, 64);
  // Plane distance 3 and tolerance `tolerance` times `unit` (the noise amplitude, scaled to the sphere's size).
  auto joins = [](const TriangleMesh& mesh, double unit, double tolerance) {
    PatchificationParameters parameters;
    parameters.MaximumPlaneDistance = 3 * unit;
    parameters.NoiseTolerance = tolerance * unit;
    auto pm = Patch(mesh, parameters);
    ExpectPatchesAreDisks(*pm);
    return pm->Patches.NoiseToleranceJoins();
  };
  EXPECT_EQ(joins(noisy, amplitude, 0.0), 0);
  EXPECT_GE(4 * joins(noisy, amplitude, 2.0), noisy.NumberOfTriangles());
  const double sphereUnit = amplitude * sphere.BoundingBoxDiagonal() / noisy.BoundingBoxDiagonal();
  EXPECT_LE(50 * joins(sphere, sphereUnit, 2.0), sphere.NumberOfTriangles());
}

// The noise tolerance does not smooth over a CAD model's creases: on the Fandisk, with the filter's
// plane distance (0.004 of the diagonal) as both the distance and the tolerance, no patch holds two
// triangles meeting at more than 60 degrees across an edge, as with the cones alone.
TEST(Patchification, NoiseToleranceKeepsCreasesAsBoundaries)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  PatchificationParameters parameters;
  parameters.MaximumPlaneDistance = 0.004 * mesh.BoundingBoxDiagonal();
  parameters.NoiseTolerance = parameters.MaximumPlaneDistance;
  auto pm = Patch(mesh, parameters);
  ExpectPatchesAreDisks(*pm);
  Index crossing = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index n = pm->Topology.EdgeNeighbor(t, k);
      if (n != InvalidIndex && pm->Patches.TrianglePatches()[n] == pm->Patches.TrianglePatches()[t])
      {
        crossing +=
          Dot(Normalized(mesh.TriangleAreaVector(t)), Normalized(mesh.TriangleAreaVector(n))) <= std::cos(60 * Pi / 180);
      }
    }
  }
  EXPECT_EQ(crossing, 0);
}

// Issue 15 (session 25): RulingAngle. On the Fandisk, whose cylinders the paper's growth (a
// triangle's two free neighbours join both or neither) cut into grids of small patches, with a
// plane distance of 1e-3 of the diagonal: a neighbour along a ruling joins alone, and the
// patches (still disks, none across a crease of more than 60 degrees) are fewer than half as many.
TEST(Patchification, RulingAngleGrowsStripsAlongCylinders)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  PatchificationParameters parameters;
  parameters.MaximumPlaneDistance = 1e-3 * mesh.BoundingBoxDiagonal();
  auto paper = Patch(mesh, parameters);
  parameters.RulingAngle = 1.0;
  auto strips = Patch(mesh, parameters);
  ExpectPatchesAreDisks(*strips);
  EXPECT_LT(2 * strips->Patches.NumberOfPatches(), paper->Patches.NumberOfPatches());
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index n = strips->Topology.EdgeNeighbor(t, k);
      if (n != InvalidIndex && strips->Patches.TrianglePatches()[n] == strips->Patches.TrianglePatches()[t])
      {
        ASSERT_GT(Dot(Normalized(mesh.TriangleAreaVector(t)), Normalized(mesh.TriangleAreaVector(n))), 0.5)
          << "triangles " << t << " and " << n;
      }
    }
  }
}

// The thickest patch along its final normal, over twice the plane distance.
double ThickestPatch(const TriangleMesh& mesh, const PatchedMesh& pm, double planeDistance)
{
  const Index np = pm.Patches.NumberOfPatches();
  std::vector<double> lo(size_t(np), std::numeric_limits<double>::infinity()), hi(size_t(np), -lo[0]);
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index p = pm.Patches.TrianglePatches()[t];
    for (int k = 0; k < 3; ++k)
    {
      const double h = Dot(pm.Patches.PatchNormal(p), mesh.Point(mesh.Triangle(t)[k]));
      lo[p] = std::min(lo[p], h);
      hi[p] = std::max(hi[p], h);
    }
  }
  double largest = 0;
  for (Index p = 0; p < np; ++p)
  {
    largest = std::max(largest, (hi[p] - lo[p]) / (2 * planeDistance));
  }
  return largest;
}

// Issue 15 (session 25): BoundPatchThickness. The running plane follows a patch as it bends, so
// the new vertex's distance from it alone let patches of a smooth isosurface grow several times
// thicker than twice the plane distance (mc1m: 1% of them 1.5-4.8 times; this isosurface: up to
// 1.29 times). With the bound, every patch lies within twice the distance along the normal it had
// when its last join was checked; its final normal differs a little from that, so the test
// allows 20%.
TEST(Patchification, BoundPatchThicknessKeepsPatchesThin)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::SyntheticIsosurface(120));
  PatchificationParameters parameters;
  parameters.MaximumPlaneDistance = 2e-4 * mesh.BoundingBoxDiagonal();
  auto thickest = [&](const PatchedMesh& pm) { return ThickestPatch(mesh, pm, parameters.MaximumPlaneDistance); };
  auto unbounded = Patch(mesh, parameters);
  parameters.BoundPatchThickness = true;
  auto bounded = Patch(mesh, parameters);
  ExpectPatchesAreDisks(*bounded);
  std::cout << "[thickness] over twice the plane distance: " << thickest(*unbounded) << " -> " << thickest(*bounded)
            << "\n";
  EXPECT_GT(thickest(*unbounded), 1.2);
  EXPECT_LE(thickest(*bounded), 1.2);
}

// Issue 15 (session 27): SmallPatchTriangles. With the plane distance of a mild target (about the
// sag of one input triangle), the new vertex's distance from the running plane of a patch of one
// or two triangles is the patch's span, and its bound was half the span bound: most seeds stayed
// alone, and every merging run merged them again. With it, patches of up to four triangles take a
// vertex up to the span bound: fewer patches and far fewer single triangles, every patch a disk.
// (The thickness along the final normal is printed, not asserted: at plane distances this small a
// few-triangle patch's normal turns as it grows, and neither growth keeps it within the bound.)
TEST(Patchification, SmallPatchesJoinUpToTheSpanBound)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::SyntheticIsosurface(120));
  PatchificationParameters parameters;
  parameters.BoundPatchThickness = true;
  parameters.MaximumPlaneDistance = 1e-4 * mesh.BoundingBoxDiagonal();
  auto singles = [](const PatchedMesh& pm) {
    Index count = 0;
    for (Index p = 0; p < pm.Patches.NumberOfPatches(); ++p)
    {
      count += pm.Patches.PatchTriangleCount(p) == 1;
    }
    return count;
  };
  auto thickest = [&](const PatchedMesh& pm) { return ThickestPatch(mesh, pm, parameters.MaximumPlaneDistance); };
  auto before = Patch(mesh, parameters);
  parameters.SmallPatchTriangles = 4;
  auto after = Patch(mesh, parameters);
  ExpectPatchesAreDisks(*after);
  std::cout << "[small patches] patches " << before->Patches.NumberOfPatches() << " -> "
            << after->Patches.NumberOfPatches() << ", single triangles " << singles(*before) << " -> "
            << singles(*after) << ", thickness over the span bound " << thickest(*before) << " -> "
            << thickest(*after) << "\n";
  // The mild-target regime: before, a large share of the patches are single triangles.
  EXPECT_GT(4 * singles(*before), before->Patches.NumberOfPatches());
  EXPECT_LT(10 * singles(*after), 7 * singles(*before));
  EXPECT_LT(10 * after->Patches.NumberOfPatches(), 9 * before->Patches.NumberOfPatches());
}

TEST(Patchification, ChainsAndPatchGraphAreConsistent)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  const Patchification& P = pm->Patches;
  // Every patch-boundary edge of the mesh is in exactly one chain; chain edges are mesh edges.
  std::map<std::pair<Index, Index>, int> chainEdges;
  for (Index c = 0; c < P.NumberOfChains(); ++c)
  {
    ASSERT_GE(P.ChainSize(c), 2);
    EXPECT_NE(P.ChainLeftPatch(c), P.ChainRightPatch(c));
    const Index* v = P.ChainVerticesBegin(c);
    EXPECT_EQ(P.EndpointVertex(P.ChainStart(c)), v[0]);
    EXPECT_EQ(P.EndpointVertex(P.ChainEnd(c)), v[P.ChainSize(c) - 1]);
    for (Index i = 0; i + 1 < P.ChainSize(c); ++i)
    {
      ASSERT_NE(pm->Topology.FindEdge(v[i], v[i + 1]), InvalidIndex);
      ++chainEdges[{ std::min(v[i], v[i + 1]), std::max(v[i], v[i + 1]) }];
    }
    // The patch graph lists the chain at both its patches.
    for (const Index p : { P.ChainLeftPatch(c), P.ChainRightPatch(c) })
    {
      if (p != InvalidIndex)
      {
        EXPECT_NE(std::find(P.PatchChainsBegin(p), P.PatchChainsEnd(p), c), P.PatchChainsEnd(p));
      }
    }
  }
  Index boundaryEdges = 0;
  for (Index e = 0; e < pm->Topology.NumberOfEdges(); ++e)
  {
    const Index* t = pm->Topology.EdgeTrianglesBegin(e);
    if (P.TrianglePatches()[t[0]] != P.TrianglePatches()[t[1]])
    {
      ++boundaryEdges;
      EXPECT_EQ((chainEdges[{ pm->Topology.EdgeVertex(e, 0), pm->Topology.EdgeVertex(e, 1) }]), 1);
    }
  }
  EXPECT_EQ(Index(chainEdges.size()), boundaryEdges);
}

// ---------------------------------------------------------------------------------------------
// Chain hierarchy and levels
TEST(SpbmLevel, ChainsStayWithinEpsilonAtEveryLevel)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("bunny00"));
  auto pm = Patch(mesh);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches);
  const Patchification& P = pm->Patches;
  const double diagonal = mesh.BoundingBoxDiagonal();
  for (const double relative : { 0.0005, 0.002, 0.01, 0.05 })
  {
    const double eps = relative * diagonal;
    Index keptTotal = 0;
    for (Index c = 0; c < P.NumberOfChains(); ++c)
    {
      const Index* v = P.ChainVerticesBegin(c);
      Index previous = 0;
      for (Index i = 1; i < P.ChainSize(c); ++i)
      {
        if (!(generator.ChainVertexKey(c, i) > float(eps)))
        {
          continue;
        }
        ++keptTotal;
        const Vec3 a = mesh.Point(v[previous]), b = mesh.Point(v[i]);
        for (Index k = previous + 1; k < i; ++k)
        {
          const Vec3 p = mesh.Point(v[k]);
          const Vec3 ab = b - a;
          const double t = std::max(0.0, std::min(1.0, Dot(p - a, ab) / std::max(1e-300, Dot(ab, ab))));
          ASSERT_LE(Norm(p - (a + t * ab)), eps * (1 + 1e-6)) << "chain " << c << " vertex " << k;
        }
        previous = i;
      }
    }
    EXPECT_GT(keptTotal, P.NumberOfChains() - 1);
  }
}

// ChainInPlaneWeight: the chain tolerance in the surface-aware measure (offset components along
// the two patch normals, at least the weight times the offset), Euclidean on border chains; the
// same epsilon keeps fewer vertices than the Euclidean hierarchy, never more.
TEST(SpbmLevel, ChainsStayWithinEpsilonAlongPatchNormals)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  const Patchification& P = pm->Patches;
  const double weight = 0.5;
  SpbmLevelGenerator weighted, euclidean;
  weighted.Initialize(pm->Mesh, P, weight);
  euclidean.Initialize(pm->Mesh, P);
  const double diagonal = mesh.BoundingBoxDiagonal();
  Index keptWeighted = 0, keptEuclidean = 0; // over all epsilons (the split points differ)
  for (const double relative : { 0.001, 0.005, 0.02 })
  {
    const double eps = relative * diagonal;
    for (Index c = 0; c < P.NumberOfChains(); ++c)
    {
      const Index* v = P.ChainVerticesBegin(c);
      const bool border = P.ChainRightPatch(c) == InvalidIndex;
      const Vec3 n1 = P.PatchNormal(P.ChainLeftPatch(c));
      const Vec3 n2 = border ? n1 : P.PatchNormal(P.ChainRightPatch(c));
      Index previous = 0;
      for (Index i = 1; i < P.ChainSize(c); ++i)
      {
        keptEuclidean += i + 1 < P.ChainSize(c) && euclidean.ChainVertexKey(c, i) > float(eps);
        if (!(weighted.ChainVertexKey(c, i) > float(eps)))
        {
          continue;
        }
        keptWeighted += i + 1 < P.ChainSize(c);
        const Vec3 a = mesh.Point(v[previous]), b = mesh.Point(v[i]);
        for (Index k = previous + 1; k < i; ++k)
        {
          const Vec3 ab = b - a;
          const double t = std::max(0.0, std::min(1.0, Dot(mesh.Point(v[k]) - a, ab) / std::max(1e-300, Dot(ab, ab))));
          const Vec3 d = mesh.Point(v[k]) - (a + t * ab);
          const double measure = border
            ? Norm(d)
            : std::max({ std::fabs(Dot(d, n1)), std::fabs(Dot(d, n2)), weight * Norm(d) });
          ASSERT_LE(measure, eps * (1 + 1e-5)) << "chain " << c << " vertex " << k;
          ASSERT_LE(Norm(d), eps / weight * (1 + 1e-5));
        }
        previous = i;
      }
    }
  }
  EXPECT_LT(keptWeighted, keptEuclidean);
  EXPECT_GT(keptWeighted, 0);
}

TEST(SpbmLevel, PredictionMatchesGenerationAndLevelsAreValid)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches);
  Index previousCount = std::numeric_limits<Index>::max();
  for (const double relative : { 0.0, 0.001, 0.004, 0.02 })
  {
    SpbmLevelParameters parameters;
    parameters.Epsilon = relative * mesh.BoundingBoxDiagonal();
    const Index predicted = generator.PredictTriangleCount(parameters);
    SpbmLevel level;
    ASSERT_TRUE(generator.Generate(parameters, level));
    EXPECT_EQ(level.PredictedTriangles, predicted);
    const Index produced = Index(level.TrianglePatch.size());
    if (level.RefinedPatches == 0 && level.OriginalPatches == 0)
    {
      EXPECT_EQ(produced, predicted);
    }
    EXPECT_LE(produced, previousCount);
    previousCount = produced;
    ExpectClosedGenusZeroLevel(mesh, level);
  }
}

// The merging runs a level reuses (the search's last prediction as the first generation pass;
// the merging run at the same parameters as the start of a removal level) give the same counts
// and the same levels as runs on a fresh generator. Fandisk at 150 and bunny00 at 525 need the
// cost-ordered removal.
TEST(SpbmLevel, ReusedMergingRunsGiveTheSameLevels)
{
  for (const auto& [name, target] : { std::make_pair("fandisk", Index(150)), std::make_pair("bunny00", Index(525)) })
  {
    const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh(name));
    auto pm = Patch(mesh);
    SpbmLevelParameters base;
    base.SizeWeightedMerge = true;
    SpbmLevelGenerator searched;
    searched.Initialize(pm->Mesh, pm->Patches);
    Index predicted = 0;
    const SpbmLevelParameters found = searched.FindParameters(target, base, &predicted);
    ASSERT_GT(found.RemovalTarget, 0) << name;
    SpbmLevel reused;
    ASSERT_TRUE(searched.Generate(found, reused));

    SpbmLevelGenerator fresh;
    fresh.Initialize(pm->Mesh, pm->Patches);
    SpbmLevel level;
    ASSERT_TRUE(fresh.Generate(found, level));
    EXPECT_EQ(reused.Triangles, level.Triangles) << name;
    EXPECT_EQ(reused.PredictedTriangles, level.PredictedTriangles) << name;
    EXPECT_EQ(predicted, level.PredictedTriangles) << name;
    EXPECT_LE(Index(level.TrianglePatch.size()), target) << name;
    ExpectClosedGenusZeroLevel(mesh, level);

    // Merging without the removal, then the removal alone on that state.
    SpbmLevelGenerator continued;
    continued.Initialize(pm->Mesh, pm->Patches);
    SpbmLevelParameters merged = found;
    merged.RemovalTarget = 0;
    const Index mergedCount = continued.PredictTriangleCount(merged);
    EXPECT_GT(mergedCount, target) << name;
    EXPECT_EQ(continued.PredictTriangleCount(found), level.PredictedTriangles) << name;
    SpbmLevel again;
    ASSERT_TRUE(continued.Generate(found, again));
    EXPECT_EQ(again.Triangles, level.Triangles) << name;
  }
}

// Size-weighted merging gives valid levels whose count the prediction knows; comparing
// candidates never increases the sampled deviation of the single search, at the same budget.
TEST(SpbmLevel, SizeWeightedMergeAndCandidateComparison)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches);
  for (const Index target : { 460, 266, 150 })
  {
    SpbmLevelParameters single;
    single.CompareCandidates = false;
    SpbmLevel one, best;
    ASSERT_TRUE(generator.GenerateForTarget(target, single, one));
    SpbmLevelParameters compare;
    SpbmLevelParameters used;
    ASSERT_TRUE(generator.GenerateForTarget(target, compare, best, &used));
    EXPECT_LE(Index(best.TrianglePatch.size()), target);
    EXPECT_GE(Index(best.TrianglePatch.size()), target * 9 / 10);
    EXPECT_LE(generator.EstimateDeviation(best), generator.EstimateDeviation(one));
    // The chosen parameters regenerate the chosen level.
    SpbmLevel again;
    ASSERT_TRUE(generator.Generate(used, again));
    EXPECT_EQ(again.Triangles, best.Triangles);

    SpbmLevelParameters weighted = used;
    weighted.SizeWeightedMerge = true;
    const Index predicted = generator.PredictTriangleCount(weighted);
    SpbmLevel level;
    ASSERT_TRUE(generator.Generate(weighted, level));
    EXPECT_EQ(level.PredictedTriangles, predicted);
    ExpectClosedGenusZeroLevel(mesh, level);
  }
}

// Beyond what merging within alpha1 reaches (the Fandisk at 150 triangles), the cost-ordered
// endpoint removal reaches the target exactly with every merge measure, the levels stay closed
// genus-0 manifolds with the predicted counts, and the level is closer to the input than the
// fixed relaxation ladder's (wider collapses, no epsilon bounds) at the same target.
TEST(SpbmLevel, CostOrderedRemovalReachesTargetCloserThanRelaxationLadder)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches, 0.42);
  const Index target = 150;
  SpbmLevelParameters base;
  SpbmLevelParameters used;
  SpbmLevel removal;
  ASSERT_TRUE(generator.GenerateForTarget(target, base, removal, &used));
  EXPECT_EQ(used.RemovalTarget, target);
  EXPECT_LE(Index(removal.TrianglePatch.size()), target);
  EXPECT_GE(Index(removal.TrianglePatch.size()), target - 2);
  ExpectClosedGenusZeroLevel(mesh, removal);
  for (const int measure : { 0, 1, 2 })
  {
    SpbmLevelParameters parameters = used;
    parameters.SizeWeightedMerge = measure == 1;
    parameters.FlatnessMerge = measure == 2;
    const Index predicted = generator.PredictTriangleCount(parameters);
    EXPECT_LE(predicted, target) << measure;
    EXPECT_GE(predicted, target - 2) << measure;
    SpbmLevel level;
    ASSERT_TRUE(generator.Generate(parameters, level));
    EXPECT_EQ(level.PredictedTriangles, predicted);
    ExpectClosedGenusZeroLevel(mesh, level);
  }
  SpbmLevelParameters ladder = base;
  ladder.CostOrderedRemoval = false;
  SpbmLevel relaxed;
  SpbmLevelParameters relaxedUsed;
  ASSERT_TRUE(generator.GenerateForTarget(target, ladder, relaxed, &relaxedUsed));
  EXPECT_EQ(relaxedUsed.RemovalTarget, 0);
  EXPECT_LE(Index(relaxed.TrianglePatch.size()), target);
  ExpectClosedGenusZeroLevel(mesh, relaxed);
  EXPECT_LT(generator.EstimateDeviation(removal), 0.75 * generator.EstimateDeviation(relaxed));
}

// The minimum-deviation triangulation changes only the diagonals inside non-planar patches: same
// profile curves and counts as the ear clipping, still a closed genus-0 level, and its triangles
// lie no farther from the input (sampled estimate) on the Fandisk levels.
TEST(SpbmLevel, MinimumDeviationTriangulationKeepsCurvesAndCounts)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  auto pm = Patch(mesh);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches, 0.42);
  for (const Index target : { 460, 266, 150 })
  {
    SpbmLevelParameters parameters;
    SpbmLevelParameters used;
    SpbmLevel dp, ears;
    ASSERT_TRUE(generator.GenerateForTarget(target, parameters, dp, &used));
    used.MinimumDeviationTriangulation = false;
    ASSERT_TRUE(generator.Generate(used, ears));
    EXPECT_EQ(dp.TrianglePatch.size(), ears.TrianglePatch.size());
    EXPECT_EQ(dp.CurveVertices, ears.CurveVertices);
    EXPECT_NE(dp.Triangles, ears.Triangles); // the curved faces are cut differently
    ExpectClosedGenusZeroLevel(mesh, dp);
    EXPECT_LE(generator.EstimateDeviation(dp), generator.EstimateDeviation(ears) * (1 + 1e-9)) << target;
  }
}

// ---------------------------------------------------------------------------------------------
// The filter
TEST(PatchBoundaryMerge, FandiskTable1LevelsAreClosedManifoldGenusZero)
{
  auto input = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->GeneratePatchColoredInputOn();
  for (const vtkIdType target : { 460, 266, 150 })
  {
    auto out = RunFilter(input, target, filter);
    ExpectValidClosedOutput(input, out, 0);
    // The search meets the dissertation's counts within the filter's 2% band (either side: a
    // kept vertex can jump over the band below the target, ReachBandAcrossKeyJumps); the smallest
    // level needs the relaxed joins and collapses (single-segment chains and alpha1 up to 90
    // degrees alone leave 188 triangles).
    EXPECT_LE(out->GetNumberOfCells(), target + std::max<vtkIdType>(2, target / 50));
    EXPECT_GE(out->GetNumberOfCells(), target - std::max<vtkIdType>(2, target / 50));
    // Profile curves: polylines over output points.
    vtkPolyData* curves = filter->GetOutput(1);
    EXPECT_GT(curves->GetNumberOfLines(), 0);
    EXPECT_EQ(curves->GetNumberOfPolys(), 0);
    EXPECT_EQ(curves->GetNumberOfPoints(), out->GetNumberOfPoints());
    // Input coloured by patch.
    vtkPolyData* colored = filter->GetOutput(2);
    EXPECT_EQ(colored->GetNumberOfCells(), input->GetNumberOfCells());
    ASSERT_NE(colored->GetCellData()->GetArray("PatchId"), nullptr);
  }
}

TEST(PatchBoundaryMerge, Bunny00LevelsKeepGenusAndManifoldness)
{
  auto input = slodtest::LoadTestMesh("bunny00");
  const MeshStatistics in = StatisticsOf(input);
  vtkNew<vtkPatchBoundaryMerge> filter;
  for (const vtkIdType target : { 1500, 1000, 525 })
  {
    auto out = RunFilter(input, target, filter);
    ExpectValidClosedOutput(input, out, in.Genus);
    EXPECT_LE(out->GetNumberOfCells(), target);
    EXPECT_GE(out->GetNumberOfCells(), target * 8 / 10);
  }
}

TEST(PatchBoundaryMerge, TorusKeepsGenusOne)
{
  auto input = slodtest::ToPolyData(slodtest::Torus(96, 32));
  for (const vtkIdType target : { 2000, 400, 120 })
  {
    auto out = RunFilter(input, target);
    ExpectValidClosedOutput(input, out, 1);
  }
}

namespace
{
// Asks the filter to abort once its progress passes a threshold.
class AbortAfterProgress : public vtkCommand
{
public:
  static AbortAfterProgress* New() { return new AbortAfterProgress; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    ++this->Calls;
    if (*static_cast<double*>(data) > this->Threshold)
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
  }
  double Threshold = 1.0;
  int Calls = 0;
};
} // namespace

// The filter contract: progress through slod::FilterProgress, and an abort (during the patch
// growth or during the level) gives an empty output with one warning (slod::ReportAbort).
TEST(PatchBoundaryMerge, ReportsProgressAndAborts)
{
  auto input = slodtest::ToPolyData(slodtest::Torus(128, 64));
  for (const double threshold : { 0.1, 0.69 })
  {
    vtkNew<vtkPatchBoundaryMerge> filter;
    vtkNew<AbortAfterProgress> abort;
    abort->Threshold = threshold;
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::ProgressEvent, abort);
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->SetInputData(input);
    filter->SetTargetNumberOfTriangles(400);
    filter->Update();
    EXPECT_GT(abort->Calls, 2) << "threshold " << threshold;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << "threshold " << threshold;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0) << "threshold " << threshold;
    EXPECT_EQ(messages->Warnings.size(), 1u) << "threshold " << threshold;
  }
}

TEST(PatchBoundaryMerge, PatchificationIsReusedAcrossLevels)
{
  auto input = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkPatchBoundaryMerge> filter;
  auto first = RunFilter(input, 1500, filter);
  EXPECT_FALSE(filter->GetPatchificationReused());
  const vtkIdType patches = filter->GetNumberOfPatches();
  auto second = RunFilter(input, 525, filter);
  EXPECT_TRUE(filter->GetPatchificationReused());
  EXPECT_EQ(filter->GetNumberOfPatches(), patches);
  EXPECT_LT(second->GetNumberOfCells(), first->GetNumberOfCells());
  // The bound (epsilon) given directly: also reused; a patch parameter change recomputes.
  filter->SetTargetNumberOfTriangles(0);
  filter->SetMaximumError(0.01);
  filter->MaximumErrorIsRelativeOn();
  filter->Update();
  EXPECT_TRUE(filter->GetPatchificationReused());
  filter->SetPatchAngle(15);
  filter->Update();
  EXPECT_FALSE(filter->GetPatchificationReused());
  EXPECT_GT(filter->GetNumberOfPatches(), patches);
  // Modifying the input recomputes too.
  input->Modified();
  filter->Update();
  EXPECT_FALSE(filter->GetPatchificationReused());
}

TEST(PatchBoundaryMerge, DeterministicAndTargetReduction)
{
  auto input = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkPatchBoundaryMerge> a, b;
  a->SetTargetReduction(0.97);
  b->SetTargetReduction(0.97);
  auto outA = RunFilter(input, 0, a);
  auto outB = RunFilter(input, 0, b);
  ASSERT_EQ(outA->GetNumberOfCells(), outB->GetNumberOfCells());
  EXPECT_LE(outA->GetNumberOfCells(), vtkIdType(std::llround(0.03 * input->GetNumberOfCells())));
  for (vtkIdType c = 0; c < outA->GetNumberOfCells(); ++c)
  {
    vtkNew<vtkIdList> ia, ib;
    outA->GetCellPoints(c, ia);
    outB->GetCellPoints(c, ib);
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(ia->GetId(k), ib->GetId(k));
    }
  }
}

// The candidates of a level run on two working states, and the tries of the cost-ordered removal
// go to whichever state is free; the level must not depend on that schedule. On the anchor at 50%
// the minimum-deviation triangulation's cached diagonal costs (float) once differed from freshly
// measured ones (double), so repeated runs gave two different levels (2 of 5 runs).
TEST(PatchBoundaryMerge, SameLevelWhicheverThreadRunsACandidate)
{
  auto input = slodtest::LoadTestMesh("anchor");
  vtkNew<vtkPatchBoundaryMerge> first;
  first->SetTargetReduction(0.5);
  auto reference = RunFilter(input, 0, first);
  ASSERT_GT(reference->GetNumberOfCells(), 0);
  for (int run = 0; run < 8; ++run)
  {
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetTargetReduction(0.5);
    auto output = RunFilter(input, 0, filter);
    ASSERT_EQ(output->GetNumberOfCells(), reference->GetNumberOfCells()) << "run " << run;
    for (vtkIdType c = 0; c < output->GetNumberOfCells(); ++c)
    {
      vtkNew<vtkIdList> ids, referenceIds;
      output->GetCellPoints(c, ids);
      reference->GetCellPoints(c, referenceIds);
      for (int k = 0; k < 3; ++k)
      {
        ASSERT_EQ(ids->GetId(k), referenceIds->GetId(k)) << "run " << run << ", cell " << c;
      }
    }
  }
}

// A level's stages run as vtkSMPTools tasks (the input's BVH beside the patch growth, the other
// merge measure beside the first level, the removal tries side by side): they must neither wait
// for each other nor share working state, so every backend gives the same level, also the
// sequential one (one task after the other). The anchor at 50% runs the removal tries, the Fandisk
// with CompareCandidates the other measure's search, and the noisy scan needs fallback passes (so
// its tries are skipped).
TEST(PatchBoundaryMerge, SameLevelWithEverySMPBackend)
{
  struct Case
  {
    vtkSmartPointer<vtkPolyData> Input;
    double Reduction;
    bool Compare, Fallback;
  };
  const Case cases[] = { { slodtest::LoadTestMesh("anchor"), 0.5, false, false },
    { slodtest::LoadTestMesh("fandisk"), 0.97, true, false },
    { slodtest::NoisyScanIsosurface(40, 1), 0.9, false, true } };
  const std::string saved = vtkSMPTools::GetBackend();
  for (const Case& test : cases)
  {
    vtkSmartPointer<vtkPolyData> reference;
    for (const char* backend : { "Sequential", "STDThread", "TBB" })
    {
      SCOPED_TRACE(backend);
      ASSERT_TRUE(vtkSMPTools::SetBackend(backend));
      vtkNew<vtkPatchBoundaryMerge> filter;
      filter->SetInputData(test.Input);
      filter->SetTargetReduction(test.Reduction);
      filter->SetCompareCandidates(test.Compare);
      filter->Update();
      auto output = vtkSmartPointer<vtkPolyData>::New();
      output->DeepCopy(filter->GetOutput());
      ASSERT_GT(output->GetNumberOfCells(), 0);
      if (test.Fallback)
      {
        EXPECT_GT(filter->GetUnmergedPatches(), 0) << "the noisy scan must need fallback passes";
      }
      if (!reference)
      {
        reference = output;
        continue;
      }
      ASSERT_EQ(output->GetNumberOfCells(), reference->GetNumberOfCells());
      for (vtkIdType c = 0; c < output->GetNumberOfCells(); ++c)
      {
        vtkNew<vtkIdList> ids, referenceIds;
        output->GetCellPoints(c, ids);
        reference->GetCellPoints(c, referenceIds);
        for (int k = 0; k < 3; ++k)
        {
          ASSERT_EQ(ids->GetId(k), referenceIds->GetId(k)) << "cell " << c;
        }
      }
    }
  }
  vtkSMPTools::SetBackend(saved.c_str());
}

TEST(PatchBoundaryMerge, MaximumErrorAndNoReduction)
{
  auto input = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkPatchBoundaryMerge> filter;
  // A target of the input size keeps the input.
  auto same = RunFilter(input, input->GetNumberOfCells(), filter);
  EXPECT_EQ(same->GetNumberOfCells(), input->GetNumberOfCells());
  // An error bound tighter than the target's epsilon wins: more triangles, epsilon at the bound.
  auto coarse = RunFilter(input, 266, filter);
  const double coarseEpsilon = filter->GetUsedEpsilon();
  filter->SetMaximumError(0.25 * coarseEpsilon);
  auto bounded = RunFilter(input, 266, filter);
  EXPECT_LE(filter->GetUsedEpsilon(), 0.25 * coarseEpsilon * (1 + 1e-9));
  EXPECT_GT(bounded->GetNumberOfCells(), coarse->GetNumberOfCells());
  ExpectValidClosedOutput(input, bounded, 0);
}

TEST(PatchBoundaryMerge, OpenSurfaceBorderIsPreserved)
{
  // A wavy open sheet: border vertices keep their place, one border loop, no holes.
  TriangleMesh grid = slodtest::Grid(60, 60);
  for (Index v = 0; v < grid.NumberOfPoints(); ++v)
  {
    Vec3 p = grid.Point(v);
    p[2] = 0.15 * std::sin(4 * p[0]) * std::cos(3 * p[1]);
    grid.SetPoint(v, p);
  }
  auto input = slodtest::ToPolyData(grid);
  vtkNew<vtkPatchBoundaryMerge> filter;
  auto out = RunFilter(input, 600, filter);
  const MeshStatistics st = RawStatistics(out);
  EXPECT_EQ(st.BoundaryLoops, 1);
  EXPECT_EQ(st.NonManifoldEdges, 0);
  EXPECT_EQ(st.NonManifoldVertices, 0);
  EXPECT_EQ(st.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(st.Components, 1);
  EXPECT_EQ(st.EulerCharacteristic, 1);
  // The four corners survive (border endpoints are never collapsed away).
  const auto kept = CoordinateSet(out);
  for (const auto& corner : { std::make_tuple(0.0, 0.0), std::make_tuple(1.0, 0.0), std::make_tuple(0.0, 1.0),
         std::make_tuple(1.0, 1.0) })
  {
    bool found = false;
    for (const auto& x : kept)
    {
      found = found || (std::abs(std::get<0>(x) - std::get<0>(corner)) < 1e-6 &&
                         std::abs(std::get<1>(x) - std::get<1>(corner)) < 1e-6);
    }
    EXPECT_TRUE(found);
  }
}

// Issue 10: a pinch vertex (two sheets touching at one vertex, as on noisy isosurfaces) must not
// become the interior of a patch: SPBM keeps no vertex inside a patch, so the sheet whose patch
// held the whole fan would drop it and the sheets would part (Euler characteristic + 1; seen on
// noisy:273). A flat sheet (one patch would hold the whole fan) and a paraboloid touching it from
// above at its centre; also the other way round (the pinch fan in the curved sheet's patches).
TEST(PatchBoundaryMerge, PinchVertexStaysOnBothSheets)
{
  for (const bool flatFirst : { true, false })
  {
    SCOPED_TRACE(flatFirst);
    const int n = 40;
    const TriangleMesh flat = slodtest::Grid(n, n);
    const Index center = (n / 2) * (n + 1) + n / 2;
    TriangleMesh mesh;
    std::vector<Index> second(size_t(flat.NumberOfPoints()));
    for (const int sheet : { 0, 1 })
    {
      const bool curved = (sheet == 1) == flatFirst;
      for (Index v = 0; v < flat.NumberOfPoints(); ++v)
      {
        Vec3 p = flat.Point(v);
        const double r2 = (p[0] - 0.5) * (p[0] - 0.5) + (p[1] - 0.5) * (p[1] - 0.5);
        p[2] = curved ? 1.5 * r2 : 0.0;
        second[v] = sheet == 1 && v == center ? center : mesh.AddPoint(p);
      }
      for (Index t = 0; t < flat.NumberOfTriangles(); ++t)
      {
        const Index* tri = flat.Triangle(t);
        mesh.AddTriangle(second[tri[0]], second[tri[1]], second[tri[2]]);
      }
    }
    auto input = slodtest::ToPolyData(mesh);
    const MeshStatistics in = RawStatistics(input);
    ASSERT_EQ(in.NonManifoldVertices, 1);
    for (const vtkIdType target : { 400, 120 })
    {
      vtkNew<vtkPatchBoundaryMerge> filter;
      auto out = RunFilter(input, target, filter);
      const MeshStatistics st = RawStatistics(out);
      EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic) << target;
      EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops) << target;
      EXPECT_EQ(st.Components, in.Components) << target;
      EXPECT_EQ(st.NonManifoldEdges, 0) << target;
      EXPECT_EQ(st.NonManifoldVertices, 1) << target;
    }
  }
}

TEST(PatchBoundaryMerge, SpiralRampStaysValidThroughFallbacks)
{
  // A helicoid ("spiralling ramp", section 4.2.8) with very loose patch angles: patch boundaries
  // overlap in projection, and the output must still be a valid surface with the input's border.
  TriangleMesh ramp = slodtest::Grid(16, 160);
  for (Index v = 0; v < ramp.NumberOfPoints(); ++v)
  {
    const Vec3 p = ramp.Point(v);
    const double radius = 0.3 + 0.7 * p[0], angle = 4 * Pi * p[1];
    ramp.SetPoint(v, { radius * std::cos(angle), radius * std::sin(angle), 0.15 * angle });
  }
  auto input = slodtest::ToPolyData(ramp);
  const MeshStatistics in = RawStatistics(input);
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetPatchAngle(80);
  filter->SetNeighborAngle(80);
  filter->SetPatchPlaneDistance(0);
  filter->AdaptPatchesToTargetOff(); // these loose patches are the case (finer ones would not overlap)
  filter->SetPatchDeviationFactor(0); // the same: no thickness bound splits them
  for (const vtkIdType target : { 2000, 300 })
  {
    auto out = RunFilter(input, target, filter);
    const MeshStatistics st = RawStatistics(out);
    EXPECT_GT(st.Triangles, 0);
    EXPECT_EQ(st.NonManifoldEdges, 0);
    EXPECT_EQ(st.NonManifoldVertices, 0);
    EXPECT_EQ(st.InconsistentlyOrientedEdges, 0);
    EXPECT_EQ(st.DegenerateTriangles, 0);
    EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops);
    EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(st.Components, 1);
    if (target == 2000)
    {
      // One spiralling patch whose border overlaps itself in projection at every resolution:
      // only the last fallback (its original triangles) is valid.
      EXPECT_GT(filter->GetOriginalPatches(), 0);
    }
  }
}

// With a negative epsilon every chain keeps all its vertices, so the finer-chain fallback levels
// cannot change a patch that failed unmerged: it goes to its original triangles next. The spiral
// ramp with loose patch angles has a patch whose border overlaps itself in projection at every
// resolution; before, it went through all seven fallback levels (8 passes, each a whole merging
// run and triangulation).
TEST(SpbmLevel, FullResolutionFallbackSkipsFinerChainLevels)
{
  TriangleMesh ramp = slodtest::Grid(16, 160);
  for (Index v = 0; v < ramp.NumberOfPoints(); ++v)
  {
    const Vec3 p = ramp.Point(v);
    const double radius = 0.3 + 0.7 * p[0], angle = 4 * Pi * p[1];
    ramp.SetPoint(v, { radius * std::cos(angle), radius * std::sin(angle), 0.15 * angle });
  }
  PatchificationParameters loose;
  loose.OneEdgePatchAngle = loose.OneEdgeNeighborAngle = 80;
  auto pm = Patch(ramp, loose);
  SpbmLevelGenerator generator;
  generator.Initialize(pm->Mesh, pm->Patches);
  SpbmLevelParameters parameters;
  parameters.Epsilon = -1;
  SpbmLevel level;
  ASSERT_TRUE(generator.Generate(parameters, level));
  ASSERT_GT(level.OriginalPatches, 0) << "the ramp must need the last fallback";
  EXPECT_EQ(level.RefinedPatches, 0);
  EXPECT_LE(level.Passes, 3);
  TriangleMesh out; // the level over its own vertices
  std::map<Index, Index> local;
  for (const Index v : level.Triangles)
  {
    const auto inserted = local.emplace(v, out.NumberOfPoints());
    if (inserted.second)
    {
      out.AddPoint(pm->Mesh.Point(v));
    }
    out.Triangles.push_back(inserted.first->second);
  }
  const MeshStatistics st = ComputeMeshStatistics(out);
  const MeshStatistics in = ComputeMeshStatistics(pm->Mesh);
  EXPECT_EQ(st.NonManifoldEdges, 0);
  EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops);
  EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic);
}

// The SPBM level of a tenth of the patched mesh's triangles (size-weighted merging), with `adjust`
// applied to the parameters the target search found.
template <typename Adjust>
void GenerateTenthLevel(const PatchedMesh& pm, Adjust&& adjust, SpbmLevel& level)
{
  SpbmLevelParameters base;
  base.SizeWeightedMerge = true;
  SpbmLevelGenerator generator;
  generator.Initialize(pm.Mesh, pm.Patches);
  SpbmLevelParameters parameters = generator.FindParameters(pm.Mesh.NumberOfTriangles() / 10, base);
  adjust(parameters);
  ASSERT_TRUE(generator.Generate(parameters, level));
}

// The patched noisy scan of `seed` at resolution 48 (surfaces no other PBM test tunes for); null
// when it cannot be prepared.
std::unique_ptr<PatchedMesh> PatchedNoisyScan(unsigned int seed)
{
  TriangleMesh mesh;
  std::vector<Index> vertexToInput;
  if (!PrepareTriangleMesh(slodtest::NoisyScanIsosurface(48, seed), PreparationOptions(), mesh, vertexToInput).Valid)
  {
    return nullptr;
  }
  return Patch(mesh);
}

// The level over the mesh's points keeps the input's Euler characteristic and border loops, has no
// more non-manifold edges and is consistently oriented.
void ExpectInputTopology(const PatchedMesh& pm, const MeshStatistics& in, const SpbmLevel& level, unsigned int seed)
{
  TriangleMesh out;
  out.Points = pm.Mesh.Points;
  out.Triangles = level.Triangles;
  out.RemoveUnusedPoints();
  const MeshStatistics st = ComputeMeshStatistics(out);
  EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic) << "seed " << seed;
  EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops) << "seed " << seed;
  EXPECT_LE(st.NonManifoldEdges, in.NonManifoldEdges) << "seed " << seed;
  EXPECT_EQ(st.InconsistentlyOrientedEdges, 0) << "seed " << seed;
}

// The tenth levels of the noisy scan of `seed` (a surface no other PBM test tunes for) with the
// boolean parameter `option` on and off.
void NoisyScanTenthLevelsWithAndWithout(unsigned int seed, bool SpbmLevelParameters::*option, SpbmLevel& on, SpbmLevel& off)
{
  auto pm = PatchedNoisyScan(seed);
  ASSERT_TRUE(pm) << "seed " << seed;
  GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { p.*option = true; }, on);
  GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { p.*option = false; }, off);
}

// Two generations of the same level (a switch between equivalent ways of doing the same work): the
// same triangles, patches and profile curves, in the same passes with the same replayed edits.
// sameCleanEdits: the replays also applied the same edits as recorded (false for an option that
// changes which edits are tested again).
void ExpectSameLevelInSamePasses(const SpbmLevel& a, const SpbmLevel& b, unsigned int seed, bool sameCleanEdits = true)
{
  EXPECT_EQ(a.Triangles, b.Triangles) << "seed " << seed;
  EXPECT_EQ(a.TrianglePatch, b.TrianglePatch) << "seed " << seed;
  EXPECT_EQ(a.CurveVertices, b.CurveVertices) << "seed " << seed;
  EXPECT_EQ(a.Passes, b.Passes) << "seed " << seed;
  EXPECT_EQ(a.ReplayedPasses, b.ReplayedPasses) << "seed " << seed;
  if (sameCleanEdits)
  {
    EXPECT_EQ(a.EditsAppliedAsRecorded, b.EditsAppliedAsRecorded) << "seed " << seed;
  }
}

// For each seed: the tenth levels of its noisy scan with adjust(parameters, true) and
// adjust(parameters, false), which must be the same level in the same passes (the switch changes
// how the work is done), then `check(on, off, seed)` for what it changes.
template <typename Adjust, typename Check>
void ExpectSameLevelsAdjusted(std::initializer_list<unsigned int> seeds, Adjust&& adjust, Check&& check)
{
  for (const unsigned int seed : seeds)
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    SpbmLevel on, off;
    for (const bool option : { true, false })
    {
      GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { adjust(p, option); }, option ? on : off);
    }
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
    ExpectSameLevelInSamePasses(on, off, seed);
    check(on, off, seed);
  }
}

// The same with the boolean parameter `option` on and off.
template <typename Check>
void ExpectSameLevelsWithAndWithout(
  std::initializer_list<unsigned int> seeds, bool SpbmLevelParameters::*option, Check&& check)
{
  ExpectSameLevelsAdjusted(seeds, [option](SpbmLevelParameters& p, bool on) { p.*option = on; }, check);
}

// Issue 10: a fallback pass that unmerges patches replays the previous pass's merging edits with
// those patches frozen (edits whose neighbourhood is unchanged as recorded, the others tested
// again) and merges again around them, instead of a whole merging run. On a noisy scan surface
// (MRI-like, needs several such passes; a mesh no other PBM test tunes for) the level keeps the
// input's topology like a whole run's, is deterministic, and keeps at most a few percent more
// triangles than the whole runs give.
TEST(SpbmLevel, FallbackPassesReplayTheRecordedMerging)
{
  TriangleMesh mesh;
  std::vector<Index> vertexToInput;
  ASSERT_TRUE(PrepareTriangleMesh(slodtest::NoisyScanIsosurface(48, 2), PreparationOptions(), mesh, vertexToInput).Valid);
  auto pm = Patch(mesh);
  const MeshStatistics in = ComputeMeshStatistics(pm->Mesh);
  auto generate = [&](bool replay, SpbmLevel& level) {
    GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { p.ReplayFallbackPasses = replay; }, level);
  };
  SpbmLevel replayed, again, whole;
  generate(true, replayed);
  generate(true, again);
  generate(false, whole);
  ASSERT_GT(replayed.UnmergedPatches, 0) << "the noisy scan must need passes that unmerge patches";
  EXPECT_GT(replayed.ReplayedPasses, 0);
  EXPECT_EQ(whole.ReplayedPasses, 0);
  EXPECT_EQ(replayed.Triangles, again.Triangles);
  EXPECT_LE(replayed.TrianglePatch.size(), whole.TrianglePatch.size() * 21 / 20);
  for (const SpbmLevel* level : { &replayed, &whole })
  {
    TriangleMesh out;
    out.Points = pm->Mesh.Points;
    out.Triangles = level->Triangles;
    out.RemoveUnusedPoints();
    const MeshStatistics st = ComputeMeshStatistics(out);
    EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops);
    EXPECT_LE(st.NonManifoldEdges, in.NonManifoldEdges);
    EXPECT_EQ(st.InconsistentlyOrientedEdges, 0);
  }
}

// Session 16: a replayed pass tests whether an edit is clean from flags on its endpoints (kept up
// to date as patches turn dirty, unite and endpoints collapse) instead of walking the patches
// around them. On noisy scans of seeds no other test uses, both give the same levels.
TEST(SpbmLevel, ReplayCleanTestFlagsMatchTheWalk)
{
  int replayedPasses = 0;
  for (const unsigned int seed : { 7u, 11u, 13u })
  {
    SpbmLevel flags, walked;
    NoisyScanTenthLevelsWithAndWithout(seed, &SpbmLevelParameters::WalkAroundEditEndpoints, walked, flags);
    ASSERT_FALSE(HasFatalFailure()) << "seed " << seed;
    ExpectSameLevelInSamePasses(flags, walked, seed);
    replayedPasses += flags.ReplayedPasses;
  }
  EXPECT_GT(replayedPasses, 0) << "the noisy scans must need replayed passes";
}

// Session 17 (issue 10): a merged patch that fails to triangulate (on scan isosurfaces: every
// diagonal is already an edge) first keeps one more boundary vertex and the pass triangulates
// again; only the patches that still fail go to the fallback levels (each unmerging pass replays
// the whole merging record). On noisy scans of seeds no other test uses, the rounds keep vertices,
// fewer patches go to the fallback levels and fewer are unmerged, and the level keeps the input's
// topology and orientation.
TEST(SpbmLevel, FailedPatchesKeepAVertexMoreBeforeTheFallback)
{
  bool fewerUnmerged = false;
  for (const unsigned int seed : { 17u, 19u })
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    const MeshStatistics in = ComputeMeshStatistics(pm->Mesh);
    SpbmLevel rounds, none;
    GenerateTenthLevel(*pm, [](SpbmLevelParameters& p) { p.FailedPatchRefinementRounds = 3; }, rounds);
    GenerateTenthLevel(*pm, [](SpbmLevelParameters& p) { p.FailedPatchRefinementRounds = 0; }, none);
    ASSERT_FALSE(HasFatalFailure()) << "seed " << seed;
    ASSERT_GT(none.FailedPatches, 0) << "seed " << seed << ": the noisy scan must have patches that fail";
    EXPECT_EQ(none.RefinedInPass, 0) << "seed " << seed;
    EXPECT_GT(rounds.RefinedInPass, 0) << "seed " << seed;
    EXPECT_LT(rounds.FailedPatches, none.FailedPatches) << "seed " << seed;
    EXPECT_LE(rounds.UnmergedPatches, none.UnmergedPatches) << "seed " << seed;
    fewerUnmerged = fewerUnmerged || rounds.UnmergedPatches < none.UnmergedPatches;
    ExpectInputTopology(*pm, in, rounds, seed);
  }
  EXPECT_TRUE(fewerUnmerged) << "the rounds must spare some patch its unmerging";
}

// Session 14: an unmerged patch that fails again goes to the next fallback level that makes its
// chains keep more vertices; the levels in between would repeat the same pass. On noisy scans (a
// surface no other PBM test tunes for) the level is the same as with one level per pass, in fewer
// passes.
TEST(SpbmLevel, IneffectiveFallbackLevelsAreSkipped)
{
  bool skipped = false;
  for (const unsigned int seed : { 2u, 3u, 5u })
  {
    SpbmLevel fast, slow;
    NoisyScanTenthLevelsWithAndWithout(seed, &SpbmLevelParameters::SkipIneffectiveFallbackLevels, fast, slow);
    ASSERT_FALSE(HasFatalFailure()) << "seed " << seed;
    EXPECT_EQ(fast.Triangles, slow.Triangles) << "seed " << seed;
    EXPECT_EQ(fast.OriginalPatches, slow.OriginalPatches) << "seed " << seed;
    EXPECT_LE(fast.Passes, slow.Passes) << "seed " << seed;
    skipped = skipped || fast.Passes < slow.Passes;
  }
  EXPECT_TRUE(skipped) << "some noisy scan must need a fallback level that changes nothing";
}

// Session 21 (issue 10): when final collapses finish the level (FinalCollapsesFollow) and a pass
// already ends beyond their tolerance of the count, an unmerged patch that fails again goes
// straight to its original triangles instead of through the finer-chain levels, each one a pass.
// On noisy scans (seeds no other test uses; their tenth is beyond the removal's reach, so the
// collapses follow) no patch ends at a finer-chain level, no more passes are run than without,
// fewer on some scan, and the level keeps the input's topology.
TEST(SpbmLevel, FailingUnmergedPatchesGoStraightToOriginalWhenCollapsesFollow)
{
  bool fewerPasses = false;
  for (const unsigned int seed : { 41u, 43u, 47u })
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    const MeshStatistics in = ComputeMeshStatistics(pm->Mesh);
    SpbmLevel on, off;
    GenerateTenthLevel(*pm, [](SpbmLevelParameters& p) { p.FinalCollapsesFollow = true; }, on);
    GenerateTenthLevel(*pm, [](SpbmLevelParameters& p) { p.FinalCollapsesFollow = false; }, off);
    ASSERT_FALSE(HasFatalFailure()) << "seed " << seed;
    ASSERT_GT(Index(on.TrianglePatch.size()), SpbmFinalCollapseTolerance(pm->Mesh.NumberOfTriangles() / 10) +
        pm->Mesh.NumberOfTriangles() / 10)
      << "seed " << seed << ": the tenth must be beyond the removal's reach";
    EXPECT_EQ(on.RefinedPatches, 0) << "seed " << seed;
    EXPECT_LE(on.Passes, off.Passes) << "seed " << seed;
    fewerPasses = fewerPasses || on.Passes < off.Passes;
    ExpectInputTopology(*pm, in, on, seed);
  }
  EXPECT_TRUE(fewerPasses) << "some noisy scan must have patches that went through finer-chain levels before";
}

// Session 27 (issue 10): when final collapses finish the level (FinalCollapsesFollow) and the
// cost-ordered removal at RemovalMergeAngle stops more than a quarter above the target, the search
// stops there: the merging run at 90 degrees only lowered a count the collapses take to the target
// anyway. On noisy scans of seeds no other test uses (their tenth is far beyond the removal's
// reach), the search takes
// fewer merging runs, keeps the removal at RemovalMergeAngle, and its level keeps the input's
// topology.
TEST(SpbmLevel, SearchStopsAtRemovalAngleWhenCollapsesFollow)
{
  for (const unsigned int seed : { 71u, 73u })
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    const MeshStatistics in = ComputeMeshStatistics(pm->Mesh);
    const Index target = pm->Mesh.NumberOfTriangles() / 10;
    int runs[2] = { 0, 0 };
    Index predicted[2] = { 0, 0 };
    SpbmLevelParameters found[2];
    SpbmLevel level;
    for (const bool follow : { false, true })
    {
      SpbmLevelParameters base;
      base.SizeWeightedMerge = true;
      base.FinalCollapsesFollow = follow;
      SpbmLevelGenerator generator;
      generator.Initialize(pm->Mesh, pm->Patches);
      found[follow] = generator.FindParameters(target, base, &predicted[follow]);
      runs[follow] = generator.MergingRunCount();
      if (follow)
      {
        ASSERT_TRUE(generator.Generate(found[follow], level)) << "seed " << seed;
      }
    }
    ASSERT_GT(4 * predicted[0], 5 * target) << "seed " << seed << ": the tenth must be far beyond the removal's reach";
    EXPECT_GT(found[1].RemovalTarget, 0) << "seed " << seed;
    EXPECT_EQ(found[1].MergeAngle, found[1].RemovalMergeAngle) << "seed " << seed;
    EXPECT_LT(runs[1], runs[0]) << "seed " << seed << ": merging runs " << runs[1] << " with, " << runs[0] << " without";
    EXPECT_GE(predicted[1], predicted[0]) << "seed " << seed; // the widest merging lowers the count
    ExpectInputTopology(*pm, in, level, seed);
  }
}

// Session 22 (issue 10): a chain's kept vertices are rebuilt only when its tolerance or locking
// changed (RebuildOnlyChangedChains; each refinement round and each merging pass rebuilt every
// chain). On noisy scans of seeds no other test uses, the levels are the same with and without
// (triangles, patches, profile curves), in the same passes, and the passes' merging rebuilds fewer
// chains.
TEST(SpbmLevel, MergingPassesRebuildOnlyTheChainsThatChanged)
{
  long long rebuildsOn = 0, rebuildsOff = 0;
  ExpectSameLevelsWithAndWithout({ 53u, 59u }, &SpbmLevelParameters::RebuildOnlyChangedChains,
    [&](const SpbmLevel& on, const SpbmLevel& off, unsigned int seed) {
      EXPECT_LE(on.ChainRebuilds, off.ChainRebuilds) << "seed " << seed;
      rebuildsOn += on.ChainRebuilds;
      rebuildsOff += off.ChainRebuilds;
    });
  ASSERT_GT(rebuildsOff, 0) << "the noisy scans must need merging passes after the search's";
  EXPECT_LT(rebuildsOn, rebuildsOff) << "chain rebuilds " << rebuildsOn << " with, " << rebuildsOff << " without";
}

// Session 39 (issue 10): a boundary walk takes the side of each chain from its slot (a left-side
// slot stays in the list of its left patch's root, unions splice whole lists) and looks through the
// patch records (Find) only for right-side slots. On noisy scans of seeds no other test uses, the
// level's walks went along chains and needed that Find for fewer of them than they walked (before:
// one per chain walked).
TEST(SpbmLevel, BoundaryWalksFindOnlyTheRightSides)
{
  for (const unsigned int seed : { 167u, 173u })
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    SpbmLevel level;
    GenerateTenthLevel(*pm, [](SpbmLevelParameters&) {}, level);
    ASSERT_FALSE(level.Triangles.empty()) << "seed " << seed;
    ASSERT_GT(level.WalkedChains, 0) << "seed " << seed << ": the level's merging must walk boundaries";
    EXPECT_LT(level.WalkSideFinds, level.WalkedChains)
      << "seed " << seed << ": " << level.WalkSideFinds << " Finds for " << level.WalkedChains << " chains walked";
  }
}

// Session 22 (issue 10): a replayed pass applies its clean unions without uniting the patches'
// supports (extreme vertices); a support read later is brought up to date by folding in the
// patches absorbed since, in union order (FoldSupportsWhenRead). With the flatness measure (which
// reads the supports of every merge candidate), on noisy scans of seeds no other test uses, the
// levels are the same with and without, supports were read after replayed unions, and fewer
// supports were united.
TEST(SpbmLevel, ReplayedUnionsFoldTheirSupportsWhenRead)
{
  long long unionsOn = 0, unionsOff = 0, folds = 0;
  ExpectSameLevelsAdjusted(
    { 61u, 67u },
    [](SpbmLevelParameters& p, bool fold) {
      p.FlatnessMerge = true;
      p.FoldSupportsWhenRead = fold;
    },
    [&](const SpbmLevel& on, const SpbmLevel& off, unsigned int seed) {
      EXPECT_LE(on.SupportUnions, off.SupportUnions) << "seed " << seed;
      EXPECT_EQ(off.SupportFolds, 0) << "seed " << seed;
      unionsOn += on.SupportUnions;
      unionsOff += off.SupportUnions;
      folds += on.SupportFolds;
    });
  ASSERT_GT(folds, 0) << "supports must be read after replayed unions";
  EXPECT_LT(unionsOn, unionsOff) << "supports united " << unionsOn << " with, " << unionsOff << " without";
}

// Session 24 (issue 10): a fallback pass triangulates again only the patches whose boundary may
// have changed since the pass before (and those next to them); the others keep their triangles
// (LocalFallbackTriangulation). On noisy scans of seeds no other test uses, which need fallback
// passes, the level is the one the whole-level passes give (the same triangles in the same order),
// and all the fallback passes together triangulate fewer patches than the level has (the
// whole-level passes: every patch in every pass).
TEST(SpbmLevel, FallbackPassesTriangulateOnlyTheChangedPatches)
{
  int fallbackPasses = 0;
  ExpectSameLevelsWithAndWithout({ 71u, 73u }, &SpbmLevelParameters::LocalFallbackTriangulation,
    [&](const SpbmLevel& local, const SpbmLevel& whole, unsigned int seed) {
      EXPECT_EQ(local.FailedPatches, whole.FailedPatches) << "seed " << seed;
      if (local.Passes > 1)
      {
        EXPECT_GE(whole.RetriangulatedPatches, Index(local.Passes - 1) * whole.NumberOfPatches / 2)
          << "seed " << seed;
        EXPECT_LT(local.RetriangulatedPatches, local.NumberOfPatches) << "seed " << seed;
      }
      fallbackPasses += local.Passes - 1;
    });
  EXPECT_GT(fallbackPasses, 0) << "the noisy scans must need fallback passes";
}

// Session 31 (issue 10): in a fallback pass, an unchanged patch that no changed patch or chain
// touches (no shared vertex) keeps its triangles without its edge context being computed again
// (ReuseUntouchedPatches). On noisy scans of seeds no other test uses, which need fallback
// passes: the level is the one the full comparison gives (the same triangles in the same order,
// patches, curves, passes and failures); without the option every kept patch is compared, with it
// most kept patches of the fallback passes are not (a pass that compares or triangulates again
// patches far from what changed fails this), and the work the passes do on patches (compared or
// triangulated again) falls below half of what the reference does.
TEST(SpbmLevel, FallbackPassesCompareOnlyThePatchesNextToAChange)
{
  Index untouched = 0, comparedOn = 0, comparedOff = 0, workOn = 0, workOff = 0;
  ExpectSameLevelsWithAndWithout({ 101u, 103u }, &SpbmLevelParameters::ReuseUntouchedPatches,
    [&](const SpbmLevel& on, const SpbmLevel& off, unsigned int seed) {
      EXPECT_EQ(on.FailedPatches, off.FailedPatches) << "seed " << seed;
      // The reference also triangulates again the patches whose boundary segment is recorded under
      // another (non-manifold) chain: its check of the kept triangles' edges refuses them, and
      // their triangulation comes out as before.
      EXPECT_LE(on.RetriangulatedPatches, off.RetriangulatedPatches) << "seed " << seed;
      EXPECT_EQ(off.ReusedUntouched, 0) << "seed " << seed;
      EXPECT_LE(on.ContextsCompared + on.ReusedUntouched, off.ContextsCompared + off.RetriangulatedPatches)
        << "seed " << seed;
      untouched += on.ReusedUntouched;
      comparedOn += on.ContextsCompared;
      comparedOff += off.ContextsCompared;
      workOn += on.ContextsCompared + on.RetriangulatedPatches;
      workOff += off.ContextsCompared + off.RetriangulatedPatches;
    });
  ASSERT_GT(comparedOff, 0) << "the noisy scans must need fallback passes that keep patches";
  EXPECT_GT(untouched, 2 * comparedOn) << untouched << " kept untouched, " << comparedOn << " compared";
  EXPECT_LT(2 * workOn, workOff) << "patches compared or triangulated again: " << workOn << " with, " << workOff
                                 << " without";
  std::cout << "kept untouched " << untouched << ", compared " << comparedOn << " (reference " << comparedOff
            << "); patch work " << workOn << " with, " << workOff << " without\n";
}

// The tenth levels of the noisy scans of `seeds` with the boolean parameter `option` on, with 1, 2
// and 8 threads, are the level without it (the same triangles in the same passes); `check(on, off,
// seed, threads)` looks at each.
template<typename Check>
void ExpectSameLevelsOverThreads(std::initializer_list<unsigned int> seeds, bool SpbmLevelParameters::*option, Check&& check)
{
  for (const unsigned int seed : seeds)
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    SpbmLevel reference;
    GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { p.*option = false; }, reference);
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
    slodtest::ForOneTwoAndEightThreads([&](int threads) {
      SpbmLevel on;
      GenerateTenthLevel(*pm, [&](SpbmLevelParameters& p) { p.*option = true; }, on);
      ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed << ", " << threads << " threads";
      ExpectSameLevelInSamePasses(on, reference, seed);
      check(on, reference, seed, threads);
    });
  }
}

// Session 33 (issue 10): in a fallback pass, a patch kept as its original triangles in the pass
// before too no longer counts as changed (KeptOriginalPatchesUnchanged), so the patches across its
// chains keep their triangles. On noisy scans of seeds 107 and 131, with the final
// collapses to follow (failed unmerged patches go to their original triangles): the level is the
// reference's (the same triangles in the same order, patches, curves, passes and failures), the
// levels have original patches through several passes, and the passes triangulate again fewer
// patches with the option than without.
TEST(SpbmLevel, FallbackPassesLeaveThePatchesAroundKeptOriginalPatches)
{
  Index original = 0, againOn = 0, againOff = 0;
  int laterPasses = 0;
  // The final collapses follow: failed unmerged patches go straight to their original triangles.
  const auto keptOriginals = [](SpbmLevelParameters& p, bool kept) {
    p.FinalCollapsesFollow = true;
    p.KeptOriginalPatchesUnchanged = kept;
  };
  ExpectSameLevelsAdjusted({ 107u, 131u }, keptOriginals, [&](const SpbmLevel& on, const SpbmLevel& off, unsigned int seed) {
    EXPECT_EQ(on.FailedPatches, off.FailedPatches) << "seed " << seed;
    EXPECT_LE(on.RetriangulatedPatches, off.RetriangulatedPatches) << "seed " << seed;
    original += on.OriginalPatches;
    laterPasses += std::max(0, on.Passes - 2);
    againOn += on.RetriangulatedPatches;
    againOff += off.RetriangulatedPatches;
  });
  ASSERT_GT(original, 0) << "the noisy scans must keep original patches";
  ASSERT_GT(laterPasses, 0) << "the noisy scans must need passes after an original patch is made";
  EXPECT_LT(againOn, againOff) << "patches triangulated again: " << againOn << " with, " << againOff << " without";
  std::cout << original << " original patches, " << laterPasses << " later passes; triangulated again " << againOn
            << " with, " << againOff << " without\n";
}

// Session 29 (issue 10): a whole-level pass measures the diagonal costs of its minimum-deviation
// triangulations first, over threads, into per-diagonal slots cached in the serial order
// (MeasureDiagonalsAhead). On noisy scans of seeds no other test uses, with 1, 2 and 8 threads:
// the level is the on-demand reference's (the same triangles in the same passes), diagonals were
// measured ahead, none without the option.
TEST(SpbmLevel, DiagonalCostsMeasuredAheadOverThreadsGiveTheSameLevel)
{
  ExpectSameLevelsOverThreads({ 89u, 97u }, &SpbmLevelParameters::MeasureDiagonalsAhead,
    [](const SpbmLevel& ahead, const SpbmLevel& reference, unsigned int seed, int threads) {
      EXPECT_EQ(reference.DiagonalsMeasuredAhead, 0) << "seed " << seed;
      EXPECT_GT(ahead.DiagonalsMeasuredAhead, 0) << "seed " << seed << ", " << threads << " threads";
      std::cout << "seed " << seed << ", " << threads << " threads: " << ahead.DiagonalsMeasured
                << " diagonals measured (" << ahead.DiagonalsMeasuredAhead << " ahead), "
                << reference.DiagonalsMeasured << " on demand\n";
    });
}

// Session 33 (issue 10): the first pass runs its minimum-deviation triangulations over threads
// against the level's edges before the pass and keeps each unless a diagonal the pass made since
// joins two corners the triangulation asked about (TriangulateAheadOverThreads). On noisy scans of
// seeds no other test uses, with 1, 2 and 8 threads: the level is the serial reference's (the same
// triangles in the same passes); patches took their triangles from ahead, and on these rough
// surfaces some had to be triangulated again (a check that misses such a diagonal, or takes a
// triangulation for the wrong patch, gives another level); none without the option.
TEST(SpbmLevel, TriangulationsAheadOverThreadsGiveTheSameLevel)
{
  Index again = 0;
  ExpectSameLevelsOverThreads({ 107u, 109u }, &SpbmLevelParameters::TriangulateAheadOverThreads,
    [&](const SpbmLevel& ahead, const SpbmLevel& reference, unsigned int seed, int threads) {
      EXPECT_EQ(reference.TriangulatedAhead + reference.TriangulatedAgain, 0) << "seed " << seed;
      EXPECT_GT(ahead.TriangulatedAhead, 0) << "seed " << seed << ", " << threads << " threads";
      again += ahead.TriangulatedAgain;
      std::cout << "seed " << seed << ", " << threads << " threads: " << ahead.TriangulatedAhead
                << " patches triangulated ahead, " << ahead.TriangulatedAgain << " again\n";
    });
  EXPECT_GT(again, 0) << "the noisy scans must have patches whose triangulation ahead does not hold";
}

// Session 34 (issue 10): with two threads and the second working state idle (CompareCandidates
// off), GenerateForTarget's search probes the given alpha1 beside RemovalMergeAngle, one merging run
// in each working state, and cancels the wider one when the given alpha1 reaches the target
// (ProbeAnglesSideBySide). On surfaces no other test tunes for, with 1, 2 and 8 threads: the same
// parameters and level as the serial order (the option off), the probes side by side with two
// threads or more and never with one, and among the cases both outcomes: the given alpha1 reaching
// the target (a level without the removal at it) and the removal deciding.
TEST(SpbmLevel, AngleProbesSideBySideGiveTheSameLevel)
{
  struct Case
  {
    std::string Name;
    std::unique_ptr<PatchedMesh> Patched;
    Index Target;
  };
  std::vector<Case> cases;
  for (const unsigned int seed : { 113u, 127u })
  {
    auto pm = PatchedNoisyScan(seed);
    ASSERT_TRUE(pm) << "seed " << seed;
    const Index target = pm->Mesh.NumberOfTriangles() / 10;
    cases.push_back({ "noisy scan " + std::to_string(seed), std::move(pm), target });
  }
  {
    auto pm = Patch(slodtest::ToTriangleMesh(slodtest::SyntheticIsosurface(60)));
    const Index target = pm->Mesh.NumberOfTriangles() / 10;
    cases.push_back({ "synthetic isosurface", std::move(pm), target });
  }
  const auto generate = [](const Case& c, bool sideBySide, SpbmLevel& level, SpbmLevelParameters& used, int& probes) {
    SpbmLevelParameters base;
    base.SizeWeightedMerge = true;
    base.CompareCandidates = false;
    base.ProbeAnglesSideBySide = sideBySide;
    SpbmLevelGenerator generator;
    generator.Initialize(c.Patched->Mesh, c.Patched->Patches);
    ASSERT_TRUE(generator.GenerateForTarget(c.Target, base, level, &used));
    probes = generator.SideBySideProbeCount();
  };
  int givenReached = 0, removalDecided = 0;
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.Name);
    SpbmLevel reference;
    SpbmLevelParameters referenceUsed;
    int referenceProbes = 0;
    generate(c, false, reference, referenceUsed, referenceProbes);
    ASSERT_FALSE(HasFatalFailure());
    EXPECT_EQ(referenceProbes, 0);
    slodtest::ForOneTwoAndEightThreads([&](int threads) {
      SpbmLevel level;
      SpbmLevelParameters used;
      int probes = 0;
      generate(c, true, level, used, probes);
      ASSERT_FALSE(HasFatalFailure()) << threads << " threads";
      EXPECT_EQ(level.Triangles, reference.Triangles) << threads << " threads";
      EXPECT_EQ(level.Passes, reference.Passes) << threads << " threads";
      EXPECT_EQ(used.Epsilon, referenceUsed.Epsilon) << threads << " threads";
      EXPECT_EQ(used.MergeAngle, referenceUsed.MergeAngle) << threads << " threads";
      EXPECT_EQ(used.RemovalTarget, referenceUsed.RemovalTarget) << threads << " threads";
      if (threads == 1)
      {
        EXPECT_EQ(probes, 0);
      }
      else
      {
        EXPECT_GT(probes, 0) << threads << " threads";
      }
      std::cout << c.Name << ", " << threads << " threads: alpha1 " << used.MergeAngle << ", removal "
                << used.RemovalTarget << ", " << level.TrianglePatch.size() << " triangles, " << probes
                << " side-by-side probes\n";
    });
    givenReached += referenceUsed.RemovalTarget == 0 && referenceUsed.MergeAngle == SpbmLevelParameters().MergeAngle;
    removalDecided += referenceUsed.RemovalTarget > 0;
  }
  EXPECT_GT(givenReached, 0) << "a case must reach the target at the given alpha1";
  EXPECT_GT(removalDecided, 0) << "a case must need the removal";
}

// Session 25 (issue 10): a replayed pass treats the patches frozen at the same fallback level as
// in the recorded run as clean (FrozenPatchesAreClean): the edits next to them are applied as
// recorded instead of being tested again in every pass (with each collapse's recorded walk root
// kept, which their tests read). On noisy scans of seeds no other test uses, which need several
// replayed passes: the same level in the same passes with and without, and fewer edits tested
// again; without, every replay after the first tests again at least the edits next to the
// patches unmerged before it.
TEST(SpbmLevel, ReplaysApplyTheEditsNextToUnchangedFrozenPatchesAsRecorded)
{
  long long testedOn = 0, testedOff = 0;
  int replays = 0;
  for (const unsigned int seed : { 79u, 83u })
  {
    SpbmLevel on, off;
    NoisyScanTenthLevelsWithAndWithout(seed, &SpbmLevelParameters::FrozenPatchesAreClean, on, off);
    ASSERT_FALSE(HasFatalFailure()) << "seed " << seed;
    ExpectSameLevelInSamePasses(on, off, seed, false);
    EXPECT_LE(on.EditsTestedAgain, off.EditsTestedAgain) << "seed " << seed;
    EXPECT_GE(on.EditsAppliedAsRecorded, off.EditsAppliedAsRecorded) << "seed " << seed;
    testedOn += on.EditsTestedAgain;
    testedOff += off.EditsTestedAgain;
    replays += on.ReplayedPasses;
  }
  ASSERT_GT(replays, 2) << "the noisy scans must need replayed passes after the first";
  EXPECT_LT(testedOn, testedOff) << "edits tested again " << testedOn << " with, " << testedOff << " without";
}

// The finest level's count is bounded from below without a merging run (the filter skips that
// run when the bound reaches the target): never above the count a run finds, at the paper's
// angle and the filter's. And FinestLevelCount, which the filter uses instead of that run, is
// the run's count exactly (merges keep the count, nothing is joined or collapsed at full
// resolution), with either merge measure.
TEST(SpbmLevel, FinestLevelLowerBoundHolds)
{
  std::vector<TriangleMesh> meshes = { slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk")),
    slodtest::ToTriangleMesh(slodtest::LoadTestMesh("elephant")) };
  std::vector<Index> vertexToInput;
  meshes.emplace_back();
  ASSERT_TRUE(PrepareTriangleMesh(slodtest::NoisyScanIsosurface(40, 5), PreparationOptions(), meshes.back(), vertexToInput).Valid);
  for (const TriangleMesh& mesh : meshes)
  {
    auto pm = Patch(mesh);
    SpbmLevelGenerator generator;
    generator.Initialize(pm->Mesh, pm->Patches);
    const Index bound = generator.FinestLevelLowerBound();
    EXPECT_GT(bound, 0);
    for (const double angle : { 20.0, 60.0 })
    {
      SpbmLevelParameters finest;
      finest.Epsilon = -1;
      finest.MergeAngle = angle;
      finest.SizeWeightedMerge = true;
      EXPECT_LE(bound, generator.PredictTriangleCount(finest)) << mesh.NumberOfTriangles() << " " << angle;
      for (const bool weighted : { true, false })
      {
        finest.SizeWeightedMerge = weighted;
        const Index counted = generator.FinestLevelCount(finest);
        EXPECT_EQ(counted, generator.PredictTriangleCount(finest)) << mesh.NumberOfTriangles() << " " << angle;
      }
    }
  }
}

// Thin patches of a test mesh, as the filter grows them for mild targets (its plane distance cap
// follows the target: PatchDeviationFactor), with the size-weighted merge and the finest level's
// count (known without a merging run).
struct ThinPatchesAtMildTarget
{
  explicit ThinPatchesAtMildTarget(const char* name)
  {
    const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh(name));
    PatchificationParameters thin;
    thin.RulingAngle = 1.0;
    thin.BoundPatchThickness = true;
    thin.MaximumPlaneDistance = 1e-4 * mesh.BoundingBoxDiagonal();
    this->Patched = Patch(mesh, thin);
    this->Base.SizeWeightedMerge = true;
    SpbmLevelGenerator probe;
    probe.Initialize(this->Patched->Mesh, this->Patched->Patches);
    SpbmLevelParameters finest = this->Base;
    finest.Epsilon = -1;
    this->FinestCount = probe.FinestLevelCount(finest);
  }
  std::unique_ptr<PatchedMesh> Patched;
  // share of the finest level's count, rounded down
  Index Target(double share) const { return static_cast<Index>(share * double(this->FinestCount)); }
  SpbmLevelParameters Base;
  Index FinestCount = 0;
};

// Issue 15 (SPBM's speed at mild targets): every evaluation of the target search is a whole
// merging run, and at mild targets the patches are small and many (mc1m at 50%: 304,459), so the
// runs are the level's time. Bracketing epsilon by the full-resolution count (known without a
// run) and narrowing by secant steps in sqrt(kept keys) needs fewer runs than the former steps
// of two triangles per key and regula falsi in k, at half and 70% of the finest level's count of
// thin patches, for counts as close to the target from below. (Four meshes: the former search
// took 48 runs, this one 36; with the paper's coarse patches, where the count is closer to
// linear in k, it is not fewer: 41 and 47, see PatchBoundaryMerge.md, session 26.)
TEST(SpbmLevel, MildTargetSearchTakesFewerMergingRuns)
{
  int runs[2] = { 0, 0 };
  for (const char* name : { "bunny00", "fandisk", "elephant", "armadillo" })
  {
    const ThinPatchesAtMildTarget thin(name);
    const auto& pm = thin.Patched;
    SpbmLevelParameters base = thin.Base;
    // The epsilon searches alone: the band step after them (ReachBandAcrossKeyJumps) may end up to
    // 2% above the target and adds its own runs.
    base.ReachBandAcrossKeyJumps = false;
    for (const double share : { 0.5, 0.7 })
    {
      const Index target = thin.Target(share);
      Index predicted[2] = { 0, 0 };
      for (const bool secant : { false, true })
      {
        SpbmLevelGenerator generator;
        generator.Initialize(pm->Mesh, pm->Patches);
        base.SecantKeptVertexSearch = secant;
        generator.FindParameters(target, base, &predicted[secant]);
        runs[secant] += generator.MergingRunCount();
        EXPECT_LE(predicted[secant], target) << name << " " << share << " secant " << secant;
      }
      // As close as the former search whenever that one was within the 2% band.
      if (50 * predicted[0] >= 49 * target)
      {
        EXPECT_GE(50 * predicted[1], 49 * target) << name << " " << share;
      }
    }
  }
  EXPECT_LT(runs[1], runs[0]) << "merging runs with the secant search " << runs[1] << ", former " << runs[0];
}

// Issue 15 (session 27): MildTargetProbesMergeAngleFirst. At a target of at least half the finest
// level's count the given alpha1 is evaluated first; when it reaches the target, the probe at
// RemovalMergeAngle (lower still) is not run: the same parameters and count, one merging run fewer
// (the former order probed RemovalMergeAngle first). Thin patches as for mild targets, on meshes
// whose coarsest level at alpha1 is below such targets.
TEST(SpbmLevel, MildTargetSkipsTheRemovalAngleProbe)
{
  int skipped = 0;
  for (const char* name : { "bunny00", "elephant" })
  {
    const ThinPatchesAtMildTarget thin(name);
    const auto& pm = thin.Patched;
    SpbmLevelParameters base = thin.Base;
    for (const double share : { 0.55, 0.8 })
    {
      const Index target = thin.Target(share);
      SpbmLevelParameters found[2];
      Index predicted[2] = { 0, 0 };
      int runs[2] = { 0, 0 };
      for (const bool first : { false, true })
      {
        SpbmLevelGenerator generator;
        generator.Initialize(pm->Mesh, pm->Patches);
        base.MildTargetProbesMergeAngleFirst = first;
        found[first] = generator.FindParameters(target, base, &predicted[first]);
        runs[first] = generator.MergingRunCount();
      }
      SCOPED_TRACE(std::string(name) + " " + std::to_string(share));
      EXPECT_EQ(predicted[1], predicted[0]);
      EXPECT_EQ(found[1].Epsilon, found[0].Epsilon);
      EXPECT_EQ(found[1].MergeAngle, found[0].MergeAngle);
      EXPECT_EQ(found[1].RemovalTarget, found[0].RemovalTarget);
      EXPECT_LE(runs[1], runs[0]);
      if (found[0].MergeAngle == base.MergeAngle && found[0].RemovalTarget == 0)
      {
        EXPECT_EQ(runs[1], runs[0] - 1); // the probe at RemovalMergeAngle decided nothing
        skipped += runs[1] < runs[0];
      }
    }
  }
  EXPECT_GT(skipped, 0);
}

// The target count and whether it was reached, from the output's field data.
std::pair<vtkIdType, bool> ReportedTarget(vtkPolyData* output)
{
  vtkDataArray* target = output->GetFieldData()->GetArray("TargetNumberOfTriangles");
  vtkDataArray* reached = output->GetFieldData()->GetArray("TargetReached");
  EXPECT_NE(target, nullptr);
  EXPECT_NE(reached, nullptr);
  return { target ? vtkIdType(target->GetTuple1(0)) : -1, reached && reached->GetTuple1(0) != 0 };
}

TEST(PatchBoundaryMerge, NoisyScanKeepsNonManifoldEdgesBordersAndHandles)
{
  // Like an MRI isosurface: handles, a border, non-manifold edges. The full-resolution chains of
  // the patches around a non-manifold edge share its segments; that is the one input edge, not a
  // duplicate segment to refine, so no patch falls back (before: one generation pass per fallback
  // level until those patches were copied as original triangles).
  // The target (10%) is beyond SPBM's patches here: with the cost-ordered removal off, the
  // relaxation ladder's level; with it (the default), the removal's level is kept when it stops
  // lower than the ladder would (before, the search dropped it for the ladder's). Both without the
  // final collapses, which would take either to the target (FinalCollapsesReachScanTargets).
  for (const unsigned seed : { 1u, 3u })
  {
    SCOPED_TRACE(seed);
    vtkNew<vtkPatchBoundaryMerge> ladder;
    ladder->CostOrderedRemovalOff();
    ladder->FinalCollapsesOff();
    ladder->SetTargetReduction(0.9);
    const MeshStatistics in = slodtest::SimplifyNoisyScan(ladder, 40, seed);
    EXPECT_EQ(ladder->GetOriginalPatches(), 0);
    EXPECT_LT(ladder->GetOutput()->GetNumberOfPolys(), in.Triangles / 2);
    vtkNew<vtkPatchBoundaryMerge> removal;
    removal->FinalCollapsesOff();
    removal->SetTargetReduction(0.9);
    slodtest::SimplifyNoisyScan(removal, 40, seed);
    EXPECT_LT(removal->GetOutput()->GetNumberOfPolys(), ladder->GetOutput()->GetNumberOfPolys());
    EXPECT_FALSE(ReportedTarget(removal->GetOutput()).second);
  }
}

// Every segment of the profile curves (port 1) is an edge of the mesh (port 0).
static void ExpectCurvesOnMeshEdges(vtkPatchBoundaryMerge* filter)
{
  std::set<std::pair<vtkIdType, vtkIdType>> edges;
  vtkPolyData* mesh = filter->GetOutput(0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    mesh->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < 3; ++k)
    {
      const vtkIdType a = ids->GetId(k), b = ids->GetId((k + 1) % 3);
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  }
  vtkPolyData* curves = filter->GetOutput(1);
  vtkIdType segments = 0, offEdges = 0;
  for (vtkIdType c = 0; c < curves->GetNumberOfCells(); ++c)
  {
    curves->GetCellPoints(c, ids);
    for (vtkIdType i = 0; i + 1 < ids->GetNumberOfIds(); ++i)
    {
      const vtkIdType a = ids->GetId(i), b = ids->GetId(i + 1);
      ++segments;
      offEdges += edges.count({ std::min(a, b), std::max(a, b) }) == 0;
    }
  }
  EXPECT_GT(segments, 0);
  EXPECT_EQ(offEdges, 0);
}

// Issue 15: aggressive targets on rough scans (noisy isosurfaces of seeds and resolutions no other
// test uses, a segmentation-mask staircase) are beyond SPBM's patches (each triangle patch blocks
// the removal); the final half-edge collapses reach them within 2% with the default angles, keep
// the input's Euler characteristic, components, border loops and non-manifold edges, output
// original vertices only, keep the profile curves on the mesh's edges and give the same output
// twice. Without them the same targets stay unreached (the old behaviour, reported).
TEST(PatchBoundaryMerge, FinalCollapsesReachScanTargets)
{
  vtkNew<vtkScanSurfaceSource> mask;
  mask->SetKindToSegmentationMask();
  mask->SetResolution(56);
  mask->Update();
  const std::tuple<const char*, vtkSmartPointer<vtkPolyData>, double> cases[] = {
    { "noisy 44 seed 29", slodtest::NoisyScanIsosurface(44, 29), 0.9 },
    { "noisy 52 seed 31", slodtest::NoisyScanIsosurface(52, 31), 0.93 },
    { "mask 56", mask->GetOutput(), 0.99 } };
  for (const auto& [name, input, reduction] : cases)
  {
    SCOPED_TRACE(name);
    vtkNew<vtkPatchBoundaryMerge> off;
    off->FinalCollapsesOff();
    off->SetTargetReduction(reduction);
    off->SetInputData(input);
    off->Update();
    const vtkIdType target = ReportedTarget(off->GetOutput()).first;
    const vtkIdType tolerance = std::max<vtkIdType>(2, target / 50);
    EXPECT_GT(off->GetOutput()->GetNumberOfPolys(), target + tolerance) << "premise: SPBM alone stops above";
    EXPECT_FALSE(ReportedTarget(off->GetOutput()).second);

    vtkNew<vtkPatchBoundaryMerge> on;
    on->SetTargetReduction(reduction);
    on->SetInputData(input);
    on->Update();
    vtkPolyData* out = on->GetOutput();
    EXPECT_GT(on->GetFinalCollapseCount(), 0);
    EXPECT_TRUE(ReportedTarget(out).second);
    EXPECT_LE(std::abs(out->GetNumberOfPolys() - target), tolerance);
    const MeshStatistics in = slodtest::ExpectPreparedInputTopology(input, out);
    EXPECT_EQ(RawStatistics(out).BoundaryLoops, in.BoundaryLoops);
    std::vector<std::array<double, 3>> inputPoints(size_t(input->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
    {
      input->GetPoint(i, inputPoints[size_t(i)].data());
    }
    std::sort(inputPoints.begin(), inputPoints.end());
    vtkIdType foreign = 0;
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      std::array<double, 3> x;
      out->GetPoint(i, x.data());
      foreign += !std::binary_search(inputPoints.begin(), inputPoints.end(), x);
    }
    EXPECT_EQ(foreign, 0) << "output points that are not input points";
    ExpectCurvesOnMeshEdges(on);
    vtkNew<vtkPatchBoundaryMerge> again;
    again->SetTargetReduction(reduction);
    again->SetInputData(input);
    again->Update();
    vtkPolyData* second = again->GetOutput();
    ExpectSameCells(out, second);
  }
}

// Issue 10 (session 24): PatchNoiseTolerance on a noisy scan isosurface. At this resolution a
// voxel is about 1/44 of the volume, so the noise is above the default plane distance (0.004 of
// the diagonal); with a plane distance above it (0.015) the tolerance lets patches grow over the
// noise: at most half the patches of the cones alone (the old growth), and the level still
// reaches the target, keeps the input's topology (Euler characteristic, components, non-manifold
// edges, border loops) and its profile curves on the mesh's edges.
TEST(PatchBoundaryMerge, NoiseToleranceOnAScanHalvesThePatchesAndKeepsTheTopology)
{
  vtkNew<vtkPatchBoundaryMerge> cones;
  cones->SetPatchPlaneDistance(0.015);
  cones->SetPatchNoiseTolerance(0.0); // the default follows the target (session 28): on at 10%
  cones->SetTargetReduction(0.9);
  slodtest::SimplifyNoisyScan(cones, 44, 37);
  vtkNew<vtkPatchBoundaryMerge> tolerant;
  tolerant->SetPatchPlaneDistance(0.015);
  tolerant->SetPatchNoiseTolerance(1.0);
  tolerant->SetTargetReduction(0.9);
  const MeshStatistics in = slodtest::SimplifyNoisyScan(tolerant, 44, 37);
  EXPECT_LE(2 * tolerant->GetNumberOfPatches(), cones->GetNumberOfPatches());
  EXPECT_TRUE(ReportedTarget(tolerant->GetOutput()).second);
  EXPECT_EQ(RawStatistics(tolerant->GetOutput()).BoundaryLoops, in.BoundaryLoops);
  ExpectCurvesOnMeshEdges(tolerant);
}

// Issue 10 (session 28): the default PatchNoiseTolerance (-1) follows the target: 1 when the target
// keeps less than a fifth of the input (the patches of a scan grow over its noise, and the level's
// merging runs, replays and fallback passes go over far fewer of them), 0 at milder targets (the
// former growth, better there). On a noisy scan (a seed no other test uses, the plane distance
// above its noise): at 10% the default grows the patches of 1, at most half of those of 0, and the
// level keeps the input's topology (Euler characteristic, components, non-manifold edges, border
// loops) and reaches the target; at 40% the default's level is 0's, cell for cell.
TEST(PatchBoundaryMerge, NoiseToleranceFollowsTheTarget)
{
  auto simplify = [](double reduction, double tolerance, vtkPatchBoundaryMerge* filter) {
    filter->SetPatchPlaneDistance(0.015);
    // The patches counted are the target's (a kept finer level's would be 1.5x the target's).
    filter->CollapseFinerLevelForTargetOff();
    if (tolerance >= 0)
    {
      filter->SetPatchNoiseTolerance(tolerance);
    }
    filter->SetTargetReduction(reduction);
    return slodtest::SimplifyNoisyScan(filter, 42, 59);
  };
  vtkNew<vtkPatchBoundaryMerge> automatic, off, on;
  EXPECT_DOUBLE_EQ(automatic->GetPatchNoiseTolerance(), -1.0);
  simplify(0.9, -1, automatic);
  simplify(0.9, 0, off);
  simplify(0.9, 1, on);
  EXPECT_EQ(automatic->GetNumberOfPatches(), on->GetNumberOfPatches());
  EXPECT_LE(2 * automatic->GetNumberOfPatches(), off->GetNumberOfPatches());
  EXPECT_TRUE(ReportedTarget(automatic->GetOutput()).second);
  vtkNew<vtkPatchBoundaryMerge> mild, mildOff;
  simplify(0.6, -1, mild);
  simplify(0.6, 0, mildOff);
  EXPECT_EQ(mild->GetNumberOfPatches(), mildOff->GetNumberOfPatches());
  ASSERT_EQ(mild->GetOutput()->GetNumberOfPoints(), mildOff->GetOutput()->GetNumberOfPoints());
  ExpectSameCells(mild->GetOutput(), mildOff->GetOutput());
}

// Below what any topology-keeping half-edge collapse reaches (a noisy scan at 1%: hundreds of
// handles), the level stops where every collapse left breaks the link condition or folds a
// triangle, says so (TargetReached 0, a warning), and still has the input's topology.
TEST(PatchBoundaryMerge, FinalCollapsesStopAtTheTopologysFloor)
{
  const vtkSmartPointer<vtkPolyData> input = slodtest::NoisyScanIsosurface(52, 31);
  vtkNew<vtkPatchBoundaryMerge> off;
  off->FinalCollapsesOff();
  off->SetTargetReduction(0.99);
  off->SetInputData(input);
  off->Update();
  vtkNew<vtkPatchBoundaryMerge> on;
  on->SetTargetReduction(0.99);
  on->SetInputData(input);
  vtkNew<slodtest::MessageCounter> messages;
  on->AddObserver(vtkCommand::WarningEvent, messages);
  on->Update();
  vtkPolyData* out = on->GetOutput();
  const auto [target, reached] = ReportedTarget(out);
  EXPECT_FALSE(reached);
  EXPECT_GT(out->GetNumberOfPolys(), target + std::max<vtkIdType>(2, target / 50));
  EXPECT_LT(out->GetNumberOfPolys(), off->GetOutput()->GetNumberOfPolys() / 2);
  bool explained = false;
  for (const std::string& warning : messages->Warnings)
  {
    explained = explained || warning.find("would change the topology") != std::string::npos;
  }
  EXPECT_TRUE(explained);
  const MeshStatistics in = slodtest::ExpectPreparedInputTopology(input, out);
  EXPECT_EQ(RawStatistics(out).BoundaryLoops, in.BoundaryLoops);
}

// Issue 15, session 39: the final collapses (after RefineDeviatingRegions' pass, among others)
// are set up over the level's own vertices, not over the input's: a level that uses a part of a
// large input (here bunny00's surface after a second, unused copy of its points and triangles)
// is collapsed over its vertices only, and exactly as over an input of its own surface alone
// (the same triangles, counts and topology after the ids are shifted back).
TEST(SpbmFinalCollapses, WorkOverTheLevelsVerticesOnly)
{
  const TriangleMesh surface = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("bunny00"));
  const Index n = surface.NumberOfPoints();
  TriangleMesh padded; // an unused copy (moved away) first, then the surface
  padded.Points = surface.Points;
  for (size_t i = 0; i < padded.Points.size(); i += 3)
  {
    padded.Points[i] += 10.0 * surface.BoundingBoxDiagonal();
  }
  padded.Points.insert(padded.Points.end(), surface.Points.begin(), surface.Points.end());
  padded.Triangles = surface.Triangles;
  for (const Index v : surface.Triangles)
  {
    padded.Triangles.push_back(v + n);
  }
  SpbmLevel alone, shifted;
  alone.Triangles = surface.Triangles;
  alone.TrianglePatch.assign(size_t(surface.NumberOfTriangles()), 0);
  alone.NumberOfPatches = 1;
  alone.CurveOffsets.assign(1, 0);
  shifted = alone;
  for (Index& v : shifted.Triangles)
  {
    v += n;
  }
  const Index target = surface.NumberOfTriangles() / 4;
  SpbmFinalCollapseStatistics aloneStatistics, shiftedStatistics;
  SpbmFinalCollapses(surface, target, alone, aloneStatistics);
  SpbmFinalCollapses(padded, target, shifted, shiftedStatistics);
  EXPECT_EQ(shiftedStatistics.Vertices, n);
  EXPECT_EQ(aloneStatistics.Vertices, n);
  EXPECT_TRUE(shiftedStatistics.Reached);
  EXPECT_LE(Index(shifted.TrianglePatch.size()), target + SpbmFinalCollapseTolerance(target));
  EXPECT_GT(shiftedStatistics.Collapses, 0);
  EXPECT_EQ(shiftedStatistics.Collapses, aloneStatistics.Collapses);
  EXPECT_EQ(shiftedStatistics.Attempts, aloneStatistics.Attempts);
  ASSERT_EQ(shifted.Triangles.size(), alone.Triangles.size());
  for (size_t i = 0; i < alone.Triangles.size(); ++i)
  {
    ASSERT_EQ(shifted.Triangles[i], alone.Triangles[i] + n) << "corner " << i;
  }
  // The collapsed level keeps the surface's topology (Euler characteristic, borders, manifold).
  TriangleMesh collapsed;
  collapsed.Points = surface.Points;
  collapsed.Triangles = alone.Triangles;
  const MeshStatistics before = ComputeMeshStatistics(surface), after = ComputeMeshStatistics(collapsed);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
  EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
  EXPECT_EQ(after.Triangles, Index(alone.TrianglePatch.size()));
}

// Issue 15: mild targets (half of bunny00, which gave a quarter; half of the cow and a tenth of a
// smooth isosurface, meshes no other test tunes for) are reached within the documented tolerance
// (2%, at least 2 triangles) with the default angles: the patches follow the target. The output
// keeps the input's topology and is reported as reaching the target.
TEST(PatchBoundaryMerge, MildTargetsAreReachedWithinTwoPercent)
{
  const std::tuple<const char*, vtkSmartPointer<vtkPolyData>, double> cases[] = {
    { "bunny00", slodtest::LoadTestMesh("bunny00"), 0.5 }, { "cow", slodtest::LoadTestMesh("cow"), 0.5 },
    { "isosurface", slodtest::SyntheticIsosurface(90), 0.9 } };
  for (const auto& [name, input, reduction] : cases)
  {
    SCOPED_TRACE(name);
    const MeshStatistics in = StatisticsOf(input);
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(input);
    filter->SetTargetReduction(reduction);
    filter->Update();
    vtkPolyData* out = filter->GetOutput();
    const vtkIdType target = std::llround((1 - reduction) * double(in.Triangles));
    const auto [reported, reached] = ReportedTarget(out);
    EXPECT_EQ(reported, target);
    EXPECT_TRUE(reached);
    EXPECT_LE(std::abs(out->GetNumberOfPolys() - target), std::max<vtkIdType>(2, target / 50));
    const MeshStatistics st = RawStatistics(out);
    EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops);
    EXPECT_EQ(st.NonManifoldEdges, 0);
    EXPECT_EQ(st.DegenerateTriangles, 0);
  }
}

// Without adapting the patches, the same bunny00 target is beyond the finest level: said in the
// field data, not hidden; the adapted filter's later, coarser level reuses its patches.
TEST(PatchBoundaryMerge, UnreachedTargetIsReported)
{
  auto input = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->AdaptPatchesToTargetOff();
  filter->SetPatchDeviationFactor(0); // the patches of the angles alone (the bound makes them finer)
  filter->SetInputData(input);
  filter->SetTargetReduction(0.5);
  filter->Update();
  const auto [target, reached] = ReportedTarget(filter->GetOutput());
  EXPECT_FALSE(reached);
  EXPECT_LT(filter->GetOutput()->GetNumberOfPolys(), target * 49 / 50);
  EXPECT_EQ(filter->GetPatchToleranceScale(), 1.0);
  filter->AdaptPatchesToTargetOn();
  filter->Update();
  EXPECT_TRUE(ReportedTarget(filter->GetOutput()).second);
  const double scale = filter->GetPatchToleranceScale();
  filter->SetTargetReduction(0.9);
  filter->Update();
  EXPECT_TRUE(filter->GetPatchificationReused());
  EXPECT_EQ(filter->GetPatchToleranceScale(), scale);
  EXPECT_TRUE(ReportedTarget(filter->GetOutput()).second);
}

TEST(PatchBoundaryMerge, InvalidAndEmptyInputs)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

  auto bad = slodtest::ToPolyData(slodtest::Tetrahedron());
  bad->GetPoints()->SetPoint(0, std::nan(""), 0, 0);
  filter->SetInputData(bad);
  filter->SetGlobalWarningDisplay(0);
  filter->Update();
  filter->SetGlobalWarningDisplay(1);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

  // A tetrahedron is already minimal: it stays a closed genus-0 surface.
  auto tet = slodtest::ToPolyData(slodtest::Tetrahedron());
  auto out = RunFilter(tet, 2);
  const MeshStatistics st = RawStatistics(out);
  EXPECT_EQ(st.BoundaryEdges, 0);
  EXPECT_EQ(st.Genus, 0);
}

// Quality at equal triangle count against the VTK peers, measured in the same run.
TEST(PatchBoundaryMerge, FandiskSharpProfilesSurviveVersusPeers)
{
  auto input = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkPatchBoundaryMerge> filter;
  for (const vtkIdType target : { 460, 266, 150 })
  {
    auto ours = RunFilter(input, target, filter);
    const vtkIdType count = ours->GetNumberOfCells();
    const double reduction = 1.0 - double(count) / double(input->GetNumberOfCells());
    vtkNew<vtkQuadricDecimation> quadric;
    quadric->SetInputData(input);
    quadric->SetTargetReduction(reduction);
    quadric->Update();
    // vtkDecimatePro at EQUAL count: with PreserveTopology when it reaches the count (within two
    // triangles), else with the setting that does (PreserveTopologyOff + SplittingOn; at 150
    // triangles PreserveTopology stops at 242).
    vtkNew<vtkDecimatePro> pro;
    pro->SetInputData(input);
    pro->SetTargetReduction(reduction);
    pro->PreserveTopologyOn();
    pro->Update();
    std::string proSetting = "PreserveTopologyOn";
    if (pro->GetOutput()->GetNumberOfCells() > count + 2)
    {
      pro->PreserveTopologyOff();
      pro->SplittingOn();
      pro->Update();
      proSetting = "PreserveTopologyOff+SplittingOn";
    }
    ASSERT_LE(pro->GetOutput()->GetNumberOfCells(), count + 2) << "vtkDecimatePro (" << proSetting << ") at " << target;
    auto measure = [&](vtkPolyData* simplified) {
      vtkNew<vtkSurfaceDeviation> deviation;
      deviation->SetReferenceData(input);
      deviation->SetComparedData(simplified);
      deviation->SetNumberOfSamples(100000);
      deviation->Update();
      return std::make_pair(deviation->GetHausdorffRelative(), deviation->GetMeanRelative());
    };
    const auto q = measure(quadric->GetOutput());
    const auto d = measure(pro->GetOutput());
    const auto o = measure(ours);
    // Goal (issue 5): the sharp profiles survive, i.e. the Hausdorff distance is no worse than
    // vtkDecimatePro's at the same count. 460 and 266: chain deviations measured along the patch
    // normals (ChainInPlaneWeight) and non-planar patches triangulated with the diagonals closest
    // to the original surface. 150 (beyond what merging within alpha1 = 90 reaches): cost-ordered
    // endpoint removal and the candidate merge measures compared at the target.
    EXPECT_LE(o.first, d.first) << "target " << target << ": SPBM Hausdorff " << o.first << " vs vtkDecimatePro "
                                << d.first << " (" << proSetting << ", " << pro->GetOutput()->GetNumberOfCells()
                                << " triangles)";
    ::testing::Test::RecordProperty("fandisk" + std::to_string(target) + "_decimatepro_setting", proSetting);
    const std::string key = "fandisk" + std::to_string(target);
    ::testing::Test::RecordProperty(key + "_triangles", std::to_string(count));
    ::testing::Test::RecordProperty(key + "_hausdorff_spbm", std::to_string(o.first));
    ::testing::Test::RecordProperty(key + "_hausdorff_quadric", std::to_string(q.first));
    ::testing::Test::RecordProperty(key + "_hausdorff_decimatepro", std::to_string(d.first));
    ::testing::Test::RecordProperty(key + "_hausdorff_ratio_to_quadric", std::to_string(q.first > 0 ? o.first / q.first : 0.0));
    ::testing::Test::RecordProperty(key + "_mean_spbm", std::to_string(o.second));
    ::testing::Test::RecordProperty(key + "_mean_quadric", std::to_string(q.second));
    std::cout << "[quality] fandisk " << count << " tris: Hausdorff SPBM " << o.first << ", quadric " << q.first
              << ", decimatepro " << d.first << " (" << proSetting << ", " << pro->GetOutput()->GetNumberOfCells()
              << " tris); mean SPBM " << o.second << ", quadric " << q.second << ", decimatepro " << d.second << "\n";
  }
}

namespace
{
// The level of `input` at `reduction` within 2% of its target and with the input's topology, and
// its Hausdorff distance over vtkQuadricDecimation's at the same count, measured in the same run.
// `thicknessScale` and `noiseWithheld`, when given, get the filter's PatchThicknessScale and
// NoiseToleranceWithheld.
double LevelHausdorffRatioToQuadric(const char* name, vtkPolyData* input, double reduction,
  double* thicknessScale = nullptr, bool* noiseWithheld = nullptr,
  const std::function<void(vtkPatchBoundaryMerge*)>& configure = nullptr)
{
  const MeshStatistics in = StatisticsOf(input);
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(input);
  filter->SetTargetReduction(reduction);
  if (configure)
  {
    configure(filter);
  }
  filter->Update();
  vtkPolyData* ours = filter->GetOutput();
  EXPECT_GT(filter->GetPatchThicknessBound(), 0.0);
  if (thicknessScale)
  {
    *thicknessScale = filter->GetPatchThicknessScale();
  }
  if (noiseWithheld)
  {
    *noiseWithheld = filter->GetNoiseToleranceWithheld();
  }
  const auto [target, reached] = ReportedTarget(ours);
  EXPECT_TRUE(reached);
  EXPECT_LE(std::abs(ours->GetNumberOfPolys() - target), std::max<vtkIdType>(2, target / 50));
  const MeshStatistics st = RawStatistics(ours);
  EXPECT_EQ(st.EulerCharacteristic, in.EulerCharacteristic);
  EXPECT_EQ(st.BoundaryLoops, in.BoundaryLoops);
  EXPECT_EQ(st.NonManifoldEdges, 0);
  vtkNew<vtkQuadricDecimation> quadric;
  quadric->SetInputData(input);
  quadric->SetTargetReduction(1.0 - double(ours->GetNumberOfPolys()) / double(input->GetNumberOfPolys()));
  quadric->Update();
  auto hausdorff = [&](vtkPolyData* simplified) {
    vtkNew<vtkSurfaceDeviation> deviation;
    deviation->SetReferenceData(input);
    deviation->SetComparedData(simplified);
    deviation->SetNumberOfSamples(100000);
    deviation->Update();
    return deviation->GetHausdorffRelative();
  };
  const double q = hausdorff(quadric->GetOutput()), o = hausdorff(ours);
  std::cout << "[quality] " << name << " " << ours->GetNumberOfPolys() << " tris: Hausdorff SPBM " << o << ", quadric "
            << q << " (" << quadric->GetOutput()->GetNumberOfPolys() << " tris), ratio " << o / q << "\n";
  return o / q;
}
} // namespace

// Issue 15: on smooth surfaces at 10%, SPBM's Hausdorff distance within 3x vtkQuadricDecimation's
// at the same count, measured in the same run (the patch thickness bound, PatchDeviationFactor:
// without it the patches are as large as the angles allow and bunny00 is 5x, the synthetic
// isosurface 10x), with the input's topology.
TEST(PatchBoundaryMerge, SmoothSurfacesWithinThreeTimesQuadricHausdorff)
{
  const std::pair<const char*, vtkSmartPointer<vtkPolyData>> cases[] = { { "bunny00",
                                                                          slodtest::LoadTestMesh("bunny00") },
    { "isosurface", slodtest::SyntheticIsosurface(120) } };
  for (const auto& [name, input] : cases)
  {
    SCOPED_TRACE(name);
    EXPECT_LE(LevelHausdorffRatioToQuadric(name, input, 0.9), 3.0);
  }
}

// Issue 15 (session 25): the Fandisk (CAD: creases, cylinders) at 10% within 3x
// vtkQuadricDecimation's Hausdorff distance at the same count (11.3x before: its creases counted
// as curvature made the thickness bound 5x too loose, and its cylinders were grids of tiny patches,
// RulingAngle). The issue's goal for CAD meshes, 2x, is not reached.
TEST(PatchBoundaryMerge, FandiskWithinThreeTimesQuadricHausdorff)
{
  EXPECT_LE(LevelHausdorffRatioToQuadric("fandisk", slodtest::LoadTestMesh("fandisk"), 0.9), 3.0);
}

// Issue 15 (session 28): SpbmLevelParameters::ReachBandAcrossKeyJumps. At half of these inputs one
// kept chain vertex more takes the count at alpha1 20 from below the 2% band to above the target
// (the vertex blocks a cascade of merges, joins and collapses), so no epsilon alone reaches the
// band: the search takes the count above when it is within the band, or searches alpha1 at the
// two epsilons. Each level is within the band with the input's topology (LevelHausdorffRatioToQuadric),
// and its Hausdorff distance within the issue's bound of vtkQuadricDecimation's at the same
// count: 2x on the CAD part (couplingdown), 3x on the smooth ones.
TEST(PatchBoundaryMerge, CountJumpsOverTheBandAreReachedThroughAlpha1)
{
  const std::pair<const char*, double> cases[] = { { "couplingdown", 2.0 }, { "elephant", 3.0 }, { "cactus", 3.0 } };
  for (const auto& [name, bound] : cases)
  {
    SCOPED_TRACE(name);
    EXPECT_LE(LevelHausdorffRatioToQuadric(name, slodtest::LoadTestMesh(name), 0.5), bound);
  }
}

// Issue 15 (session 29): LoosenThicknessForTarget. On these smooth inputs at 50% the thickness
// bound made the patches so small that their corners took nearly the whole budget: the search kept
// 3 of poly2x^2+y^2's 274 chain keys, its epsilon (33x the bound) was the error, 95x
// vtkQuadricDecimation's Hausdorff distance (blobby_3cc 5.8x). The level is made again with the
// bound doubled and the closer one kept: within the band with the input's topology, and within 3x
// vtkQuadricDecimation's distance at the same count (measured in the same run) on blobby_3cc, 10x
// on poly2x^2+y^2. Where the level is within the bound (bunny00 at 10%) the patches stay as given.
// Session 31: poly2x^2+y^2's border corners now stay (BorderCornerAngle) and its level is within
// the bound without a second growth (2.6x); it is measured with the paper's chains (angle 0),
// where the bound is still what saves it. Session 35: bunny00 at 10% is not a scan for the finer
// level's trigger any more and is redone from a finer level (scale 2/3): the bound is not loosened.
TEST(PatchBoundaryMerge, TooSmallPatchesAreGrownAgainWithALooserThicknessBound)
{
  const std::tuple<const char*, double, double> cases[] = { { "poly2x^2+y^2-0.062500", 10.0, 0.0 },
    { "blobby_3cc", 3.0, 60.0 } };
  for (const auto& [name, bound, cornerAngle] : cases)
  {
    SCOPED_TRACE(name);
    double scale = 0;
    const double angle = cornerAngle;
    EXPECT_LE(LevelHausdorffRatioToQuadric(name, slodtest::LoadTestMesh(name), 0.5, &scale, nullptr,
                [angle](vtkPatchBoundaryMerge* filter) { filter->SetBorderCornerAngle(angle); }),
      bound);
    EXPECT_GT(scale, 1.0);
  }
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(slodtest::LoadTestMesh("bunny00"));
  filter->SetTargetReduction(0.9);
  filter->Update();
  EXPECT_LE(filter->GetPatchThicknessScale(), 1.0);
}

// Issue 15 (session 30): LoosenThicknessForTarget's first try at a coarse target. The automatic
// PatchNoiseTolerance (on below a fifth kept, for scan isosurfaces) let triangles join patches by
// their distance alone; on this smooth model at 10% the patches it grew took the budget with their
// corners and failed triangulations (Hausdorff 8x vtkQuadricDecimation's). The level is made
// again without it and the closer one kept: within 3x vtkQuadricDecimation's distance at the same
// count (measured in the same run), within the band, with the input's topology. On a scan
// (bunny00 at 10%) the level is within the thickness bound and the noise tolerance stays.
TEST(PatchBoundaryMerge, CoarseTargetsRetryWithoutTheNoiseToleranceOnSmoothModels)
{
  bool withheld = false;
  EXPECT_LE(LevelHausdorffRatioToQuadric(
              "mannequin-devil", slodtest::LoadTestMesh("mannequin-devil"), 0.9, nullptr, &withheld),
    3.0);
  EXPECT_TRUE(withheld);
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(slodtest::LoadTestMesh("bunny00"));
  filter->SetTargetReduction(0.9);
  filter->Update();
  EXPECT_FALSE(filter->GetNoiseToleranceWithheld());
}

// Issue 15 (session 33): CollapseFinerLevelForTarget. On these small smooth models at mild targets
// the patches grown for the target are too coarse for the surface: their corners take the budget
// and their flat re-triangulation sets the error (about 4x vtkQuadricDecimation's Hausdorff
// distance at the same count on base-s33; the CAD model boeing at 10%, grown with the automatic
// noise tolerance, 6.5x), whatever the search chooses. A level of 1.5x the target
// from patches grown for that count, brought down to the target by the final collapses, is kept
// when it is closer: within 3x vtkQuadricDecimation's distance (measured in the same run), within
// the band, with the input's topology, closer than the level with the option off, and its
// collapses are counted.
TEST(PatchBoundaryMerge, CoarsePatchLevelsAreRedoneFromAFinerLevelByCollapses)
{
  const std::pair<const char*, double> cases[] = { { "nefertiti", 0.5 }, { "horizons", 0.7 }, { "boeing", 0.9 } };
  for (const auto& [name, reduction] : cases)
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const double ratio = LevelHausdorffRatioToQuadric(name, input, reduction);
    EXPECT_LE(ratio, 3.0);
    const double withoutRatio = LevelHausdorffRatioToQuadric(name, input, reduction, nullptr, nullptr,
      [](vtkPatchBoundaryMerge* filter) {
        // The level itself: the refined regions (session 37; at mild targets by default since
        // session 45) would redo it without the option too.
        filter->CollapseFinerLevelForTargetOff();
        filter->RefineDeviatingRegionsOff();
        filter->SetMildTargetRegionAllowance(0);
      });
    EXPECT_LT(ratio, withoutRatio);
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(input);
    filter->SetTargetReduction(reduction);
    filter->Update();
    EXPECT_GT(filter->GetFinalCollapseCount(), 0);
  }
}

// Issue 15 (session 35): every target below a fifth of the input grows its patches with the
// automatic noise tolerance, and such patches took the scans' trigger for the finer level (1.5x
// the thickness bound instead of 0.5x), so smooth meshes at 10% were never redone from a finer
// level: horizons 3.08x and itemb 3.63x vtkQuadricDecimation's Hausdorff distance at the same
// count on base-s35 (this test's 100,000 samples). The tolerance admits next to none of their triangles, so they are not scans
// now: within the issue's 3x for smooth meshes, measured in the same run, and closer than without
// the finer level.
TEST(PatchBoundaryMerge, SmoothMeshesAtCoarseTargetsAreNotTakenForScans)
{
  for (const char* name : { "horizons", "itemb" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const double ratio = LevelHausdorffRatioToQuadric(name, input, 0.9);
    EXPECT_LE(ratio, 3.0);
    const double withoutRatio = LevelHausdorffRatioToQuadric(name, input, 0.9, nullptr, nullptr,
      [](vtkPatchBoundaryMerge* filter) { filter->CollapseFinerLevelForTargetOff(); });
    EXPECT_LT(ratio, withoutRatio);
  }
}

// Issue 15 (session 36): the finer level runs where the level misses what its patches were grown
// for (deviating more than they were allowed to lie from their planes), not by the kind of
// surface. Base-s36 took every level whose patches the noise tolerance had grown over less than a
// quarter of the input for a smooth mesh's and redid it from a finer level once it deviated half
// the thickness bound: a segmentation mask's staircase and an open height-field scan at 10% (no
// other test's resolutions) within the issue's 3x of vtkQuadricDecimation already, at several
// times the time. Their levels, measured below the trigger, are now the levels without the finer
// level (same count, same collapses: the finer level is not made), within 3x vtkQuadricDecimation,
// measured in the same run; horizons at 10%, beyond its bound, still takes it and comes within 3x.
TEST(PatchBoundaryMerge, FinerLevelOnlyWhereTheLevelDeviatesBeyondItsPatches)
{
  const std::pair<const char*, int> scans[] = { { "mask", 236 }, { "openscan", 64 } };
  for (const auto& [kind, resolution] : scans)
  {
    SCOPED_TRACE(kind);
    vtkNew<vtkScanSurfaceSource> source;
    source->SetKind(std::string(kind) == "mask" ? vtkScanSurfaceSource::SegmentationMask : vtkScanSurfaceSource::OpenScan);
    source->SetResolution(resolution);
    source->Update();
    vtkPolyData* input = source->GetOutput();
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(input);
    filter->SetTargetReduction(0.9);
    filter->Update();
    vtkNew<vtkPatchBoundaryMerge> without;
    without->SetInputData(input);
    without->SetTargetReduction(0.9);
    without->CollapseFinerLevelForTargetOff();
    without->Update();
    EXPECT_FALSE(filter->GetFinerLevelTried());
    EXPECT_GT(filter->GetLevelDeviationShare(), 0.0);
    EXPECT_LT(filter->GetLevelDeviationShare(), 1.0);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPolys(), without->GetOutput()->GetNumberOfPolys());
    EXPECT_EQ(filter->GetFinalCollapseCount(), without->GetFinalCollapseCount());
    EXPECT_LE(LevelHausdorffRatioToQuadric(kind, input, 0.9), 3.0);
  }
  vtkSmartPointer<vtkPolyData> horizons = slodtest::LoadTestMesh("horizons");
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(horizons);
  filter->SetTargetReduction(0.9);
  filter->Update();
  EXPECT_TRUE(filter->GetFinerLevelTried());
  EXPECT_GT(filter->GetLevelDeviationShare(), 1.0);
  EXPECT_LE(LevelHausdorffRatioToQuadric("horizons", horizons, 0.9), 3.0);
}

// Issue 10 (session 38): the finer level's trigger decides by the surface, not by how densely it
// is sampled. The same noisy scan (the default seed) at two resolutions, 4x the triangles apart, to
// 10%: the level's vertex distances follow the same distribution, but the largest of them grows
// with the number of vertices (a few extreme noise samples), and the whole-level finer level must
// not be made at one density and not at the other; on the scan's noise it is not made at all.
TEST(PatchBoundaryMerge, FinerLevelTriggerDoesNotFollowTheSamplingDensity)
{
  bool tried[2] = { true, true };
  const int resolutions[2] = { 68, 137 };
  for (int i = 0; i < 2; ++i)
  {
    SCOPED_TRACE(resolutions[i]);
    vtkNew<vtkScanSurfaceSource> source;
    source->SetKindToNoisyIsosurface();
    source->SetResolution(resolutions[i]);
    source->Update();
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(source->GetOutput());
    filter->SetTargetReduction(0.9);
    filter->Update();
    tried[i] = filter->GetFinerLevelTried();
    const vtkIdType target = source->GetOutput()->GetNumberOfPolys() / 10;
    EXPECT_LE(std::abs(filter->GetOutput()->GetNumberOfPolys() - target), target / 50 + 2);
  }
  EXPECT_EQ(tried[0], tried[1]);
  EXPECT_FALSE(tried[0]);
  EXPECT_FALSE(tried[1]);
}

// Session 42 (issue 10): the level's fallback passes go on while a failed patch can still change
// (a fixed point), and the failures shrink about fourfold per pass from a number proportional to
// the input, so the tail of a handful of patches cost the noisy 4M scan two more whole-level passes
// than the 1M one. With LateFailureShare (default 1/10,000 of the input patches) a pass with that
// few failures sends them to their original triangles at once instead of unmerging them first. On
// a noisy scan no other test uses (seed 3, 251k triangles) to 10%: the level needs fewer passes
// than with the share at 0 (one fallback level per pass, base-s42's rule), late patches went
// straight to original, and both outputs reach the target with the same topology.
TEST(PatchBoundaryMerge, LateFallbackFailuresGoStraightToOriginal)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKindToNoisyIsosurface();
  source->SetResolution(137);
  source->SetSeed(3);
  source->Update();
  const vtkIdType target = source->GetOutput()->GetNumberOfPolys() / 10;
  int passes[2] = { 0, 0 };
  vtkIdType late[2] = { 0, 0 };
  MeshStatistics st[2];
  for (const int rule : { 0, 1 })
  {
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(source->GetOutput());
    filter->SetTargetReduction(0.9);
    if (!rule)
    {
      filter->SetLateFailureShare(0.0);
    }
    filter->Update();
    passes[rule] = filter->GetGenerationPasses();
    late[rule] = filter->GetLateOriginalPatches();
    st[rule] = ComputeMeshStatistics(slodtest::ToTriangleMesh(filter->GetOutput()));
    EXPECT_LE(std::abs(filter->GetOutput()->GetNumberOfPolys() - target), target / 50 + 2) << "rule " << rule;
  }
  EXPECT_GT(passes[0], 2) << "the scan must need fallback passes";
  EXPECT_LT(passes[1], passes[0]);
  EXPECT_EQ(late[0], 0);
  EXPECT_GT(late[1], 0);
  EXPECT_EQ(st[1].EulerCharacteristic, st[0].EulerCharacteristic);
  EXPECT_EQ(st[1].BoundaryLoops, st[0].BoundaryLoops);
  EXPECT_LE(st[1].NonManifoldEdges, st[0].NonManifoldEdges);
}

// Session 43 (issue 10): the late replays of a level (after its first, with patches at finer
// fallback levels, so that the refinement of the non-simple patches is made from scratch) test only
// the boundaries they have not seen (RememberBoundaryOutcomes). The noisy scan at resolution 137,
// seed 5 (251k triangles; no other test uses it) to 10%: it needs such replays, and the boundaries
// they test stay within the root patches that had changed when each began (plus a few per replay)
// (base-s43 tested every boundary that is not simple, and those around them, in each: tens of
// times more); on target with the input's Euler characteristic and border loops.
TEST(PatchBoundaryMerge, LateReplaysTestOnlyTheBoundariesThatChanged)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKindToNoisyIsosurface();
  source->SetResolution(137);
  source->SetSeed(5);
  source->Update();
  const vtkIdType target = source->GetOutput()->GetNumberOfPolys() / 10;
  vtkNew<vtkPatchBoundaryMerge> filter;
  filter->SetInputData(source->GetOutput());
  filter->SetTargetReduction(0.9);
  filter->Update();
  const int replays = filter->GetLateReplays();
  const vtkIdType changed = filter->GetLateReplayChangedPatches();
  const vtkIdType tested = filter->GetLateReplayBoundaryTests();
  std::cout << replays << " late replays, " << changed << " patches changed, " << tested << " boundaries tested\n";
  ASSERT_GT(replays, 0) << "the scan must need late replays";
  EXPECT_LE(tested, changed + 8 * replays);
  EXPECT_LE(std::abs(filter->GetOutput()->GetNumberOfPolys() - target), target / 50 + 2);
  const MeshStatistics in = ComputeMeshStatistics(slodtest::ToTriangleMesh(source->GetOutput()));
  const MeshStatistics out = ComputeMeshStatistics(slodtest::ToTriangleMesh(filter->GetOutput()));
  EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
  EXPECT_EQ(out.BoundaryLoops, in.BoundaryLoops);
}

// Issue 15 (session 37): RefineDeviatingRegions. A flat square with one Gaussian bump in a corner
// at 10%: the whole level deviates less than its patches' allowance with the coarse target's noise
// tolerance (the finer level of CollapseFinerLevelForTarget is not made), but the bump's vertices
// lie beyond half the thickness bound, the cap its patches were grown with. Only patches on the
// bump are kept as their original triangles and collapsed again (the output's field-data count; the
// flat part keeps no more vertices than without),
// and the level's largest vertex distance, measured here, falls under that cap; without the
// refinement it stays above. Same count band and topology as the input.
double LargestVertexDistance(vtkPolyData* input, vtkPolyData* output)
{
  const TriangleMesh simplified = slodtest::ToTriangleMesh(output);
  const TriangleBVH tree(simplified);
  double worst2 = 0;
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double x[3];
    input->GetPoint(i, x);
    worst2 = std::max(worst2, tree.ClosestPoint({ x[0], x[1], x[2] }).Distance2);
  }
  return std::sqrt(worst2);
}

TEST(PatchBoundaryMerge, OnlyTheRegionsThatDeviateAreRefined)
{
  const double centre = 0.75, sigma = 0.08, height = 0.1;
  TriangleMesh mesh = slodtest::Grid(60, 60);
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    const double dx = mesh.Points[3 * size_t(v)] - centre, dy = mesh.Points[3 * size_t(v) + 1] - centre;
    mesh.Points[3 * size_t(v) + 2] = height * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
  }
  vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(mesh);
  const double diagonal = mesh.BoundingBoxDiagonal();
  vtkIdType refined[2] = { 0, 0 };
  double distance[2] = { 0, 0 };
  vtkIdType flatVertices[2] = { 0, 0 }; // output vertices off the bump (beyond 3 sigma)
  for (const bool refine : { true, false })
  {
    SCOPED_TRACE(refine ? "RefineDeviatingRegions on" : "off");
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(input);
    filter->SetTargetReduction(0.9);
    filter->SetRefineDeviatingRegions(refine);
    filter->GeneratePatchColoredInputOn();
    filter->Update();
    vtkPolyData* output = filter->GetOutput();
    EXPECT_FALSE(filter->GetFinerLevelTried());
    EXPECT_GT(filter->GetLevelDeviationShare(), 0.0);
    EXPECT_LT(filter->GetLevelDeviationShare(), 1.0);
    const vtkIdType target = mesh.NumberOfTriangles() / 10;
    EXPECT_LE(std::abs(output->GetNumberOfPolys() - target), std::max<vtkIdType>(2, target / 50));
    slodtest::ExpectSameTopology(mesh, slodtest::ToTriangleMesh(output));
    vtkDataArray* count = output->GetFieldData()->GetArray("RegionRefinedPatches");
    refined[refine] = count ? static_cast<vtkIdType>(count->GetTuple1(0)) : 0;
    EXPECT_EQ(refined[refine], filter->GetRegionRefinedPatches());
    distance[refine] = LargestVertexDistance(input, output) / diagonal;
    for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
    {
      double x[3];
      output->GetPoint(i, x);
      flatVertices[refine] += std::hypot(x[0] - centre, x[1] - centre) >= 3 * sigma ? 1 : 0;
    }
    // The cap the patches were grown with (PatchThicknessBound: relative, the bound as given here).
    EXPECT_EQ(filter->GetPatchThicknessScale(), 1.0);
    const double cap = 0.5 * filter->GetPatchThicknessBound();
    if (refine)
    {
      EXPECT_LE(distance[refine], cap);
      // The refined patches are on the bump (within 3 sigma of its centre) and a minority of them.
      vtkPolyData* patched = filter->GetOutput(2);
      vtkDataArray* patchOf = patched->GetCellData()->GetArray("PatchId");
      ASSERT_NE(patchOf, nullptr);
      std::set<vtkIdType> onBump;
      for (vtkIdType c = 0; c < patched->GetNumberOfCells(); ++c)
      {
        vtkNew<vtkIdList> ids;
        patched->GetCellPoints(c, ids);
        for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        {
          double x[3];
          patched->GetPoint(ids->GetId(k), x);
          if (std::hypot(x[0] - centre, x[1] - centre) < 3 * sigma)
          {
            onBump.insert(static_cast<vtkIdType>(patchOf->GetTuple1(c)));
          }
        }
      }
      EXPECT_GT(refined[refine], 0);
      EXPECT_LT(2 * refined[refine], static_cast<vtkIdType>(onBump.size()));
    }
    else
    {
      EXPECT_GT(distance[refine], cap);
    }
  }
  std::cout << "bump at 10%: refined patches " << refined[true] << ", largest vertex distance " << distance[true]
            << " (without " << distance[false] << "), vertices off the bump " << flatVertices[true] << " (without "
            << flatVertices[false] << ")\n";
  EXPECT_EQ(refined[false], 0);
  EXPECT_LT(distance[true], distance[false]);
  // The flat part is not refined: it keeps no more vertices than without (the final collapses move
  // budget from it to the bump, never the other way).
  EXPECT_LE(flatVertices[true], flatVertices[false]);
}

// Issue 15 (session 38): RefineDeviatingRegions' pass goes on from the level's own last pass, so
// its work follows the refined regions, not the level. A gently waved square (many patches, all
// within their allowance) with one narrow Gaussian bump at 10%: the bump's patches are refined and
// the level keeps its other patches' triangles. The pass's report (field data, with the refined
// patches): the level triangles it triangulated again are at most twice the refined patches'
// input triangles and under a quarter of the level; base-s38 triangulated every patch again (the
// whole level). The refined level is kept (closer to the input, measured here), in the count band,
// with the input's topology.
TEST(PatchBoundaryMerge, RegionRefinementWorkFollowsTheRefinedPatches)
{
  TriangleMesh mesh = slodtest::Grid(120, 120);
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    const double x = mesh.Points[3 * size_t(v)], y = mesh.Points[3 * size_t(v) + 1];
    const double dx = x - 0.75, dy = y - 0.75, sigma = 0.05;
    mesh.Points[3 * size_t(v) + 2] =
      0.02 * std::sin(6 * x) * std::sin(5 * y) + 0.1 * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
  }
  vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(mesh);
  auto simplify = [&](bool refine) {
    auto filter = vtkSmartPointer<vtkPatchBoundaryMerge>::New();
    filter->SetInputData(input);
    filter->SetTargetReduction(0.9);
    filter->SetRefineDeviatingRegions(refine);
    filter->Update();
    const vtkIdType target = mesh.NumberOfTriangles() / 10;
    EXPECT_LE(std::abs(filter->GetOutput()->GetNumberOfPolys() - target), std::max<vtkIdType>(2, target / 50));
    slodtest::ExpectSameTopology(mesh, slodtest::ToTriangleMesh(filter->GetOutput()));
    return filter;
  };
  vtkSmartPointer<vtkPatchBoundaryMerge> without = simplify(false);
  EXPECT_EQ(without->GetRegionRetriangulatedTriangles(), -1);
  vtkSmartPointer<vtkPatchBoundaryMerge> filter = simplify(true);
  vtkPolyData* output = filter->GetOutput();
  EXPECT_GT(filter->GetRegionRefinedPatches(), 0);
  vtkDataArray* inputTriangles = output->GetFieldData()->GetArray("RegionInputTriangles");
  vtkDataArray* retriangulated = output->GetFieldData()->GetArray("RegionRetriangulatedTriangles");
  ASSERT_NE(inputTriangles, nullptr);
  ASSERT_NE(retriangulated, nullptr);
  const vtkIdType region = static_cast<vtkIdType>(inputTriangles->GetTuple1(0));
  const vtkIdType again = static_cast<vtkIdType>(retriangulated->GetTuple1(0));
  EXPECT_EQ(region, filter->GetRegionInputTriangles());
  EXPECT_EQ(again, filter->GetRegionRetriangulatedTriangles());
  std::cout << "waves and bump at 10%: " << filter->GetRegionRefinedPatches() << " patches refined, " << region
            << " input triangles; " << again << " of " << output->GetNumberOfPolys()
            << " level triangles triangulated again\n";
  EXPECT_GT(region, 0);
  EXPECT_LE(again, 2 * region);
  EXPECT_LT(4 * again, output->GetNumberOfPolys());
  EXPECT_LT(LargestVertexDistance(input, output), LargestVertexDistance(input, without->GetOutput()));
}

// Issue 15 (session 34): the minimum-deviation triangulation's diagonal cost is the distance of its
// midpoint from the input, which reads zero for a chord of a curved crease chain: it lies on the
// face beyond the crease. On the pinion at 50% the gear teeth's flanks were closed at their ends
// by triangles standing in the plane of the gear's face (their heights along the flank's normal
// unseen), 5.3x vtkQuadricDecimation's Hausdorff distance at the same count on base-s34; a
// triangle turned by more than 75 degrees from its patch's normal now counts its height as its
// cost. Within the issue's 2x for CAD meshes, measured in the same run, within the band, with the
// input's topology.
TEST(PatchBoundaryMerge, CurvedCreaseChainsAreNotFoldedIntoTheFaceBeyond)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("pinion");
  EXPECT_LE(LevelHausdorffRatioToQuadric("pinion", input, 0.5), 2.0);
}

// Issue 15 (session 34): CollapseFinerLevelForTarget's trigger at 2x the estimate kappa s^2 / 8
// (half the thickness bound as given) instead of 3x. The Fandisk at 50% (target beyond every chain
// vertex of its patches: 6,216 for 6,473 on base-s34) deviated 0.67x the bound on every vertex,
// its strided samples below it: 6.2x vtkQuadricDecimation's Hausdorff distance. The finer level,
// brought down by collapses, reaches the band and comes within 3x, measured in the same run.
TEST(PatchBoundaryMerge, CurvedCadPatchesAtMildTargetsAreRedoneFromAFinerLevel)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  EXPECT_LE(LevelHausdorffRatioToQuadric("fandisk", input, 0.5), 3.0);
}

// Issue 15 (session 45): MildTargetRegionAllowance. ALSTOM_TEST4 (CAD: flat faces, fillets, long
// crease chains; used by no other SPBM test) at 50%: its level deviates 0.46x the thickness bound
// as given, under the finer level's trigger (0.5x), while vtkQuadricDecimation spends its removals
// on the flat faces: base-s45's level was 3.2x its Hausdorff distance. At mild targets the patches
// whose vertices deviate beyond 1/8 of the bound are refined by region: within 3x of
// vtkQuadricDecimation at the same count, and closer than with the refinement off, both measured
// in this run, with the input's topology and the count in the band (LevelHausdorffRatioToQuadric).
TEST(PatchBoundaryMerge, CadPatchesAtMildTargetsAreRefinedByRegion)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("ALSTOM_TEST4");
  const double refined = LevelHausdorffRatioToQuadric("ALSTOM_TEST4", input, 0.5);
  EXPECT_LE(refined, 3.0);
  const double off = LevelHausdorffRatioToQuadric("ALSTOM_TEST4 (off)", input, 0.5, nullptr, nullptr,
    [](vtkPatchBoundaryMerge* filter) { filter->SetMildTargetRegionAllowance(0); });
  EXPECT_LT(refined, off);
}

// The ear clipper's extension: the caller's ear test and the strict (no fallback) mode.
TEST(PolygonTriangulationExtension, AcceptEarAndStrictMode)
{
  const std::vector<Vec3> square = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } };
  PolygonTriangulationOptions options;
  options.AllowFallback = false;
  // Forbid the diagonal 0-2: the triangulation must use 1-3.
  options.AcceptEar = [](Index a, Index, Index c) { return !((a == 0 && c == 2) || (a == 2 && c == 0)); };
  auto result = TriangulatePolygon(square, { 0, 0, 1 }, options);
  ASSERT_FALSE(result.Failed);
  ASSERT_EQ(result.Triangles.size(), 2u);
  for (const auto& t : result.Triangles)
  {
    EXPECT_TRUE(std::find(t.begin(), t.end(), 1) != t.end() && std::find(t.begin(), t.end(), 3) != t.end());
  }
  // Forbid both diagonals: strict mode fails instead of producing a non-manifold edge.
  options.AcceptEar = [](Index, Index, Index) { return false; };
  result = TriangulatePolygon(square, { 0, 0, 1 }, options);
  EXPECT_TRUE(result.Failed);
  // A self-intersecting (bow-tie) projection: strict fails, the default still covers it.
  const std::vector<Vec3> bowtie = { { 0, 0, 0 }, { 1, 1, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
  PolygonTriangulationOptions strict;
  strict.AllowFallback = false;
  EXPECT_TRUE(TriangulatePolygon(bowtie, { 0, 0, 1 }, strict).Failed);
  EXPECT_EQ(TriangulatePolygon(bowtie, { 0, 0, 1 }).Triangles.size(), 2u);
  // Smallest angle first: a long thin quad is cut along its short diagonal... the ear with the
  // smallest angle is clipped first.
  const std::vector<Vec3> kite = { { 0, 0, 0 }, { 4, -0.5, 0 }, { 8, 0, 0 }, { 4, 0.5, 0 } };
  result = TriangulatePolygon(kite, { 0, 0, 1 });
  ASSERT_EQ(result.Triangles.size(), 2u);
  EXPECT_EQ(result.Triangles[0][1] % 2, 0); // corner 0 or 2 (the sharp ones) clipped first
}

// Minimum-cost triangulation (dynamic programming over valid diagonals): picks the cheapest
// diagonal, never an invalid one, and fails in strict fashion when nothing valid is left.
TEST(PolygonTriangulationExtension, MinimumCostTriangulation)
{
  // Non-planar quad (a fold along 0-2): the cost says which diagonal lies on the surface.
  const std::vector<Vec3> quad = { { 0, 0, 0 }, { 1, 0, 0.3 }, { 1, 1, 0 }, { 0, 1, 0.3 } };
  for (const Index cheap : { 0, 1 })
  {
    MinimumCostTriangulationOptions options;
    options.DiagonalCost = [&](Index i, Index j) { return i == cheap && j == cheap + 2 ? 0.0 : 1.0; };
    const auto result = TriangulatePolygonMinimumCost(quad, { 0, 0, 1 }, options);
    ASSERT_FALSE(result.Failed);
    ASSERT_EQ(result.Triangles.size(), 2u);
    for (const auto& t : result.Triangles)
    {
      EXPECT_TRUE(std::find(t.begin(), t.end(), cheap) != t.end() && std::find(t.begin(), t.end(), cheap + 2) != t.end());
    }
  }
  // A concave polygon (an L): n - 2 counter-clockwise triangles covering its area, whatever the
  // costs say (the cheap diagonal 1-4 leaves the polygon and must not be used).
  const std::vector<Vec3> ell = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 }, { 0, 2, 0 } };
  MinimumCostTriangulationOptions options;
  options.DiagonalCost = [](Index i, Index j) { return i == 1 && j == 4 ? 0.0 : 1.0 + i + j; };
  auto result = TriangulatePolygonMinimumCost(ell, { 0, 0, 1 }, options);
  ASSERT_FALSE(result.Failed);
  ASSERT_EQ(result.Triangles.size(), 4u);
  double area = 0;
  for (const auto& t : result.Triangles)
  {
    const Vec3 n = Cross(ell[t[1]] - ell[t[0]], ell[t[2]] - ell[t[0]]);
    EXPECT_GT(n[2], 0);
    area += 0.5 * n[2];
    EXPECT_FALSE((std::find(t.begin(), t.end(), 1) != t.end()) && (std::find(t.begin(), t.end(), 4) != t.end()));
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
  // The reflex corner 3 must be in a diagonal of every triangulation; forbid all of its diagonals.
  options.AcceptDiagonal = [](Index i, Index j) { return i != 3 && j != 3; };
  EXPECT_TRUE(TriangulatePolygonMinimumCost(ell, { 0, 0, 1 }, options).Failed);
  // Bow-tie projection: no valid triangulation.
  const std::vector<Vec3> bowtie = { { 0, 0, 0 }, { 1, 1, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
  EXPECT_TRUE(TriangulatePolygonMinimumCost(bowtie, { 0, 0, 1 }, MinimumCostTriangulationOptions()).Failed);
}

// The level's edge map with the per-vertex filter (TrackVertices) answers every lookup as the
// plain table does, through inserts, erases, growth and resets, and the filter turns away most
// absent pairs without probing (what makes the triangulation's all-pairs lookups cheap).
TEST(SpbmEdgeMap, VertexFilterAnswersAsTheTable)
{
  using slod::spbm::EdgeMap;
  const Index vertices = 5000;
  EdgeMap tracked, plain;
  tracked.TrackVertices(size_t(vertices));
  uint64_t state = 12345;
  auto next = [&state](Index bound) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return Index((state >> 33) % uint64_t(bound));
  };
  for (int round = 0; round < 3; ++round)
  {
    tracked.Reset(16); // small: the tables grow several times below
    plain.Reset(16);
    std::set<std::pair<Index, Index>> present;
    for (int k = 0; k < 20000; ++k)
    {
      const Index a = next(vertices), b = next(vertices);
      Index x = -7, y = -7;
      if (a == b)
      {
        continue;
      }
      if (k % 5 == 4 && !present.empty())
      {
        const auto it = present.lower_bound({ a, b });
        const auto gone = it == present.end() ? *present.begin() : *it;
        EXPECT_TRUE(tracked.Erase(gone.first, gone.second));
        EXPECT_TRUE(plain.Erase(gone.second, gone.first));
        present.erase(gone);
        continue;
      }
      EXPECT_EQ(tracked.Insert(a, b, k, x), plain.Insert(b, a, k, y));
      EXPECT_EQ(x, y);
      present.insert({ std::min(a, b), std::max(a, b) });
    }
    Index turnedAway = 0, absent = 0;
    for (int k = 0; k < 50000; ++k)
    {
      const Index a = next(vertices), b = next(vertices);
      Index x = -7, y = -7;
      const bool found = tracked.Find(a, b, x);
      ASSERT_EQ(found, plain.Find(a, b, y));
      ASSERT_EQ(x, y);
      ASSERT_EQ(found, a != b && present.count({ std::min(a, b), std::max(a, b) }) > 0);
      ASSERT_TRUE(!found || tracked.MayContain(a, b));
      absent += !found;
      turnedAway += !tracked.MayContain(a, b);
    }
    for (const auto& edge : present)
    {
      ASSERT_TRUE(tracked.Contains(edge.second, edge.first));
    }
    // About 6 edges per vertex in 64-bit words: most absent pairs fail one of the two bits.
    EXPECT_GT(turnedAway, absent / 2);
  }
  // Ids beyond the tracked range are probed (never turned away).
  Index value = 0;
  EXPECT_TRUE(tracked.Insert(vertices + 3, 1, 42, value));
  EXPECT_TRUE(tracked.MayContain(vertices + 3, 1));
  EXPECT_TRUE(tracked.Find(1, vertices + 3, value) && value == 42);
}

namespace
{
// Positions of the input's border vertices where the border turns by at least `degrees` (two
// border edges meet there; each border edge belongs to one triangle).
std::vector<std::array<double, 3>> BorderCorners(vtkPolyData* input, double degrees)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> uses;
  const vtkIdType* ids;
  vtkIdType n;
  auto polys = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell())
  {
    polys->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      ++uses[std::minmax(ids[k], ids[(k + 1) % n])];
    }
  }
  std::map<vtkIdType, std::vector<vtkIdType>> borderNeighbors;
  for (const auto& [edge, count] : uses)
  {
    if (count == 1)
    {
      borderNeighbors[edge.first].push_back(edge.second);
      borderNeighbors[edge.second].push_back(edge.first);
    }
  }
  std::vector<std::array<double, 3>> corners;
  for (const auto& [v, neighbors] : borderNeighbors)
  {
    if (neighbors.size() != 2)
    {
      continue;
    }
    Vec3 a, b, c;
    input->GetPoint(neighbors[0], a.data());
    input->GetPoint(v, b.data());
    input->GetPoint(neighbors[1], c.data());
    const Vec3 in = b - a, out = c - b;
    if (Dot(in, out) <= std::cos(vtkMath::RadiansFromDegrees(degrees)) * Norm(in) * Norm(out))
    {
      corners.push_back({ b[0], b[1], b[2] });
    }
  }
  return corners;
}

bool HasPoint(vtkPolyData* mesh, const std::array<double, 3>& p)
{
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double q[3];
    mesh->GetPoint(i, q);
    if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2])
    {
      return true;
    }
  }
  return false;
}
} // namespace

// Issue 15 (session 31): the corners of an open sheet's border stay (BorderCornerAngle, 60
// degrees). three_peaks (a height field over a rectangle) at 10%: the paper's chains end only
// where the patch across changes, so a corner was an inner chain vertex and the coarse target's
// chain tolerance cut it off (Hausdorff 8.4x vtkQuadricDecimation's, all of it at one corner).
TEST(PatchBoundaryMerge, BorderCornersOfAnOpenSheetStay)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("three_peaks");
  const auto corners = BorderCorners(input, 60.0);
  ASSERT_GE(corners.size(), 4u);
  auto simplified = [&](double cornerAngle) {
    vtkNew<vtkPatchBoundaryMerge> filter;
    filter->SetInputData(input);
    filter->SetTargetReduction(0.9);
    filter->SetBorderCornerAngle(cornerAngle);
    // The paper's chains are compared by themselves: the finer level's collapses (session 33) and
    // the refined regions' (session 37) bring the cut corners back at this target.
    filter->SetCollapseFinerLevelForTarget(cornerAngle > 0);
    filter->SetRefineDeviatingRegions(cornerAngle > 0);
    filter->Update();
    return vtkSmartPointer<vtkPolyData>(filter->GetOutput());
  };
  vtkSmartPointer<vtkPolyData> kept = simplified(60.0);
  for (const auto& corner : corners)
  {
    EXPECT_TRUE(HasPoint(kept, corner)) << corner[0] << " " << corner[1] << " " << corner[2];
  }
  // The paper's chains (0): some corner is cut, so the assertion above is not vacuous.
  vtkSmartPointer<vtkPolyData> paper = simplified(0.0);
  EXPECT_FALSE(std::all_of(
    corners.begin(), corners.end(), [&](const std::array<double, 3>& c) { return HasPoint(paper, c); }));
  EXPECT_LE(LevelHausdorffRatioToQuadric("three_peaks", input, 0.9), 3.0);
}

// Issue 15 (session 32): LoosenThicknessForTarget decides from EstimateDeviation, whose strided
// samples missed the few chain vertices a coarse level's epsilon drops, where its largest error
// sits (mushroom at 70%: sampled 1.08x the thickness bound, measured 1.58x, so the looser patches
// were never tried). With everyVertex the estimate covers every input vertex: it is at least the
// exact largest vertex-to-level distance (computed here by brute force), on a mesh the change was
// not tuned on, at three levels.
TEST(SpbmLevel, DeviationEstimateCoversEveryVertex)
{
  const auto pm = Patch(slodtest::ToTriangleMesh(slodtest::LoadTestMesh("blobby")));
  const TriangleMesh& prepared = pm->Mesh;
  SpbmLevelGenerator generator;
  generator.Initialize(prepared, pm->Patches);
  for (const Index target : { prepared.NumberOfTriangles() / 2, prepared.NumberOfTriangles() / 10, Index(60) })
  {
    SpbmLevel level;
    ASSERT_TRUE(generator.GenerateForTarget(target, SpbmLevelParameters{}, level));
    ASSERT_FALSE(level.Triangles.empty());
    double worst2 = 0;
    for (Index v = 0; v < prepared.NumberOfPoints(); ++v)
    {
      const Vec3 p = prepared.Point(v);
      double nearest2 = std::numeric_limits<double>::infinity();
      for (size_t t = 0; t < level.Triangles.size(); t += 3)
      {
        const Vec3 q = ClosestPointOnTriangle(p, prepared.Point(level.Triangles[t]),
          prepared.Point(level.Triangles[t + 1]), prepared.Point(level.Triangles[t + 2]));
        nearest2 = std::min(nearest2, Dot(p - q, p - q));
      }
      worst2 = std::max(worst2, nearest2);
    }
    const double everyVertex = generator.EstimateDeviation(level, 3000, true);
    EXPECT_GE(everyVertex, std::sqrt(worst2) * (1 - 1e-9)) << "target " << target;
    EXPECT_GE(everyVertex, generator.EstimateDeviation(level));
  }
}
