// SPDX-License-Identifier: BSD-3-Clause
// vtkTopologicalNoiseRemoval (Guskov & Wood 2001): handles below the feature size cut and filled,
// those above kept (torus, block plates with square holes of known sizes, CGAL's cheese at several
// sizes), Euler characteristic and genus before/after, manifold and consistently oriented output,
// Hausdorff distance to the input within the feature size, field-data counts, small components
// and cavities, point data, determinism, bad and non-manifold input.
#include "TestSupport.h"

#include "slodBlockModel.h"
#include "slodManifoldSplit.h"
#include "slodMeshTopology.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkSurfaceDeviation.h"
#include "vtkTopologicalNoiseRemoval.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace slod;
using namespace slodtest;

namespace
{

struct CleanRun
{
  vtkSmartPointer<vtkPolyData> Surface, Loops;
  vtkSmartPointer<MessageCounter> Messages;
};

CleanRun Clean(vtkPolyData* input, double alpha, bool relative = false, bool removeComponents = true,
  bool splitNonManifold = true, double surveyFactor = 2.0)
{
  vtkNew<vtkTopologicalNoiseRemoval> filter;
  filter->SetInputData(input);
  filter->SetKeptHandleSurveyFactor(surveyFactor);
  filter->SetSplitNonManifold(splitNonManifold);
  filter->SetRemoveComponents(removeComponents);
  filter->SetFeatureSize(alpha);
  filter->SetFeatureSizeIsRelative(relative);
  CleanRun run;
  run.Messages = vtkSmartPointer<MessageCounter>::New();
  filter->AddObserver(vtkCommand::WarningEvent, run.Messages);
  filter->AddObserver(vtkCommand::ErrorEvent, run.Messages);
  filter->Update();
  run.Surface = filter->GetOutput(0);
  run.Loops = filter->GetOutput(1);
  return run;
}

int FieldCount(vtkPolyData* pd, const char* name);

std::vector<double> FieldValues(vtkPolyData* pd, const char* name)
{
  std::vector<double> values;
  vtkDataArray* a = pd->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i)
  {
    values.push_back(a->GetTuple1(i));
  }
  return values;
}

// The kept handles the survey reported: one "Removed" 0 loop on port 1 each, each size between
// the feature size and the largest size surveyed (a doubling of the feature size), and, with the
// handles it did not size, as many as the output's genus.
std::vector<double> ExpectSurveyedHandles(const CleanRun& run, double alpha)
{
  const std::vector<double> sizes = FieldValues(run.Surface, "KeptHandleSizes");
  const double surveySize = FieldValues(run.Surface, "KeptHandleSurveySize").at(0);
  if (!sizes.empty())
  {
    const double rounds = std::log2(surveySize / alpha);
    EXPECT_GE(rounds, 1.0 - 1e-9);
    EXPECT_NEAR(rounds, std::round(rounds), 1e-9);
  }
  for (double size : sizes)
  {
    EXPECT_GT(size, alpha);
    EXPECT_LE(size, surveySize * (1 + 1e-9));
  }
  int keptLoops = 0;
  vtkDataArray* removed = run.Loops->GetCellData()->GetArray("Removed");
  for (vtkIdType c = 0; removed && c < run.Loops->GetNumberOfCells(); ++c)
  {
    keptLoops += removed->GetTuple1(c) == 0 ? 1 : 0;
  }
  EXPECT_EQ(keptLoops, static_cast<int>(sizes.size()) + FieldCount(run.Surface, "LoopsKept"));
  EXPECT_EQ(static_cast<int>(sizes.size()) + FieldCount(run.Surface, "HandlesNotSized"),
    FieldCount(run.Surface, "HandlesKept"));
  return sizes;
}

int FieldCount(vtkPolyData* pd, const char* name)
{
  vtkDataArray* a = pd->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? static_cast<int>(a->GetTuple1(0)) : -1000;
}

MeshStatistics Stats(vtkPolyData* pd)
{
  const TriangleMesh mesh = RawTriangleMesh(pd);
  return MeshTopology(mesh).Statistics(mesh);
}

void ExpectCleanManifold(const MeshStatistics& s)
{
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.NonManifoldVertices, 0);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
}

// Symmetric Hausdorff distance (absolute), sampled by vtkSurfaceDeviation.
double Hausdorff(vtkPolyData* a, vtkPolyData* b)
{
  vtkNew<vtkSurfaceDeviation> d;
  d->SetReferenceData(a);
  d->SetComparedData(b);
  d->SetNumberOfSamples(20000);
  d->Update();
  return d->GetHausdorff();
}

// Every loop of port 1 that was cut is at most pi alpha long.
void ExpectShortCutLoops(vtkPolyData* loops, double alpha)
{
  vtkDataArray* removed = loops->GetCellData()->GetArray("Removed");
  vtkDataArray* length = loops->GetCellData()->GetArray("Length");
  ASSERT_NE(removed, nullptr);
  ASSERT_NE(length, nullptr);
  for (vtkIdType c = 0; c < loops->GetNumberOfCells(); ++c)
  {
    if (removed->GetTuple1(c) == 1)
    {
      EXPECT_LE(length->GetTuple1(c), Pi * alpha * (1 + 1e-9));
    }
  }
}

// A 17 x 17 cell plate (thickness 0.5) with a 3 x 3 hole in the middle and four 1 x 1 holes three
// cells from the border and from the large hole: genus 5. The shortest loop around a small hole
// runs around its wall (length 4, size 4 / pi = 1.27), around the large one 12 (size 3.82); a loop
// around a bar between holes or around the border is at least 2 (3 + 0.5) = 7 long (size 2.23).
TriangleMesh PlateWithSmallAndLargeHoles()
{
  const int n = 17;
  std::vector<double> heights(size_t(n) * n, 0.5);
  for (int j = 7; j < 10; ++j)
  {
    for (int i = 7; i < 10; ++i)
    {
      heights[size_t(i) + n * size_t(j)] = 0;
    }
  }
  for (int j : { 3, 13 })
  {
    for (int i : { 3, 13 })
    {
      heights[size_t(i) + n * size_t(j)] = 0;
    }
  }
  return BlockModel(n, n, heights, 1.0, 2);
}
} // namespace

TEST(TopologicalNoiseRemoval, TorusCutBelowItsMeridianKeptAbove)
{
  // Minor radius 0.35: the meridian is 2 pi 0.35 = 2.2 long (size 0.7), the inner equator 4.1 (1.3).
  vtkSmartPointer<vtkPolyData> torus = ToPolyData(Torus(64, 32, 1.0, 0.35));
  const MeshStatistics before = Stats(torus);
  ASSERT_EQ(before.EulerCharacteristic, 0);

  const CleanRun kept = Clean(torus, 0.6);
  EXPECT_EQ(FieldCount(kept.Surface, "HandlesRemoved"), 0);
  EXPECT_EQ(Stats(kept.Surface).EulerCharacteristic, 0);
  EXPECT_EQ(kept.Surface->GetNumberOfPolys(), torus->GetNumberOfPolys());
  // The kept handle is reported with its size by the survey's first round (up to 2 x 0.6 = 1.2,
  // above the meridian's 0.7, below the inner equator's 1.3): one, between 0.6 and 1.2, and no
  // second round.
  EXPECT_EQ(ExpectSurveyedHandles(kept, 0.6).size(), 1u);
  EXPECT_DOUBLE_EQ(FieldValues(kept.Surface, "KeptHandleSurveySize").at(0), 1.2);

  const CleanRun cut = Clean(torus, 0.8);
  const MeshStatistics after = Stats(cut.Surface);
  EXPECT_EQ(FieldCount(cut.Surface, "HandlesRemoved"), 1);
  EXPECT_EQ(FieldCount(cut.Surface, "HandlesKept"), 0);
  EXPECT_EQ(after.EulerCharacteristic, 2);
  EXPECT_EQ(after.Genus, 0);
  EXPECT_EQ(after.Components, 1);
  EXPECT_EQ(after.BoundaryEdges, 0);
  ExpectCleanManifold(after);
  EXPECT_EQ(cut.Loops->GetNumberOfCells(), 1);
  ExpectShortCutLoops(cut.Loops, 0.8);
  // The fills are disks spanning a meridian: they stay within its radius of the torus.
  EXPECT_LE(Hausdorff(torus, cut.Surface), 0.35 + 1e-3);
  EXPECT_TRUE(cut.Messages->Warnings.empty());
}

TEST(TopologicalNoiseRemoval, PlateSmallHolesRemovedLargeKept)
{
  vtkSmartPointer<vtkPolyData> plate = ToPolyData(PlateWithSmallAndLargeHoles());
  const MeshStatistics before = Stats(plate);
  ASSERT_EQ(before.Genus, 5);

  // Every loop is longer than pi; the survey goes on (up to 64 alpha) until every handle is sized.
  const CleanRun none = Clean(plate, 1.0, false, true, true, 64.0);
  EXPECT_EQ(FieldCount(none.Surface, "HandlesRemoved"), 0);
  EXPECT_EQ(Stats(none.Surface).Genus, 5);
  // Reported: all five handles; the four small holes (loops of 4: 1.27) and the large hole (its
  // shortest loop is its 3 x 3 wall's perimeter, 12: 3.82; a surveyed loop is never shorter).
  const std::vector<double> sizes = ExpectSurveyedHandles(none, 1.0);
  ASSERT_EQ(sizes.size(), 5u);
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_LE(sizes[i], 2.0);
  }
  EXPECT_GE(sizes[4], 12.0 / 3.14159265358979 - 1e-9);

  const double alpha = 1.8; // between the small holes (1.27) and the bars (2.23), large hole 3.82
  const CleanRun small = Clean(plate, alpha, false, true, true, 64.0);
  const MeshStatistics after = Stats(small.Surface);
  EXPECT_EQ(FieldCount(small.Surface, "HandlesRemoved"), 4);
  EXPECT_EQ(FieldCount(small.Surface, "HandlesKept"), 1);
  // The large hole (3.82) is beyond the survey's first round (3.6): sized by a later one.
  const std::vector<double> large = ExpectSurveyedHandles(small, alpha);
  ASSERT_EQ(large.size(), 1u);
  EXPECT_GE(large[0], 12.0 / 3.14159265358979 - 1e-9);
  EXPECT_EQ(FieldCount(small.Surface, "HandlesNotSized"), 0);
  EXPECT_EQ(after.Genus, 1);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic + 8);
  ExpectCleanManifold(after);
  ExpectShortCutLoops(small.Loops, alpha);
  // A filled 1 x 1 hole is at most half a cell from the walls it spans.
  EXPECT_LE(Hausdorff(plate, small.Surface), 0.5 * std::sqrt(2.0) + 1e-3);

  const CleanRun all = Clean(plate, 4.5); // every loop around a hole is at most 12 < 4.5 pi
  const MeshStatistics allStats = Stats(all.Surface);
  EXPECT_EQ(FieldCount(all.Surface, "HandlesRemoved"), 5);
  EXPECT_EQ(allStats.Genus, 0);
  EXPECT_EQ(allStats.EulerCharacteristic, 2);
  ExpectCleanManifold(allStats);
  EXPECT_LE(Hausdorff(plate, all.Surface), 4.5);
}

// CGAL's cheese (genus 133, smooth round through-holes): the genus drops by exactly the loops
// cut, every cut loop is short, more goes at a larger size, and cleaning again at the same size
// finds nothing left (no loop within the size remains).
TEST(TopologicalNoiseRemoval, CheeseAtTwoSizes)
{
  vtkSmartPointer<vtkPolyData> cheese = LoadTestMesh("cheese");
  const MeshStatistics before = Stats(cheese);
  ASSERT_EQ(before.Genus, 133);
  const double diagonal = std::sqrt(std::pow(cheese->GetBounds()[1] - cheese->GetBounds()[0], 2) +
    std::pow(cheese->GetBounds()[3] - cheese->GetBounds()[2], 2) +
    std::pow(cheese->GetBounds()[5] - cheese->GetBounds()[4], 2));
  int previousRemoved = 0;
  // Two sizes inside the range of the hole sizes (relative to the diagonal): some holes go, some stay.
  for (double relative : { 0.04, 0.06 })
  {
    const double alpha = relative * diagonal;
    const CleanRun run = Clean(cheese, relative, true);
    const MeshStatistics after = Stats(run.Surface);
    const int removed = FieldCount(run.Surface, "HandlesRemoved");
    EXPECT_GT(removed, previousRemoved) << relative;
    EXPECT_GT(after.Genus, 0) << relative; // the large holes stay
    EXPECT_EQ(after.Genus, before.Genus - removed) << relative;
    EXPECT_EQ(FieldCount(run.Surface, "HandlesKept"), after.Genus);
    ExpectCleanManifold(after);
    EXPECT_EQ(after.Components, 1);
    ExpectShortCutLoops(run.Loops, alpha);
    EXPECT_LE(Hausdorff(cheese, run.Surface), alpha);
    const CleanRun again = Clean(run.Surface, alpha);
    EXPECT_EQ(FieldCount(again.Surface, "HandlesRemoved"), 0) << relative;
    previousRemoved = removed;
  }
}

TEST(TopologicalNoiseRemoval, SmallComponentsAndCavitiesRemoved)
{
  // A unit-diameter sphere, a speck of diameter 0.05 outside it and one inside it (a cavity).
  const TriangleMesh big = Sphere(24, 24);
  TriangleMesh speck = Sphere(8, 8), cavity = Sphere(8, 8);
  for (Index v = 0; v < speck.NumberOfPoints(); ++v)
  {
    speck.SetPoint(v, 0.1 * speck.Point(v) + Vec3{ 2.0, 0.0, 0.0 });
    cavity.SetPoint(v, 0.1 * cavity.Point(v));
  }
  vtkSmartPointer<vtkPolyData> input = ToPolyData(Concatenate(Concatenate(big, speck), cavity));
  ASSERT_EQ(Stats(input).Components, 3);
  const CleanRun run = Clean(input, 0.2);
  EXPECT_EQ(FieldCount(run.Surface, "ComponentsRemoved"), 1);
  EXPECT_EQ(FieldCount(run.Surface, "CavitiesRemoved"), 1);
  EXPECT_EQ(run.Surface->GetNumberOfPolys(), ToPolyData(big)->GetNumberOfPolys());
  EXPECT_EQ(Stats(run.Surface).Components, 1);
  const CleanRun keep = Clean(input, 0.05); // both are 0.1 wide (diagonal 0.17): kept
  EXPECT_EQ(Stats(keep.Surface).Components, 3);
}

TEST(TopologicalNoiseRemoval, PointDataFollowTheCopiedVertices)
{
  vtkSmartPointer<vtkPolyData> torus = ToPolyData(Torus(64, 32, 1.0, 0.35));
  vtkNew<vtkDoubleArray> xs;
  xs->SetName("x");
  for (vtkIdType i = 0; i < torus->GetNumberOfPoints(); ++i)
  {
    xs->InsertNextValue(torus->GetPoint(i)[0]);
  }
  torus->GetPointData()->AddArray(xs);
  const CleanRun run = Clean(torus, 0.8);
  ASSERT_EQ(FieldCount(run.Surface, "HandlesRemoved"), 1);
  EXPECT_GT(run.Surface->GetNumberOfPoints(), torus->GetNumberOfPoints()); // the cut's copies
  vtkDataArray* out = run.Surface->GetPointData()->GetArray("x");
  ASSERT_NE(out, nullptr);
  for (vtkIdType i = 0; i < run.Surface->GetNumberOfPoints(); ++i)
  {
    EXPECT_NEAR(out->GetTuple1(i), run.Surface->GetPoint(i)[0], 1e-6);
  }
}

TEST(TopologicalNoiseRemoval, Deterministic)
{
  vtkSmartPointer<vtkPolyData> cheese = LoadTestMesh("cheese");
  const CleanRun a = Clean(cheese, 0.05, true), b = Clean(cheese, 0.05, true);
  ASSERT_EQ(a.Surface->GetNumberOfPolys(), b.Surface->GetNumberOfPolys());
  const TriangleMesh ma = RawTriangleMesh(a.Surface), mb = RawTriangleMesh(b.Surface);
  EXPECT_EQ(ma.Triangles, mb.Triangles);
  EXPECT_EQ(ma.Points, mb.Points);
}

TEST(TopologicalNoiseRemoval, BadInputGivesDefinedOutput)
{
  vtkNew<vtkPolyData> empty;
  const CleanRun e = Clean(empty, 1.0);
  EXPECT_EQ(e.Surface->GetNumberOfPolys(), 0);
  EXPECT_FALSE(e.Messages->Warnings.empty() && e.Messages->Errors.empty());

  // Non-manifold edge: a warning, the fan is left alone.
  vtkSmartPointer<vtkPolyData> fan = ToPolyData(NonManifoldFan(3));
  const CleanRun f = Clean(fan, 10.0);
  EXPECT_FALSE(f.Messages->Warnings.empty());
  EXPECT_EQ(f.Surface->GetNumberOfPolys(), fan->GetNumberOfPolys());
}

// A noisy scan-like isosurface (handles, pinched vertices, non-manifold edges, a border), with
// SplitNonManifold off: a warning, no new non-manifold edge, the border kept, the genus never
// raised, every cut short.
TEST(TopologicalNoiseRemoval, NoisyScanWithNonManifoldPartsLocked)
{
  vtkSmartPointer<vtkPolyData> scan = NoisyScanIsosurface(40, 3);
  const TriangleMesh prepared = ToTriangleMesh(scan); // as the filter sees it
  const MeshStatistics before = MeshTopology(prepared).Statistics(prepared);
  ASSERT_GT(before.NonManifoldEdges, 0);
  const CleanRun run = Clean(scan, 0.03, true, /*removeComponents=*/false, /*splitNonManifold=*/false);
  const MeshStatistics after = Stats(run.Surface);
  EXPECT_FALSE(run.Messages->Warnings.empty());
  EXPECT_LE(after.NonManifoldEdges, before.NonManifoldEdges);
  EXPECT_EQ(after.BoundaryEdges, before.BoundaryEdges);
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(FieldCount(run.Surface, "NonManifoldEdgesSplit"), 0);
  // The relation above holds trivially when nothing is cut: the scan's noise must give cuts.
  EXPECT_GT(FieldCount(run.Surface, "HandlesRemoved"), 0);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic + 2 * FieldCount(run.Surface, "HandlesRemoved"));
}

// The same scan with the default SplitNonManifold: the non-manifold edges and vertices are split
// into sheets first (no border opened), the output is manifold where the split could pair, and
// every cut raises the Euler characteristic of the split mesh by 2.
TEST(TopologicalNoiseRemoval, NoisyScanSplitIntoManifoldSheets)
{
  vtkSmartPointer<vtkPolyData> scan = NoisyScanIsosurface(40, 3);
  const TriangleMesh prepared = ToTriangleMesh(scan);
  const MeshTopology topology(prepared);
  const MeshStatistics before = topology.Statistics(prepared);
  ASSERT_GT(before.NonManifoldEdges, 0);
  const ManifoldSplitResult split = SplitNonManifold(prepared, topology);
  const MeshStatistics sheets = ComputeMeshStatistics(split.Mesh);
  const CleanRun run = Clean(scan, 0.03, true, /*removeComponents=*/false);
  const MeshStatistics after = Stats(run.Surface);
  EXPECT_EQ(FieldCount(run.Surface, "NonManifoldEdgesSplit"), split.EdgesSplit);
  EXPECT_EQ(FieldCount(run.Surface, "NonManifoldVerticesSplit"), split.VerticesSplit);
  EXPECT_GT(split.EdgesSplit, 0);
  EXPECT_EQ(after.NonManifoldEdges, split.EdgesLeft);
  EXPECT_EQ(after.BoundaryEdges, before.BoundaryEdges);
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
  EXPECT_GT(FieldCount(run.Surface, "HandlesRemoved"), 0);
  EXPECT_EQ(after.EulerCharacteristic, sheets.EulerCharacteristic + 2 * FieldCount(run.Surface, "HandlesRemoved"));
  // The input's non-manifold edges are reported (by the input preparation); a warning that some
  // could not be split comes exactly when one could not.
  EXPECT_FALSE(run.Messages->Warnings.empty());
  bool leftReported = false;
  for (const std::string& warning : run.Messages->Warnings)
  {
    leftReported = leftReported || warning.find("could not be split") != std::string::npos;
  }
  EXPECT_EQ(leftReported, split.EdgesLeft > 0);
}

// CAD parts with drilled holes (CGAL's anchor, genus 4, and couplingdown, genus 9) at a feature size
// of 0.1 of the diagonal: the same genus change as vtkHoleBumpRemoval (Ho ch. 5, which finds the
// holes by their sharp rims) at the same size, with the fills within the feature size.
TEST(TopologicalNoiseRemoval, SameGenusChangeAsHoleBumpRemovalOnCadParts)
{
  for (const char* name : { "anchor", "couplingdown" })
  {
    vtkSmartPointer<vtkPolyData> part = LoadTestMesh(name);
    const MeshStatistics before = Stats(part);
    ASSERT_GT(before.Genus, 0) << name;
    const CleanRun run = Clean(part, 0.1, /*relative=*/true);
    vtkNew<vtkHoleBumpRemoval> holes;
    holes->SetInputData(part);
    holes->SetFeatureSize(0.1);
    holes->FeatureSizeIsRelativeOn();
    holes->Update();
    const MeshStatistics cleaned = Stats(run.Surface), reference = Stats(holes->GetOutput());
    EXPECT_LT(cleaned.Genus, before.Genus) << name;
    EXPECT_EQ(cleaned.Genus, reference.Genus) << name;
    ExpectCleanManifold(cleaned);
    const double alpha = FieldValues(run.Surface, "FeatureSize").at(0);
    EXPECT_LE(Hausdorff(part, run.Surface), alpha) << name;
  }
}

// Asked to abort at its first progress report: a warning and an empty output (the filter contract).
TEST(TopologicalNoiseRemoval, AbortGivesEmptyOutput)
{
  struct AbortAtProgress : vtkCommand
  {
    static AbortAtProgress* New() { return new AbortAtProgress; }
    void Execute(vtkObject* caller, unsigned long, void*) override
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
  };
  vtkNew<vtkTopologicalNoiseRemoval> filter;
  filter->SetInputData(ToPolyData(Torus(64, 32, 1.0, 0.35)));
  filter->SetFeatureSize(0.8);
  filter->FeatureSizeIsRelativeOff();
  vtkNew<AbortAtProgress> abort;
  vtkNew<MessageCounter> messages;
  filter->AddObserver(vtkCommand::ProgressEvent, abort);
  filter->AddObserver(vtkCommand::WarningEvent, messages);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_FALSE(messages->Warnings.empty());
}

// A separation search with a budget too small to decide (one triangle per side): the torus's
// meridian loop is kept and reported (LoopsKept, port 1 with Removed = 0), and nothing is cut.
TEST(TopologicalNoiseRemoval, UndecidedSeparationKeepsAndReportsTheLoop)
{
  vtkNew<vtkTopologicalNoiseRemoval> filter;
  vtkSmartPointer<vtkPolyData> torus = ToPolyData(Torus(64, 32, 1.0, 0.35));
  filter->SetInputData(torus);
  filter->SetFeatureSize(0.8);
  filter->FeatureSizeIsRelativeOff();
  filter->SetSeparationSearchBudget(1);
  filter->Update();
  vtkPolyData* surface = filter->GetOutput(0);
  vtkPolyData* loops = filter->GetOutput(1);
  EXPECT_EQ(filter->GetNumberOfHandlesRemoved(), 0);
  EXPECT_GE(filter->GetNumberOfLoopsKept(), 1);
  EXPECT_EQ(FieldCount(surface, "LoopsKept"), filter->GetNumberOfLoopsKept());
  EXPECT_EQ(Stats(surface).EulerCharacteristic, 0);
  EXPECT_EQ(surface->GetNumberOfPolys(), torus->GetNumberOfPolys());
  ASSERT_EQ(loops->GetNumberOfCells(), filter->GetNumberOfLoopsKept());
  vtkDataArray* removed = loops->GetCellData()->GetArray("Removed");
  ASSERT_NE(removed, nullptr);
  for (vtkIdType c = 0; c < loops->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(removed->GetTuple1(c), 0);
  }
  ExpectShortCutLoops(loops, 0.8);
}

// One pass that cuts: the regions near its cut are not grown again, which the filter must say (a
// warning) instead of reporting a finished clean-up; with passes to spare it says nothing.
TEST(TopologicalNoiseRemoval, PassLimitReachedIsReported)
{
  vtkSmartPointer<vtkPolyData> torus = ToPolyData(Torus(64, 32, 1.0, 0.35));
  for (int passes : { 1, 2 })
  {
    vtkNew<vtkTopologicalNoiseRemoval> filter;
    filter->SetInputData(torus);
    filter->SetFeatureSize(0.8);
    filter->FeatureSizeIsRelativeOff();
    filter->SetMaximumPasses(passes);
    vtkNew<MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->Update();
    EXPECT_EQ(filter->GetNumberOfHandlesRemoved(), 1) << passes;
    EXPECT_EQ(messages->Warnings.size(), passes == 1 ? 1u : 0u) << passes;
  }
}

// A survey limited to twice the feature size cannot size the plate's large hole (3.82 > 3.6): it
// says so in HandlesNotSized instead of listing fewer handles than the output has.
TEST(TopologicalNoiseRemoval, HandlesBeyondTheSurveyAreCounted)
{
  vtkSmartPointer<vtkPolyData> plate = ToPolyData(PlateWithSmallAndLargeHoles());
  vtkNew<vtkTopologicalNoiseRemoval> filter;
  filter->SetInputData(plate);
  filter->SetFeatureSize(1.8);
  filter->FeatureSizeIsRelativeOff();
  filter->SetKeptHandleSurveyFactor(2.0);
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  EXPECT_EQ(filter->GetOutputGenus(), 1);
  EXPECT_EQ(FieldValues(out, "KeptHandleSizes").size(), 0u);
  EXPECT_EQ(FieldCount(out, "HandlesNotSized"), 1);
  EXPECT_DOUBLE_EQ(FieldValues(out, "KeptHandleSurveySize").at(0), 3.6);
}

// The survey's rounds have the passes' limit too: a round stopped by it may miss kept handles,
// which the filter must say (a warning and SurveyPassLimitReached), and not with passes to spare.
TEST(TopologicalNoiseRemoval, SurveyPassLimitIsReported)
{
  vtkSmartPointer<vtkPolyData> torus = ToPolyData(Torus(64, 32, 1.0, 0.35));
  for (int passes : { 1, 2 })
  {
    vtkNew<vtkTopologicalNoiseRemoval> filter;
    filter->SetInputData(torus);
    filter->SetFeatureSize(0.6); // kept (meridian 0.7); the survey at 1.2 cuts it on its copy
    filter->FeatureSizeIsRelativeOff();
    filter->SetMaximumPasses(passes);
    vtkNew<MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->Update();
    EXPECT_EQ(filter->GetNumberOfHandlesRemoved(), 0) << passes;
    EXPECT_EQ(FieldCount(filter->GetOutput(), "SurveyPassLimitReached"), passes == 1 ? 1 : 0) << passes;
    EXPECT_EQ(messages->Warnings.size(), passes == 1 ? 1u : 0u) << passes;
  }
}
