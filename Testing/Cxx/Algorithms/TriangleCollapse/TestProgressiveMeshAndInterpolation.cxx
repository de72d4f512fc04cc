// SPDX-License-Identifier: BSD-3-Clause
// Progressive meshes from triangle collapses (vtkQuadricTriangleCollapse records +
// vtkProgressiveMeshReconstruction) and interpolation between two levels (vtkLODInterpolation).
#include "TestSupport.h"

#include "slodMeshTopology.h"
#include "vtkLODInterpolation.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"

#include "vtkCellArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

using namespace slod;

namespace
{
// Triangles as coordinate triples, rotated so the smallest corner comes first (orientation kept),
// sorted: equal lists mean the same mesh up to point and triangle ordering.
std::vector<std::array<double, 9>> CanonicalTriangles(const TriangleMesh& mesh)
{
  std::vector<std::array<double, 9>> out;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    std::array<Vec3, 3> c = { mesh.Point(tri[0]), mesh.Point(tri[1]), mesh.Point(tri[2]) };
    const int first = int(std::min_element(c.begin(), c.end()) - c.begin());
    std::array<double, 9> row;
    for (int k = 0; k < 3; ++k)
    {
      const Vec3& p = c[(first + k) % 3];
      std::copy(p.begin(), p.end(), row.begin() + 3 * k);
    }
    out.push_back(row);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Progressive
{
  vtkNew<vtkQuadricTriangleCollapse> Collapse;
  vtkNew<vtkProgressiveMeshReconstruction> Reconstruction;
  Progressive(vtkPolyData* input, vtkIdType target, bool batches = false)
  {
    this->Collapse->SetBatchCollapses(batches);
    this->Collapse->SetInputData(input);
    this->Collapse->SetTargetNumberOfTriangles(target);
    this->Collapse->SetTargetReduction(0);
    this->Collapse->GenerateProgressiveMeshOn();
    this->Reconstruction->SetCoarseMeshConnection(this->Collapse->GetOutputPort(0));
    this->Reconstruction->SetRecordsConnection(this->Collapse->GetOutputPort(1));
  }
};

// Collapsing to 2% with records, then applying every record to the coarse mesh, gives the input.
void ExpectExactRoundTrip(const char* name, bool batches)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
  const TriangleMesh prepared = slodtest::ToTriangleMesh(input);
  Progressive pm(input, prepared.NumberOfTriangles() / 50, batches);
  pm.Reconstruction->Update();
  vtkTable* records = pm.Collapse->GetCollapseRecords();
  ASSERT_EQ(records->GetNumberOfRows(), pm.Collapse->GetNumberOfCollapses());
  EXPECT_GT(records->GetNumberOfRows(), 0);
  EXPECT_EQ(pm.Reconstruction->GetAppliedVertexSplits(), records->GetNumberOfRows());
  const TriangleMesh rebuilt = slodtest::RawTriangleMesh(pm.Reconstruction->GetOutput());
  EXPECT_EQ(rebuilt.NumberOfTriangles(), prepared.NumberOfTriangles());
  EXPECT_EQ(rebuilt.NumberOfPoints(), prepared.NumberOfPoints());
  EXPECT_TRUE(CanonicalTriangles(rebuilt) == CanonicalTriangles(prepared)) << "the rebuilt mesh differs from the input";
}
} // namespace

class ProgressiveMeshRoundTrip : public ::testing::TestWithParam<const char*>
{
};

TEST_P(ProgressiveMeshRoundTrip, CoarsePlusAllRecordsIsTheInput)
{
  for (bool batches : { false, true })
  {
    SCOPED_TRACE(batches ? "batch collapses" : "strict order");
    ExpectExactRoundTrip(GetParam(), batches);
  }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, ProgressiveMeshRoundTrip, ::testing::Values("fandisk", "bunny00", "elephant-with-holes"));

TEST(ProgressiveMesh, AnyLevelInOrderKSplits)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("femur");
  Progressive pm(input, 100);
  pm.Reconstruction->SetNumberOfVertexSplits(0);
  pm.Reconstruction->Update();
  // Level 0 is the coarse mesh itself.
  EXPECT_EQ(pm.Reconstruction->GetOutput()->GetNumberOfPolys(), pm.Collapse->GetOutput()->GetNumberOfPolys());
  const MeshStatistics base = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
  vtkIdType level = 0;
  for (vtkIdType target : { 500, 2000, 7000, 1000, 300 })
  {
    pm.Reconstruction->SetTargetNumberOfTriangles(target);
    pm.Reconstruction->Update();
    const vtkIdType n = pm.Reconstruction->GetOutput()->GetNumberOfPolys();
    EXPECT_GE(n, target);
    EXPECT_LE(n, target + 3);
    // Moving between levels costs exactly the number of splits (or re-collapses) in between.
    const vtkIdType now = pm.Reconstruction->GetAppliedVertexSplits();
    EXPECT_EQ(pm.Reconstruction->GetOperationsLastUpdate(), std::abs(now - level));
    level = now;
    const MeshStatistics s = ComputeMeshStatistics(slodtest::RawTriangleMesh(pm.Reconstruction->GetOutput()));
    EXPECT_EQ(s.NonManifoldEdges, 0);
    EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
    EXPECT_EQ(s.Genus, base.Genus);
  }
}

TEST(ProgressiveMesh, RejectsInputsWithoutRecords)
{
  vtkNew<vtkProgressiveMeshReconstruction> reconstruction;
  vtkNew<vtkTable> table;
  reconstruction->SetInputData(0, slodtest::LoadTestMesh("femur"));
  reconstruction->SetInputData(1, table);
  reconstruction->SetGlobalWarningDisplay(0);
  reconstruction->Update();
  EXPECT_EQ(reconstruction->GetOutput()->GetNumberOfPoints(), 0);
}

namespace
{
vtkSmartPointer<vtkPolyData> Interpolate(vtkPolyData* detailed, vtkPolyData* coarse, double t, double epsilon)
{
  vtkNew<vtkLODInterpolation> filter;
  filter->SetDetailedData(detailed);
  filter->SetCoarseData(coarse);
  filter->SetT(t);
  filter->SetEpsilon(epsilon);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}
} // namespace

TEST(LODInterpolation, EndsReproduceTheInputs)
{
  vtkSmartPointer<vtkPolyData> detailed = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(detailed);
  collapse->SetTargetReduction(0.95);
  collapse->Update();
  vtkPolyData* coarse = collapse->GetOutput();
  const TriangleMesh d = slodtest::RawTriangleMesh(detailed), c = slodtest::RawTriangleMesh(coarse);
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(Interpolate(detailed, coarse, 0.0, 1e-3))) == CanonicalTriangles(d));
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(Interpolate(detailed, coarse, 1.0, 1e-3))) == CanonicalTriangles(c));
}

TEST(LODInterpolation, CorrespondencesAndInterpolationMatchBruteForce)
{
  vtkSmartPointer<vtkPolyData> detailed = slodtest::LoadTestMesh("femur");
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(detailed);
  collapse->SetTargetReduction(0.95);
  collapse->Update();
  const TriangleMesh d = slodtest::ToTriangleMesh(detailed), c = slodtest::RawTriangleMesh(collapse->GetOutput());
  // Epsilon 0: no merging, so output vertex i is detailed vertex i moved halfway to its match.
  const TriangleMesh out = slodtest::RawTriangleMesh(Interpolate(detailed, collapse->GetOutput(), 0.5, 0.0));
  ASSERT_EQ(out.NumberOfPoints(), d.NumberOfPoints());
  ASSERT_EQ(out.NumberOfTriangles(), d.NumberOfTriangles());
  auto nearest = [](const TriangleMesh& m, const Vec3& p) {
    Index best = 0;
    double bestD = std::numeric_limits<double>::infinity();
    for (Index v = 0; v < m.NumberOfPoints(); ++v)
    {
      const Vec3 e = m.Point(v) - p;
      if (Dot(e, e) < bestD)
      {
        bestD = Dot(e, e);
        best = v;
      }
    }
    return best;
  };
  // Brute force steps 1 and 2.
  std::vector<Index> match(d.NumberOfPoints(), InvalidIndex);
  std::vector<double> matchD(d.NumberOfPoints(), std::numeric_limits<double>::infinity());
  for (Index l = 0; l < c.NumberOfPoints(); ++l)
  {
    const Index h = nearest(d, c.Point(l));
    const Vec3 e = c.Point(l) - d.Point(h);
    if (Dot(e, e) < matchD[h])
    {
      matchD[h] = Dot(e, e);
      match[h] = l;
    }
  }
  double worst = 0;
  for (Index h = 0; h < d.NumberOfPoints(); ++h)
  {
    const Index l = match[h] != InvalidIndex ? match[h] : nearest(c, d.Point(h));
    const Vec3 expected = 0.5 * (c.Point(l) + d.Point(h));
    worst = std::max(worst, Norm(expected - out.Point(h)));
  }
  EXPECT_LT(worst, 1e-5 * d.BoundingBoxDiagonal());
}

TEST(LODInterpolation, MergesCloseVerticesAndDropsDegenerateTriangles)
{
  vtkSmartPointer<vtkPolyData> detailed = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(detailed);
  collapse->SetTargetReduction(0.97);
  collapse->Update();
  vtkNew<vtkLODInterpolation> filter;
  filter->SetDetailedData(detailed);
  filter->SetCoarseData(collapse->GetOutput());
  const vtkIdType nd = detailed->GetNumberOfPolys();
  vtkIdType previous = nd + 1;
  for (double t : { 0.25, 0.5, 0.9, 0.99 })
  {
    filter->SetT(t);
    filter->SetEpsilon(2e-3);
    filter->Update();
    const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
    EXPECT_EQ(filter->GetRemovedTriangles(), nd - out.NumberOfTriangles());
    // Closer to the coarse mesh, more vertices coincide: the count falls monotonically.
    EXPECT_LE(out.NumberOfTriangles(), previous);
    previous = out.NumberOfTriangles();
    for (Index t2 = 0; t2 < out.NumberOfTriangles(); ++t2)
    {
      const Index* tri = out.Triangle(t2);
      ASSERT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0]);
    }
  }
  EXPECT_LT(previous, nd / 2);
}
