// Tests of the topology simplification of Ho 1999, chapter 5 (slodTopologySimplification and
// vtkHoleBumpRemoval): holes, bumps, cavities and cracks on programmatic block models (counted
// exactly), genus after removal, manifold and watertight output, triangle counts (a plate with
// holes becomes a 12-triangle box), the outer profile kept, features above alpha kept,
// determinism, bad input, and a comparison with vtkDecimatePro / vtkQuadricDecimation.
#include "TestSupport.h"

#include "slodBlockModel.h"
#include "slodMeshTopology.h"
#include "slodTopologySimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkQuadricDecimation.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

using namespace slod;
using namespace slodtest;

namespace
{
MeshStatistics Stats(const TriangleMesh& mesh)
{
  TriangleMesh copy = mesh;
  copy.RemoveUnusedPoints();
  return MeshTopology(copy).Statistics(copy);
}

TriangleMesh ResultMesh(const TriangleMesh& input, const TopologySimplificationResult& result)
{
  TriangleMesh out;
  out.Points = input.Points;
  out.Triangles = result.Triangles;
  out.RemoveUnusedPoints();
  return out;
}

void ExpectClosedManifold(const MeshStatistics& s)
{
  EXPECT_EQ(s.BoundaryEdges, 0);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.NonManifoldVertices, 0);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(s.DegenerateTriangles, 0);
}

// Heights of a (2k+1) x (2k+1) plate: `value` at the odd cells.
std::vector<double> PlateHeights(int k, double plate, double value)
{
  const int n = 2 * k + 1;
  std::vector<double> h(size_t(n) * n, plate);
  for (int j = 1; j < n; j += 2)
  {
    for (int i = 1; i < n; i += 2)
    {
      h[size_t(i) + size_t(n) * j] = value;
    }
  }
  return h;
}

TopologySimplificationResult Simplify(const TriangleMesh& mesh, double alpha,
  TopologyCompletion completion = TopologyCompletion::TriangulatePatches)
{
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = alpha;
  p.Completion = completion;
  TopologySimplificationResult r;
  EXPECT_TRUE(TopologySimplifier().Run(mesh, p, r));
  return r;
}

Index Count(const TopologySimplificationResult& r, TopologyFeatureKind kind, bool removed)
{
  return removed ? r.Removed[int(kind)] : r.Detected[int(kind)];
}

// Symmetric Hausdorff distance (absolute) between two meshes, sampled by vtkSurfaceDeviation.
double Hausdorff(const TriangleMesh& a, const TriangleMesh& b, double* ab = nullptr)
{
  vtkNew<vtkSurfaceDeviation> d;
  d->SetReferenceData(ToPolyData(a));
  d->SetComparedData(ToPolyData(b));
  d->SetNumberOfSamples(20000);
  d->Update();
  if (ab)
  {
    *ab = d->GetHausdorffAB();
  }
  return d->GetHausdorff();
}

// A 9 x 9 plate with one 3 x 3 hole in the middle and four 1 x 1 holes near the corners.
TriangleMesh LargeAndSmallHoles(int subdivisions)
{
  std::vector<double> h(81, 0.5);
  for (int j = 3; j < 6; ++j)
  {
    for (int i = 3; i < 6; ++i)
    {
      h[size_t(i) + 9 * size_t(j)] = 0;
    }
  }
  h[1 + 9] = h[7 + 9] = h[1 + 9 * 7] = h[7 + 9 * 7] = 0;
  return BlockModel(9, 9, h, 1.0, subdivisions);
}
} // namespace


TEST(BlockModel, ClosedModelsWithTheExpectedGenus)
{
  for (int sub = 1; sub <= 3; ++sub)
  {
    const MeshStatistics s = Stats(PlateWithHoles(3, 2, 0.5, sub));
    ExpectClosedManifold(s);
    EXPECT_EQ(s.Components, 1);
    EXPECT_EQ(s.Genus, 6);
  }
  const MeshStatistics round = Stats(PlateWithRoundHoles(3, 2, 0.25, 16, 0.5));
  ExpectClosedManifold(round);
  EXPECT_EQ(round.Genus, 6);
  const MeshStatistics bumps = Stats(BlockModel(7, 7, PlateHeights(3, 1.0, 1.4), 1.0, 2));
  ExpectClosedManifold(bumps);
  EXPECT_EQ(bumps.Genus, 0);
  const MeshStatistics large = Stats(LargeAndSmallHoles(2));
  ExpectClosedManifold(large);
  EXPECT_EQ(large.Genus, 5);
}

// The Fixture experiment: a plate with a grid of small holes becomes the 12-triangle box.
TEST(TopologySimplification, PlateHolesRemovedDownToTwelveTriangles)
{
  for (int sub = 1; sub <= 4; ++sub)
  {
    SCOPED_TRACE(sub);
    const TriangleMesh plate = PlateWithHoles(3, 3, 0.5, sub);
    const TopologySimplificationResult r = Simplify(plate, 2.0); // holes: diameter ~1.41
    EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, false), 9);
    EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), 9);
    EXPECT_EQ(Count(r, TopologyFeatureKind::Bump, false), 0);
    EXPECT_EQ(Count(r, TopologyFeatureKind::Cavity, false), 0);
    EXPECT_EQ(Count(r, TopologyFeatureKind::Crack, false), 0);
    EXPECT_EQ(r.Loops.size(), 18u); // two rims per hole
    const MeshStatistics s = Stats(ResultMesh(plate, r));
    ExpectClosedManifold(s);
    EXPECT_EQ(s.Genus, 0);
    EXPECT_EQ(s.Triangles, 12);
    EXPECT_EQ(r.MergedPatches, 6);
  }
}

TEST(TopologySimplification, RoundHolesRemoved)
{
  const TriangleMesh plate = PlateWithRoundHoles(4, 4, 0.3, 24, 0.3);
  const TopologySimplificationResult r = Simplify(plate, 0.8); // holes: diameter 0.6
  EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, false), 16);
  EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), 16);
  const MeshStatistics s = Stats(ResultMesh(plate, r));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.Triangles, 12);
  // Below alpha nothing goes: the output keeps the genus (profiles triangulated exactly).
  const TopologySimplificationResult kept = Simplify(plate, 0.5);
  EXPECT_EQ(Count(kept, TopologyFeatureKind::Hole, false), 16);
  EXPECT_EQ(Count(kept, TopologyFeatureKind::Hole, true), 0);
  const MeshStatistics k = Stats(ResultMesh(plate, kept));
  ExpectClosedManifold(k);
  EXPECT_EQ(k.Genus, 16);
}

// The Battery experiment: bumps on top of a box; and the same with cavities.
TEST(TopologySimplification, BumpsAndCavitiesRemoved)
{
  for (int sub = 1; sub <= 3; ++sub)
  {
    SCOPED_TRACE(sub);
    const TriangleMesh bumps = BlockModel(7, 7, PlateHeights(3, 1.0, 1.4), 1.0, sub);
    const TopologySimplificationResult b = Simplify(bumps, 2.0);
    EXPECT_EQ(Count(b, TopologyFeatureKind::Bump, false), 9);
    EXPECT_EQ(Count(b, TopologyFeatureKind::Bump, true), 9);
    EXPECT_EQ(Count(b, TopologyFeatureKind::Cavity, false), 0);
    EXPECT_EQ(Count(b, TopologyFeatureKind::Hole, false), 0);
    MeshStatistics s = Stats(ResultMesh(bumps, b));
    ExpectClosedManifold(s);
    EXPECT_EQ(s.Genus, 0);
    EXPECT_EQ(s.Triangles, 12);

    const TriangleMesh cavities = BlockModel(7, 7, PlateHeights(3, 1.0, 0.6), 1.0, sub);
    const TopologySimplificationResult c = Simplify(cavities, 2.0);
    EXPECT_EQ(Count(c, TopologyFeatureKind::Cavity, false), 9);
    EXPECT_EQ(Count(c, TopologyFeatureKind::Cavity, true), 9);
    EXPECT_EQ(Count(c, TopologyFeatureKind::Bump, false), 0);
    s = Stats(ResultMesh(cavities, c));
    ExpectClosedManifold(s);
    EXPECT_EQ(s.Triangles, 12);
  }
}

TEST(TopologySimplification, MixedFeaturesCountedExactly)
{
  std::vector<double> h = PlateHeights(3, 1.0, 1.4); // 9 bumps ...
  h[1 + 7 * 1] = 0.6;                                // ... one a cavity
  h[3 + 7 * 3] = 0.0;                                // ... one a hole
  h[5 + 7 * 5] = 0.5;                                // ... one a cavity
  const TriangleMesh mesh = BlockModel(7, 7, h, 1.0, 2);
  ASSERT_EQ(Stats(mesh).Genus, 1);
  const TopologySimplificationResult r = Simplify(mesh, 2.0);
  EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), 1);
  EXPECT_EQ(Count(r, TopologyFeatureKind::Bump, true), 6);
  EXPECT_EQ(Count(r, TopologyFeatureKind::Cavity, true), 2);
  const MeshStatistics s = Stats(ResultMesh(mesh, r));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.Triangles, 12);
  // Only bumps: holes and cavities stay.
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = 2.0;
  p.RemoveHoles = false;
  p.RemoveCavities = false;
  TopologySimplificationResult onlyBumps;
  ASSERT_TRUE(TopologySimplifier().Run(mesh, p, onlyBumps));
  EXPECT_EQ(Count(onlyBumps, TopologyFeatureKind::Bump, true), 6);
  EXPECT_EQ(Count(onlyBumps, TopologyFeatureKind::Hole, true), 0);
  EXPECT_EQ(Count(onlyBumps, TopologyFeatureKind::Cavity, true), 0);
  EXPECT_EQ(Stats(ResultMesh(mesh, onlyBumps)).Genus, 1);
}

// The Disk experiment: alpha selects which holes go; the genus drops by the number removed.
TEST(TopologySimplification, AlphaSelectsHoles)
{
  const TriangleMesh mesh = LargeAndSmallHoles(2);
  const TopologySimplificationResult small = Simplify(mesh, 2.0);
  EXPECT_EQ(Count(small, TopologyFeatureKind::Hole, false), 5);
  EXPECT_EQ(Count(small, TopologyFeatureKind::Hole, true), 4);
  for (const TopologyFeature& f : small.Features)
  {
    EXPECT_EQ(f.Removed, f.Size < 2.0);
    EXPECT_EQ(f.Removed, f.Reason.empty());
  }
  MeshStatistics s = Stats(ResultMesh(mesh, small));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 1);
  // The large hole is kept exactly: its rim vertices are still there.
  const TopologySimplificationResult all = Simplify(mesh, 5.0);
  EXPECT_EQ(Count(all, TopologyFeatureKind::Hole, true), 5);
  s = Stats(ResultMesh(mesh, all));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.Triangles, 12);
}

// Keeping the triangles: the output is exactly the plate without holes (the outer profile is
// kept to rounding), made of input triangles and the fills.
TEST(TopologySimplification, KeepTrianglesMatchesTheSolidPlate)
{
  const TriangleMesh plate = PlateWithHoles(2, 2, 0.5, 2);
  const TopologySimplificationResult r = Simplify(plate, 2.0, TopologyCompletion::KeepTriangles);
  EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), 4);
  Index fills = 0;
  Index removed = 0, filled = 0;
  for (const TopologyFeature& f : r.Features)
  {
    removed += f.RemovedTriangles;
    filled += f.FillTriangles;
  }
  for (unsigned char f : r.TriangleFill)
  {
    fills += f != 0;
  }
  EXPECT_EQ(fills, filled);
  EXPECT_EQ(r.Triangles.size() / 3, size_t(plate.NumberOfTriangles() - removed + filled));
  const TriangleMesh out = ResultMesh(plate, r);
  const MeshStatistics s = Stats(out);
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  const TriangleMesh solid = BlockModel(5, 5, std::vector<double>(25, 0.5), 1.0, 2);
  EXPECT_LT(Hausdorff(solid, out), 1e-6);
  // The triangulated completion covers the same solid.
  const TopologySimplificationResult t = Simplify(plate, 2.0);
  EXPECT_LT(Hausdorff(solid, ResultMesh(plate, t)), 1e-6);
}

// Option (1): SPBM after the topology simplification, to a target.
TEST(TopologySimplification, SpbmCompletionReachesTarget)
{
  const TriangleMesh mesh = LargeAndSmallHoles(3);
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = 2.0;
  p.Completion = TopologyCompletion::Spbm;
  p.SpbmTargetTriangles = 40;
  TopologySimplificationResult r;
  ASSERT_TRUE(TopologySimplifier().Run(mesh, p, r));
  EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), 4);
  const MeshStatistics s = Stats(ResultMesh(mesh, r));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 1);
  EXPECT_LE(s.Triangles, 40);
  EXPECT_GE(s.Triangles, 32); // the fewest for a box with a square through-hole
}

// Cracks: border loops of an open surface; small ones close, the outer border stays.
TEST(TopologySimplification, CracksClosed)
{
  TriangleMesh grid = Grid(12, 12);
  // Drop two triangles (one quad) and a strip of three quads: two cracks.
  std::vector<Index> keep;
  auto quadOf = [](Index t) { return t / 2; };
  for (Index t = 0; t < grid.NumberOfTriangles(); ++t)
  {
    const Index q = quadOf(t), i = q % 12, j = q / 12;
    const bool hole1 = i == 3 && j == 3;
    const bool hole2 = j == 8 && i >= 6 && i <= 8;
    if (!hole1 && !hole2)
    {
      keep.insert(keep.end(), grid.Triangle(t), grid.Triangle(t) + 3);
    }
  }
  grid.Triangles = keep;
  MeshStatistics s = Stats(grid);
  ASSERT_EQ(s.BoundaryLoops, 3);
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = 0.5; // the grid is 1 x 1; the cracks are below 0.3
  p.Completion = TopologyCompletion::KeepTriangles;
  TopologySimplificationResult r;
  ASSERT_TRUE(TopologySimplifier().Run(grid, p, r));
  EXPECT_EQ(Count(r, TopologyFeatureKind::Crack, true), 2);
  s = Stats(ResultMesh(grid, r));
  EXPECT_EQ(s.BoundaryLoops, 1); // the outer border
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(s.Triangles, 12 * 12 * 2);
  // A closed box with a crack becomes watertight.
  TriangleMesh box = BlockModel(3, 3, std::vector<double>(9, 1.0), 1.0, 2);
  box.Triangles.erase(box.Triangles.begin(), box.Triangles.begin() + 6); // two top quads' triangles
  ASSERT_GT(Stats(box).BoundaryEdges, 0);
  p.MaximumFeatureSize = 2.0;
  p.Completion = TopologyCompletion::TriangulatePatches;
  ASSERT_TRUE(TopologySimplifier().Run(box, p, r));
  EXPECT_EQ(Count(r, TopologyFeatureKind::Crack, true), 1);
  s = Stats(ResultMesh(box, r));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.Triangles, 12);
  // FillCracks off keeps the crack.
  p.FillCracks = false;
  ASSERT_TRUE(TopologySimplifier().Run(box, p, r));
  EXPECT_EQ(Count(r, TopologyFeatureKind::Crack, true), 0);
  EXPECT_GT(Stats(ResultMesh(box, r)).BoundaryEdges, 0);
}

TEST(TopologySimplification, Deterministic)
{
  const TriangleMesh mesh = PlateWithRoundHoles(3, 3, 0.3, 16, 0.4);
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = 0.8;
  p.Completion = TopologyCompletion::KeepTriangles;
  TopologySimplificationResult a, b;
  ASSERT_TRUE(TopologySimplifier().Run(mesh, p, a));
  ASSERT_TRUE(TopologySimplifier().Run(mesh, p, b));
  EXPECT_EQ(a.Triangles, b.Triangles);
  EXPECT_EQ(a.TrianglePatch, b.TrianglePatch);
  EXPECT_EQ(a.Loops.size(), b.Loops.size());
}

TEST(TopologySimplification, LoopDiameterEstimate)
{
  TriangleMesh m;
  std::vector<Index> loop;
  for (int i = 0; i < 40; ++i)
  {
    const double a = 2 * 3.14159265358979 * i / 40;
    loop.push_back(m.AddPoint({ 3 * std::cos(a), 3 * std::sin(a), 0 }));
  }
  EXPECT_NEAR(EstimateLoopDiameter(m, loop), 6.0, 1e-6);
  // A slot: the near-collinear triple's circle is capped by the box.
  TriangleMesh slot;
  std::vector<Index> s;
  for (int i = 0; i <= 20; ++i)
  {
    s.push_back(slot.AddPoint({ double(i), 0, 0 }));
  }
  for (int i = 20; i >= 0; --i)
  {
    s.push_back(slot.AddPoint({ double(i), 0.1, 0 }));
  }
  const double d = EstimateLoopDiameter(slot, s);
  EXPECT_GT(d, 15.0);
  EXPECT_LE(d, std::sqrt(400.0 + 0.01) + 1e-9);
}

// The CGAL demo CAD models with small holes: the genus drops by exactly the holes removed.
TEST(TopologySimplification, DemoMeshesWithHoles)
{
  struct Case
  {
    const char* Name;
    long long Genus;
    Index Holes; // removed at alpha = 0.2 of the diagonal
  };
  for (const Case& c : { Case{ "anchor", 4, 4 }, Case{ "couplingdown", 9, 8 }, Case{ "joint", 2, 1 } })
  {
    SCOPED_TRACE(c.Name);
    const TriangleMesh mesh = ToTriangleMesh(LoadTestMesh(c.Name));
    ASSERT_EQ(Stats(mesh).Genus, c.Genus);
    const TopologySimplificationResult r = Simplify(mesh, 0.2 * mesh.BoundingBoxDiagonal());
    EXPECT_EQ(Count(r, TopologyFeatureKind::Hole, true), c.Holes);
    const MeshStatistics s = Stats(ResultMesh(mesh, r));
    ExpectClosedManifold(s);
    EXPECT_EQ(s.Genus, c.Genus - c.Holes);
    EXPECT_LT(s.Triangles, mesh.NumberOfTriangles());
  }
}
