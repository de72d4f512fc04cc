// SPDX-License-Identifier: BSD-3-Clause
// Progressive meshes from triangle collapses (vtkQuadricTriangleCollapse records +
// vtkProgressiveMeshReconstruction) and interpolation between two levels (vtkLODInterpolation).
#include "TestSupport.h"

#include "slodMeshTopology.h"
#include "vtkLODInterpolation.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkSurfaceDeviation.h"

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
#include <string>

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

// Two levels of one collapse run and its records: the coarse mesh at `coarseShare` of the input's
// triangles, the detailed one a reconstruction level at `detailedShare` (1: the input itself).
struct TwoLevels
{
  vtkSmartPointer<vtkPolyData> Detailed, Coarse;
  vtkSmartPointer<vtkTable> Records;
  TwoLevels(vtkPolyData* input, double detailedShare, double coarseShare)
  {
    const vtkIdType n = input->GetNumberOfPolys();
    Progressive pm(input, vtkIdType(coarseShare * n));
    pm.Reconstruction->SetTargetNumberOfTriangles(vtkIdType(detailedShare * n));
    pm.Reconstruction->Update();
    this->Coarse = vtkSmartPointer<vtkPolyData>::New();
    this->Coarse->DeepCopy(pm.Collapse->GetOutput(0));
    this->Records = vtkSmartPointer<vtkTable>::New();
    this->Records->DeepCopy(pm.Collapse->GetCollapseRecords());
    this->Detailed = input;
    if (detailedShare < 1)
    {
      this->Detailed = vtkSmartPointer<vtkPolyData>::New();
      this->Detailed->DeepCopy(pm.Reconstruction->GetOutput());
    }
  }
  vtkSmartPointer<vtkPolyData> Morph(double t, vtkLODInterpolation* filter = nullptr) const
  {
    vtkNew<vtkLODInterpolation> own;
    filter = filter ? filter : own.Get();
    filter->SetDetailedData(this->Detailed);
    filter->SetCoarseData(this->Coarse);
    filter->SetRecordsData(this->Records);
    filter->SetT(t);
    filter->Update();
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(filter->GetOutput());
    return out;
  }
};

// Triangles with the same three vertices as an earlier one (any order).
Index DuplicateTriangles(const TriangleMesh& mesh)
{
  std::vector<std::array<Index, 3>> sorted;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    std::array<Index, 3> v = { mesh.Triangle(t)[0], mesh.Triangle(t)[1], mesh.Triangle(t)[2] };
    std::sort(v.begin(), v.end());
    sorted.push_back(v);
  }
  std::sort(sorted.begin(), sorted.end());
  return Index(sorted.size() - (std::unique(sorted.begin(), sorted.end()) - sorted.begin()));
}

// Symmetric Hausdorff distance of two surfaces (every vertex and 20,000 samples per side).
double Hausdorff(vtkPolyData* a, vtkPolyData* b)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetInputData(0, a);
  deviation->SetInputData(1, b);
  deviation->SetNumberOfSamples(20000);
  deviation->SampleVerticesOn();
  deviation->Update();
  return deviation->GetHausdorff();
}

// The geomorph at t in `ts` (0 and 1 included): the ends are the two levels; in between no
// non-manifold edge or vertex, no duplicate triangle, no misoriented edge, the Euler
// characteristic and border loops of both ends; from t to t + delta the surface moves by at most
// 2 delta times the diagonal (each vertex moves on a segment no longer than about the diagonal),
// at t = 1 - delta to 1 included.
void ExpectContinuousManifoldMorph(const TwoLevels& levels, const std::vector<double>& ts)
{
  const TriangleMesh detailed = slodtest::RawTriangleMesh(levels.Detailed), coarse = slodtest::RawTriangleMesh(levels.Coarse);
  const MeshStatistics d = ComputeMeshStatistics(detailed), c = ComputeMeshStatistics(coarse);
  ASSERT_EQ(d.EulerCharacteristic, c.EulerCharacteristic);
  ASSERT_EQ(d.BoundaryLoops, c.BoundaryLoops);
  const double diagonal = detailed.BoundingBoxDiagonal(), delta = 1e-6;
  vtkNew<vtkLODInterpolation> filter;
  for (double t : ts)
  {
    SCOPED_TRACE("t = " + std::to_string(t));
    vtkSmartPointer<vtkPolyData> out = levels.Morph(t, filter);
    EXPECT_TRUE(filter->GetUsedCollapseRecords());
    const TriangleMesh mesh = slodtest::RawTriangleMesh(out);
    const MeshStatistics s = ComputeMeshStatistics(mesh);
    EXPECT_EQ(s.NonManifoldEdges, 0);
    EXPECT_EQ(s.NonManifoldVertices, 0);
    EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
    EXPECT_EQ(DuplicateTriangles(mesh), 0);
    EXPECT_EQ(s.EulerCharacteristic, d.EulerCharacteristic);
    EXPECT_EQ(s.BoundaryLoops, d.BoundaryLoops);
    EXPECT_EQ(s.Components, d.Components);
    const double next = std::min(1.0, t + delta), previous = next - delta;
    EXPECT_LE(Hausdorff(levels.Morph(previous), levels.Morph(next)), 2 * delta * diagonal) << "jump between " << previous << " and " << next;
  }
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(levels.Morph(0.0))) == CanonicalTriangles(detailed));
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(levels.Morph(1.0))) == CanonicalTriangles(coarse));
}

const std::vector<double> MorphTimes = { 0, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999999, 1 - 1e-9, 1 };
} // namespace

// The case: bunny00 between its 10 % and 2 % levels of one collapse run.
TEST(LODInterpolation, GeomorphBetweenTwoLevelsIsContinuousAndManifold)
{
  ExpectContinuousManifoldMorph(TwoLevels(slodtest::LoadTestMesh("bunny00"), 0.10, 0.02), MorphTimes);
}

// From the collapse filter's input itself (no OriginalVertexId) to its output; an open mesh with
// holes (border loops kept at every t).
TEST(LODInterpolation, GeomorphFromTheInputKeepsBorders)
{
  ExpectContinuousManifoldMorph(TwoLevels(slodtest::LoadTestMesh("fandisk"), 1.0, 0.05), MorphTimes);
  ExpectContinuousManifoldMorph(TwoLevels(slodtest::LoadTestMesh("mech-holes-shark"), 1.0, 0.05), { 0, 1e-6, 0.5, 0.999999, 1 });
}

// Records that do not relate the two meshes (levels swapped, or the coarse mesh of a run with
// other collapses: triangle collapses only) are an error and an empty output, never a wrong morph.
TEST(LODInterpolation, RecordsOfOtherLevelsAreAnError)
{
  const TwoLevels levels(slodtest::LoadTestMesh("fandisk"), 0.5, 0.05);
  vtkNew<vtkQuadricTriangleCollapse> otherRun;
  otherRun->SetInputData(slodtest::LoadTestMesh("fandisk"));
  otherRun->EdgeCollapsesOff();
  otherRun->GenerateProgressiveMeshOn();
  otherRun->Update();
  vtkObject::GlobalWarningDisplayOn(); // another test may have turned it off: no error event then
  for (int wrong = 0; wrong < 2; ++wrong)
  {
    vtkNew<vtkLODInterpolation> filter;
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::ErrorEvent, messages);
    filter->SetDetailedData(wrong == 0 ? levels.Coarse : levels.Detailed);
    filter->SetCoarseData(wrong == 0 ? levels.Detailed.Get() : otherRun->GetOutput());
    filter->SetRecordsData(levels.Records);
    filter->Update();
    EXPECT_EQ(messages->Errors.size(), 1u);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
}

// Without records (the paper's nearest-vertex correspondence) t = 0 is still the detailed mesh:
// no edge merges before it has shrunk.
TEST(LODInterpolation, NearestVertexMorphStartsAtTheDetailedMesh)
{
  vtkSmartPointer<vtkPolyData> detailed = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(detailed);
  collapse->SetTargetReduction(0.95);
  collapse->Update();
  vtkNew<vtkLODInterpolation> filter;
  filter->SetDetailedData(detailed);
  filter->SetCoarseData(collapse->GetOutput());
  filter->SetEpsilon(1e-2);
  filter->SetT(0.0);
  filter->Update();
  EXPECT_FALSE(filter->GetUsedCollapseRecords());
  EXPECT_EQ(filter->GetMergedVertices(), 0);
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(filter->GetOutput())) == CanonicalTriangles(slodtest::RawTriangleMesh(detailed)));
}

// The ends are the two levels (the geomorph's; without a special case for either).
TEST(LODInterpolation, EndsReproduceTheInputs)
{
  vtkSmartPointer<vtkPolyData> detailed = slodtest::LoadTestMesh("fandisk");
  const TwoLevels levels(detailed, 1.0, 0.05);
  const TriangleMesh d = slodtest::RawTriangleMesh(detailed), c = slodtest::RawTriangleMesh(levels.Coarse);
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(levels.Morph(0.0))) == CanonicalTriangles(d));
  EXPECT_TRUE(CanonicalTriangles(slodtest::RawTriangleMesh(levels.Morph(1.0))) == CanonicalTriangles(c));
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
