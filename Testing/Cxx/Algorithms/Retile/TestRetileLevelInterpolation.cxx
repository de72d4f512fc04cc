// SPDX-License-Identifier: BSD-3-Clause
// vtkRetileLevelInterpolation (Turk 1992 sections 6.2-6.3): between two nested levels of vtkRetile,
// the fragment mesh has exactly the high-detail shape at T = 1 and the low-detail shape at T = 0
// (vtkSurfaceDeviation), stays a consistently oriented closed manifold of the same Euler
// characteristic for every T, moves continuously with T, tiles each high triangle; bad input.
#include "TestSupport.h"

#include "slodFragmentTracking.h"
#include "slodLevelInterpolation.h"
#include "slodMeshTopology.h"
#include "vtkRetile.h"
#include "vtkRetileLevelInterpolation.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkMath.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

using namespace slod;

namespace
{
struct Levels
{
  vtkSmartPointer<vtkPolyData> Low, High;
};

// Two nested levels of vtkRetile (lowCount and 4 * lowCount vertices).
Levels NestedLevels(vtkPolyData* input, vtkIdType highCount)
{
  vtkNew<vtkRetile> retile;
  retile->SetInputData(input);
  retile->SetNumberOfPoints(highCount);
  retile->GenerateNestedLevelsOn();
  retile->SetNumberOfNestedLevels(2);
  retile->SetNestedLevelRatio(4.0);
  retile->Update();
  Levels levels;
  vtkMultiBlockDataSet* blocks = retile->GetNestedLevels();
  if (blocks->GetNumberOfBlocks() == 2)
  {
    levels.Low = vtkPolyData::SafeDownCast(blocks->GetBlock(0));
    levels.High = vtkPolyData::SafeDownCast(blocks->GetBlock(1));
  }
  return levels;
}

vtkSmartPointer<vtkPolyData> Interpolate(const Levels& levels, double t, vtkRetileLevelInterpolation* filter)
{
  filter->SetHighDetailData(levels.High);
  filter->SetLowDetailData(levels.Low);
  filter->SetT(t);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(filter->GetOutput());
  return out;
}

// Symmetric Hausdorff distance relative to a's bounding-box diagonal.
double Hausdorff(vtkPolyData* a, vtkPolyData* b, double* ab = nullptr, double* ba = nullptr, double* mean = nullptr)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(a);
  deviation->SetComparedData(b);
  deviation->SetNumberOfSamples(100000);
  deviation->Update();
  if (ab)
  {
    *ab = deviation->GetHausdorffABRelative();
  }
  if (ba)
  {
    *ba = deviation->GetHausdorffBARelative();
  }
  if (mean)
  {
    *mean = deviation->GetMeanRelative();
  }
  return deviation->GetHausdorffRelative();
}

// How the correspondence is found: tracking the fragments through vtkRetile's recorded removals
// (section 6.2: T = 0 must be the low level to rounding), or the closest-point flattening without
// records (exact where it does not fold; elsewhere regression bounds, the goal reported as not met).
enum class Path
{
  Tracked,
  ClosestPointExact,
  ClosestPointBounded
};

// Both ends exact, every T a consistently oriented manifold with the input's Euler
// characteristic, continuous in T, each high triangle tiled by its fragments.
void CheckInterpolation(const char* name, const Levels& levels, Path path)
{
  ASSERT_TRUE(levels.Low && levels.High) << name;
  const TriangleMesh high = slodtest::ToTriangleMesh(levels.High);
  const MeshStatistics highStats = ComputeMeshStatistics(high);
  const bool exactLow = path != Path::ClosestPointBounded;

  vtkNew<vtkRetileLevelInterpolation> filter;
  filter->SetUseRemovalRecords(path == Path::Tracked);
  vtkNew<slodtest::MessageCounter> messages;
  filter->AddObserver(vtkCommand::ErrorEvent, messages);
  filter->AddObserver(vtkCommand::WarningEvent, messages);
  const auto start = std::chrono::steady_clock::now();
  auto atOne = Interpolate(levels, 1.0, filter);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(messages->Errors.empty()) << name << ": " << messages->Errors.front();
  ASSERT_GT(atOne->GetNumberOfPolys(), 0) << name;
  const vtkIdType fragments = filter->GetNumberOfFragments();
  const vtkIdType inconsistent = filter->GetNumberOfInconsistentFragments();
  const vtkIdType untraced = filter->GetNumberOfUntracedEdges();
  // The tracked path replays one removal per vertex the low level does not have.
  EXPECT_EQ(filter->GetNumberOfTrackedRemovals(),
    path == Path::Tracked ? levels.High->GetNumberOfPoints() - levels.Low->GetNumberOfPoints() : 0)
    << name;
  if (exactLow)
  {
    EXPECT_EQ(untraced, 0) << name;
    EXPECT_EQ(inconsistent, 0) << name;
  }
  else
  {
    // Regression bounds (measured 2026-11-22: inconsistent fragments bunny00 8 of 8633, synthetic:60
    // 1 of 10208; 0 untraced edges).
    EXPECT_LE(inconsistent, fragments / 100) << name;
    EXPECT_LE(untraced, levels.High->GetNumberOfPolys() / 500) << name;
  }
  EXPECT_EQ(filter->GetNumberOfSharedVertices(), levels.Low->GetNumberOfPoints()) << name;
  EXPECT_EQ(filter->GetNumberOfSharedVertices() + filter->GetNumberOfFlattenedVertices(),
    levels.High->GetNumberOfPoints() + filter->GetNumberOfInsertedVertices())
    << name;
  EXPECT_LE(filter->GetNumberOfInsertedVertices(), levels.Low->GetNumberOfPoints() / 50) << name;
  EXPECT_GE(filter->GetNumberOfFragments(), levels.High->GetNumberOfPolys()) << name;
  std::printf("%s: low %lld / high %lld triangles -> %lld fragments, %lld output triangles, %lld crossings, "
              "%lld flattened vertices, %lld inserted, %.3f s\n",
    name, static_cast<long long>(levels.Low->GetNumberOfPolys()),
    static_cast<long long>(levels.High->GetNumberOfPolys()),
    static_cast<long long>(filter->GetNumberOfFragments()), static_cast<long long>(atOne->GetNumberOfPolys()),
    static_cast<long long>(filter->GetNumberOfCrossings()),
    static_cast<long long>(filter->GetNumberOfFlattenedVertices()),
    static_cast<long long>(filter->GetNumberOfInsertedVertices()), seconds);

  // T = 1: the high-detail shape; T = 0: the low-detail shape (both ways).
  double ab = 0, ba = 0;
  const double atHigh = Hausdorff(levels.High, atOne, &ab, &ba);
  std::printf("%s: T=1 Hausdorff to high %.3g (high->out %.3g, out->high %.3g)\n", name, atHigh, ab, ba);
  EXPECT_LT(atHigh, 1e-9) << name;
  auto atZero = Interpolate(levels, 0.0, filter);
  double mean = 0;
  const double atLow = Hausdorff(levels.Low, atZero, &ab, &ba, &mean);
  const double highVsLow = Hausdorff(levels.High, levels.Low);
  std::printf("%s: T=0 Hausdorff to low %.3g (low->out %.3g, out->low %.3g), mean %.3g; high vs low %.3g; "
              "%lld inconsistent fragments, %lld untraced edges\n",
    name, atLow, ab, ba, mean, highVsLow, static_cast<long long>(inconsistent), static_cast<long long>(untraced));
  if (path == Path::Tracked)
  {
    EXPECT_LT(atLow, 1e-11) << name; // rounding only: every fragment lies in one low triangle
  }
  else if (exactLow)
  {
    EXPECT_LT(atLow, 1e-9) << name;
  }
  else
  {
    if (atLow >= 1e-9)
    {
      std::printf("GOAL NOT MET (%s): T=0 Hausdorff to the low level %.3g, goal < 1e-9 (folds of the "
                  "closest-point flattening)\n",
        name, atLow);
    }
    EXPECT_LT(atLow, highVsLow) << name; // closer to the low level than the high level is
    EXPECT_LT(mean, 1e-4) << name;       // the departure is local
  }

  // Fragments tile each high triangle: at T = 1 their areas add up to its area.
  const TriangleMesh one = slodtest::RawTriangleMesh(atOne);
  auto* highTriangle = vtkIdTypeArray::SafeDownCast(atOne->GetCellData()->GetArray("HighTriangle"));
  ASSERT_NE(highTriangle, nullptr);
  ASSERT_EQ(highTriangle->GetNumberOfTuples(), one.NumberOfTriangles());
  std::vector<double> area(static_cast<size_t>(high.NumberOfTriangles()), 0.0);
  for (Index c = 0; c < one.NumberOfTriangles(); ++c)
  {
    area[highTriangle->GetValue(c)] += one.TriangleArea(c);
  }
  double worst = 0;
  for (Index t = 0; t < high.NumberOfTriangles(); ++t)
  {
    worst = std::max(worst, std::abs(area[t] - high.TriangleArea(t)) / high.TriangleArea(t));
  }
  EXPECT_LT(worst, 1e-9) << name;
  // Every output triangle's LowTriangle is valid (it lies on one low triangle at T = 0).
  auto* lowTriangle = vtkIdTypeArray::SafeDownCast(atOne->GetCellData()->GetArray("LowTriangle"));
  ASSERT_NE(lowTriangle, nullptr);
  if (inconsistent == 0)
  {
    EXPECT_GE(lowTriangle->GetRange()[0], 0) << name;
  }
  ASSERT_NE(atOne->GetPointData()->GetArray("LowPosition"), nullptr);
  ASSERT_NE(atOne->GetPointData()->GetArray("HighPosition"), nullptr);

  // Intermediate T: closed, manifold, consistently oriented, same Euler characteristic and genus.
  for (double t : { 0.0, 0.25, 0.5, 0.75, 1.0 })
  {
    auto mid = Interpolate(levels, t, filter);
    const TriangleMesh mesh = slodtest::RawTriangleMesh(mid);
    ASSERT_EQ(mesh.NumberOfPoints(), one.NumberOfPoints()) << name << " T=" << t;
    ASSERT_EQ(mesh.Triangles, one.Triangles) << name << " T=" << t; // same connectivity for every T
    const MeshStatistics stats = ComputeMeshStatistics(mesh);
    EXPECT_EQ(stats.NonManifoldEdges, 0) << name << " T=" << t;
    EXPECT_EQ(stats.NonManifoldVertices, 0) << name << " T=" << t;
    EXPECT_EQ(stats.BoundaryEdges, highStats.BoundaryEdges) << name << " T=" << t;
    EXPECT_EQ(stats.InconsistentlyOrientedEdges, 0) << name << " T=" << t;
    EXPECT_EQ(stats.EulerCharacteristic, highStats.EulerCharacteristic) << name << " T=" << t;
    EXPECT_EQ(stats.Genus, highStats.Genus) << name << " T=" << t;
    EXPECT_EQ(stats.Components, highStats.Components) << name << " T=" << t;
  }

  // Continuity: a step of 0.01 in T moves no vertex more than 0.01 of the largest end-to-end move.
  vtkDataArray* lowPos = atOne->GetPointData()->GetArray("LowPosition");
  vtkDataArray* highPos = atOne->GetPointData()->GetArray("HighPosition");
  double largest = 0;
  for (vtkIdType i = 0; i < lowPos->GetNumberOfTuples(); ++i)
  {
    double a[3], b[3];
    lowPos->GetTuple(i, a);
    highPos->GetTuple(i, b);
    largest = std::max(largest, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
  }
  EXPECT_GT(largest, 0) << name;
  double worstStep = 0;
  auto previous = Interpolate(levels, 0.0, filter);
  for (int k = 1; k <= 100; k += 11)
  {
    auto before = Interpolate(levels, 0.01 * (k - 1), filter);
    auto after = Interpolate(levels, 0.01 * k, filter);
    for (vtkIdType i = 0; i < after->GetNumberOfPoints(); ++i)
    {
      double a[3], b[3];
      before->GetPoint(i, a);
      after->GetPoint(i, b);
      worstStep = std::max(worstStep, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
    }
  }
  std::printf("%s: largest end-to-end move %.3g (relative %.3g), largest move per 0.01 step %.3g\n", name, largest,
    largest / high.BoundingBoxDiagonal(), worstStep);
  EXPECT_LE(worstStep, 0.01 * largest * (1 + 1e-9)) << name;
}
} // namespace

TEST(RetileLevelInterpolation, Bunny00)
{
  CheckInterpolation("bunny00", NestedLevels(slodtest::LoadTestMesh("bunny00"), 2000), Path::Tracked);
}

// Creases: every T manifold (a non-manifold edge appeared there before crowded candidates were
// separated in the re-tiling).
TEST(RetileLevelInterpolation, FandiskCreases)
{
  CheckInterpolation("fandisk", NestedLevels(slodtest::LoadTestMesh("fandisk"), 2000), Path::Tracked);
}

// Genus 2 with tunnels narrower than the coarse spacing (retained vertices), and a scan with thin
// limbs: the closest-point flattening folded most there (80 and 41 inconsistent fragments).
TEST(RetileLevelInterpolation, FemurAndArmadillo)
{
  CheckInterpolation("femur", NestedLevels(slodtest::LoadTestMesh("femur"), 2000), Path::Tracked);
  CheckInterpolation("armadillo", NestedLevels(slodtest::LoadTestMesh("armadillo"), 2000), Path::Tracked);
}

TEST(RetileLevelInterpolation, TorusGenusOne)
{
  CheckInterpolation("torus", NestedLevels(slodtest::ToPolyData(slodtest::Torus(64, 24)), 800), Path::Tracked);
}

TEST(RetileLevelInterpolation, SphereExact)
{
  CheckInterpolation("sphere", NestedLevels(slodtest::ToPolyData(slodtest::Sphere(64, 64)), 2000), Path::Tracked);
}

TEST(RetileLevelInterpolation, SyntheticIsosurface)
{
  CheckInterpolation("synthetic:60", NestedLevels(slodtest::SyntheticIsosurface(60), 2400), Path::Tracked);
}

// Without the records (UseRemovalRecords off, or two meshes from elsewhere): the closest-point
// flattening, exact on a sphere, bounded where the low level bends sharply.
TEST(RetileLevelInterpolation, ClosestPointWithoutRecords)
{
  CheckInterpolation(
    "sphere closest point", NestedLevels(slodtest::ToPolyData(slodtest::Sphere(64, 64)), 2000), Path::ClosestPointExact);
  CheckInterpolation("bunny00 closest point", NestedLevels(slodtest::LoadTestMesh("bunny00"), 2000),
    Path::ClosestPointBounded);
}

// Records that do not turn the high level into the low one (edited, or of another pair) are not
// trusted: a warning, and the closest-point flattening.
TEST(RetileLevelInterpolation, RecordsThatDoNotReplayFallBack)
{
  const Levels levels = NestedLevels(slodtest::ToPolyData(slodtest::Torus(48, 16)), 600);
  ASSERT_TRUE(levels.High);
  auto edited = vtkSmartPointer<vtkPolyData>::New();
  edited->DeepCopy(levels.Low);
  auto* records = vtkIdTypeArray::SafeDownCast(edited->GetFieldData()->GetAbstractArray("RetileRemovals"));
  ASSERT_NE(records, nullptr);
  ASSERT_GT(records->GetNumberOfTuples(), 1);
  const vtkIdType first = records->GetValue(0);
  records->SetValue(0, records->GetValue(2)); // the first two removals swapped
  records->SetValue(2, first);
  const vtkIdType firstTarget = records->GetValue(1);
  records->SetValue(1, records->GetValue(3));
  records->SetValue(3, firstTarget);
  records->SetValue(2 * records->GetNumberOfTuples() - 2, 0); // the last removes vertex 0
  vtkNew<vtkRetileLevelInterpolation> filter;
  vtkNew<slodtest::MessageCounter> messages;
  filter->AddObserver(vtkCommand::WarningEvent, messages);
  filter->AddObserver(vtkCommand::ErrorEvent, messages);
  filter->SetHighDetailData(levels.High);
  filter->SetLowDetailData(edited);
  filter->Update();
  EXPECT_EQ(messages->Errors.size(), 0u);
  ASSERT_GE(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings.front().find("RetileRemovals"), std::string::npos) << messages->Warnings.front();
  EXPECT_EQ(filter->GetNumberOfTrackedRemovals(), 0);
  EXPECT_GT(filter->GetOutput()->GetNumberOfPolys(), levels.High->GetNumberOfPolys());
}

namespace
{
vtkSmartPointer<vtkMultiBlockDataSet> ThreeLevels(vtkPolyData* input, vtkIdType finest)
{
  vtkNew<vtkRetile> retile;
  retile->SetInputData(input);
  retile->SetNumberOfPoints(finest);
  retile->GenerateNestedLevelsOn();
  retile->SetNumberOfNestedLevels(3);
  retile->SetNestedLevelRatio(3.0);
  retile->Update();
  return retile->GetNestedLevels();
}

Levels Pair(vtkMultiBlockDataSet* blocks, unsigned int low, unsigned int high)
{
  Levels levels;
  levels.Low = vtkPolyData::SafeDownCast(blocks->GetBlock(low));
  levels.High = vtkPolyData::SafeDownCast(blocks->GetBlock(high));
  return levels;
}
} // namespace

// Section 6.2 across several levels: each level's records chain those of the finer levels, so
// every pair of nested levels (0 with 2 too) is tracked, with T = 0 the low level exactly (until
// 2026-12-03 level 0 with level 2 fell back to the closest-point path).
TEST(RetileLevelInterpolation, AnyPairOfNestedLevelsIsTracked)
{
  for (const char* name : { "bunny00", "femur" })
  {
    vtkSmartPointer<vtkMultiBlockDataSet> blocks = ThreeLevels(slodtest::LoadTestMesh(name), 1800);
    ASSERT_EQ(blocks->GetNumberOfBlocks(), 3u) << name;
    for (const auto& pair : { std::make_pair(0u, 2u), std::make_pair(1u, 2u), std::make_pair(0u, 1u) })
    {
      const std::string label = std::string(name) + " levels " + std::to_string(pair.first) + "-" + std::to_string(pair.second);
      CheckInterpolation(label.c_str(), Pair(blocks, pair.first, pair.second), Path::Tracked);
    }
  }
  vtkSmartPointer<vtkMultiBlockDataSet> torus = ThreeLevels(slodtest::ToPolyData(slodtest::Torus(48, 16)), 720);
  ASSERT_EQ(torus->GetNumberOfBlocks(), 3u);
  CheckInterpolation("torus levels 0-2", Pair(torus, 0, 2), Path::Tracked);
}

// An open surface (mushroom: one border loop): the coarser levels remove border vertices only
// along the border, so their records replay (until 2026-12-03 a border vertex collapsed onto an
// inner neighbour, or a lone border triangle removed, made the tracking fall back to the
// closest-point path). Every level keeps the input's border loops; every pair of levels is
// tracked with no inconsistent fragment. The T = 0 shape is the low level except at a spot or two
// (2.8e-11 and 3.9e-8 relative, mean 2e-17: open, Documentation/Retile.md), so exactness is
// reported (GOAL NOT MET) rather than asserted there.
TEST(RetileLevelInterpolation, OpenSurfaceLevelsAreTracked)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("mushroom");
  const MeshStatistics inputStats = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
  ASSERT_GT(inputStats.BoundaryEdges, 0);
  vtkSmartPointer<vtkMultiBlockDataSet> blocks = ThreeLevels(input, 900);
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 3u);
  for (unsigned int level = 0; level < 3; ++level)
  {
    const MeshStatistics stats = ComputeMeshStatistics(slodtest::ToTriangleMesh(
      vtkPolyData::SafeDownCast(blocks->GetBlock(level))));
    EXPECT_EQ(stats.BoundaryLoops, inputStats.BoundaryLoops) << "level " << level;
    EXPECT_EQ(stats.EulerCharacteristic, inputStats.EulerCharacteristic) << "level " << level;
  }
  for (const auto& pair : { std::make_pair(0u, 2u), std::make_pair(1u, 2u), std::make_pair(0u, 1u) })
  {
    SCOPED_TRACE("mushroom levels " + std::to_string(pair.first) + "-" + std::to_string(pair.second));
    const Levels levels = Pair(blocks, pair.first, pair.second);
    vtkNew<vtkRetileLevelInterpolation> filter;
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    auto atOne = Interpolate(levels, 1.0, filter);
    EXPECT_TRUE(messages->Warnings.empty());
    EXPECT_EQ(filter->GetNumberOfTrackedRemovals(),
      levels.High->GetNumberOfPoints() - levels.Low->GetNumberOfPoints());
    EXPECT_EQ(filter->GetNumberOfInconsistentFragments(), 0);
    EXPECT_EQ(filter->GetNumberOfUntracedEdges(), 0);
    EXPECT_LT(Hausdorff(levels.High, atOne), 1e-9);
    auto atZero = Interpolate(levels, 0.0, filter);
    double mean = 0;
    const double atLow = Hausdorff(levels.Low, atZero, nullptr, nullptr, &mean);
    std::printf("mushroom levels %u-%u: T=0 Hausdorff to low %.3g, mean %.3g\n", pair.first, pair.second, atLow, mean);
    if (atLow >= 1e-11)
    {
      std::printf("GOAL NOT MET (mushroom levels %u-%u): T=0 Hausdorff to the low level %.3g, goal < 1e-11\n",
        pair.first, pair.second, atLow);
    }
    EXPECT_LT(atLow, 1e-3 * Hausdorff(levels.High, levels.Low)); // a spot, not a different shape
    EXPECT_LT(mean, 1e-12);
  }
}

namespace
{
std::vector<Index> Records(vtkPolyData* low)
{
  auto* records = vtkIdTypeArray::SafeDownCast(low->GetFieldData()->GetAbstractArray("RetileRemovals"));
  std::vector<Index> removals;
  for (vtkIdType i = 0; records && i < records->GetNumberOfValues(); ++i)
  {
    removals.push_back(static_cast<Index>(records->GetValue(i)));
  }
  return removals;
}
} // namespace

// The fragment tracker and the closest-point path report progress (non-decreasing, to 1) and stop
// when it asks to; the filter then gives the contract's abort result (empty output, one warning).
TEST(RetileLevelInterpolation, ProgressAndAbort)
{
  const Levels levels = NestedLevels(slodtest::LoadTestMesh("bunny00"), 2000);
  ASSERT_TRUE(levels.High);
  const TriangleMesh high = slodtest::ToTriangleMesh(levels.High), low = slodtest::ToTriangleMesh(levels.Low);
  const std::vector<Index> removals = Records(levels.Low);
  ASSERT_FALSE(removals.empty());
  for (int path = 0; path < 2; ++path)
  {
    std::vector<double> fractions;
    auto record = [&](double f) {
      fractions.push_back(f);
      return true;
    };
    LevelInterpolation result;
    path == 0 ? TrackLevels(high, low, removals, result, record) : InterpolateLevels(high, low, result, record);
    ASSERT_TRUE(result.Valid) << path << ": " << result.Error;
    ASSERT_GE(fractions.size(), 3u) << path;
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end())) << path;
    EXPECT_EQ(fractions.back(), 1.0) << path;
    int calls = 0;
    auto stop = [&](double) { return ++calls < 2; };
    path == 0 ? TrackLevels(high, low, removals, result, stop) : InterpolateLevels(high, low, result, stop);
    EXPECT_TRUE(result.Aborted) << path;
    EXPECT_FALSE(result.Valid) << path;
    EXPECT_TRUE(result.Error.empty()) << path << ": " << result.Error;
    EXPECT_EQ(calls, 2) << path;
  }
  for (bool useRecords : { true, false })
  {
    vtkNew<vtkRetileLevelInterpolation> filter;
    filter->SetUseRemovalRecords(useRecords);
    vtkNew<slodtest::AbortAtFirstProgress> observer;
    filter->AddObserver(vtkCommand::ProgressEvent, observer);
    filter->AddObserver(vtkCommand::WarningEvent, observer);
    filter->SetHighDetailData(levels.High);
    filter->SetLowDetailData(levels.Low);
    filter->Update();
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << useRecords;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0) << useRecords;
    EXPECT_EQ(observer->AbortWarnings, 1) << useRecords;
  }
}

TEST(RetileLevelInterpolation, SameLevelIsIdentity)
{
  // Interpolating a level with itself: no vertex flattened, no crossing, one fragment per triangle.
  Levels levels = NestedLevels(slodtest::ToPolyData(slodtest::Sphere(32, 32)), 400);
  ASSERT_TRUE(levels.High);
  levels.Low = levels.High;
  vtkNew<vtkRetileLevelInterpolation> filter;
  auto out = Interpolate(levels, 0.0, filter);
  EXPECT_EQ(filter->GetNumberOfFlattenedVertices(), 0);
  EXPECT_EQ(filter->GetNumberOfCrossings(), 0);
  EXPECT_EQ(filter->GetNumberOfFragments(), levels.High->GetNumberOfPolys());
  EXPECT_EQ(out->GetNumberOfPolys(), levels.High->GetNumberOfPolys());
}

TEST(RetileLevelInterpolation, Deterministic)
{
  const Levels levels = NestedLevels(slodtest::ToPolyData(slodtest::Torus(48, 16)), 600);
  ASSERT_TRUE(levels.High);
  LevelInterpolation a, b;
  InterpolateLevels(slodtest::ToTriangleMesh(levels.High), slodtest::ToTriangleMesh(levels.Low), a);
  InterpolateLevels(slodtest::ToTriangleMesh(levels.High), slodtest::ToTriangleMesh(levels.Low), b);
  ASSERT_TRUE(a.Valid);
  EXPECT_EQ(a.Triangles, b.Triangles);
  EXPECT_EQ(a.LowPositions, b.LowPositions);
  EXPECT_EQ(a.HighPositions, b.HighPositions);
  // Evaluate gives the same mesh as the filter's arithmetic at the ends.
  TriangleMesh atOne;
  a.Evaluate(1.0, atOne);
  EXPECT_EQ(atOne.Points, a.HighPositions);
}

TEST(RetileLevelInterpolation, CoreRejectsBadInput)
{
  LevelInterpolation result;
  InterpolateLevels(TriangleMesh(), slodtest::Tetrahedron(), result);
  EXPECT_FALSE(result.Valid);
  EXPECT_FALSE(result.Error.empty());
  InterpolateLevels(slodtest::Sphere(16, 16), slodtest::Tetrahedron(), result);
  EXPECT_FALSE(result.Valid);
  EXPECT_NE(result.Error.find("not nested"), std::string::npos) << result.Error;
}

TEST(RetileLevelInterpolation, FilterBadInputGivesErrorAndEmptyOutput)
{
  const Levels levels = NestedLevels(slodtest::ToPolyData(slodtest::Sphere(32, 32)), 400);
  ASSERT_TRUE(levels.High);
  auto other = slodtest::ToPolyData(slodtest::Torus(32, 12));
  vtkNew<vtkPolyData> empty;
  const std::pair<vtkPolyData*, vtkPolyData*> cases[] = { { empty, levels.Low }, { levels.High, empty },
    { levels.High, other }, { levels.Low, levels.High } };
  for (const auto& c : cases)
  {
    vtkNew<vtkRetileLevelInterpolation> filter;
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::ErrorEvent, messages);
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->SetHighDetailData(c.first);
    filter->SetLowDetailData(c.second);
    filter->SetT(0.5);
    filter->Update();
    EXPECT_EQ(messages->Errors.size(), 1u);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
  }
  // Missing input on port 1.
  vtkNew<vtkRetileLevelInterpolation> filter;
  vtkNew<slodtest::MessageCounter> messages;
  filter->AddObserver(vtkCommand::ErrorEvent, messages);
  filter->SetHighDetailData(levels.High);
  filter->Update(); // the pipeline reports the missing connection
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}
