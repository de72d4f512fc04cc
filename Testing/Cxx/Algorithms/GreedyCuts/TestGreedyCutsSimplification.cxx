// SPDX-License-Identifier: BSD-3-Clause
// Tests of the greedy-cuts simplification (Ho 1999, chapter 3): the epsilon guarantee (two-sided
// Hausdorff measured by vtkSurfaceDeviation), original vertices only, manifold, watertight, same
// genus, no flipped triangles, monotone in epsilon, deterministic, the epsilon search for a target,
// bad input, and the comparison with vtkQuadricDecimation / vtkDecimatePro at the same count.
#include "TestSupport.h"

#include "slodChainSimplification.h"
#include "slodGreedyCuts.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodProvedCollapses.h"
#include "slodTriangleBVH.h"
#include "vtkGreedyCutsSimplification.h"
#include "vtkScanSurfaceSource.h"
#include "vtkSurfaceDeviation.h"
#include "vtkTriangleFilter.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkFieldData.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkQuadricDecimation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

using namespace slod;

namespace
{
struct Figures
{
  vtkSmartPointer<vtkPolyData> Output;
  double Bound = 0;
  double Hausdorff = 0; // measured, absolute
  double Seconds = 0;
  std::string Statistics;
};

double MeasureHausdorff(vtkPolyData* reference, vtkPolyData* compared)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(compared);
  deviation->SetNumberOfSamples(100000);
  deviation->Update();
  return deviation->GetHausdorff();
}

// The figures of a filter that has run on input (measured Hausdorff included).
Figures Collect(vtkGreedyCutsSimplification* filter, vtkPolyData* input)
{
  Figures f;
  f.Output = filter->GetOutput();
  f.Bound = filter->GetUsedMaximumError();
  f.Hausdorff = MeasureHausdorff(input, f.Output);
  return f;
}

// The figures of a run to `target` triangles under the loose bound 0.1 (the count decides).
Figures SimplifyToTarget(vtkPolyData* input, vtkIdType target)
{
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(0.1);
  filter->SetTargetNumberOfTriangles(target);
  filter->Update();
  return Collect(filter, input);
}

Figures Simplify(vtkPolyData* input, double relativeError, bool measure = true)
{
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(relativeError);
  const auto start = std::chrono::steady_clock::now();
  filter->Update();
  Figures f;
  f.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  f.Output = filter->GetOutput();
  f.Bound = filter->GetUsedMaximumError();
  std::ostringstream stats;
  stats << filter->GetNumberOfPatches() << " patches (" << filter->GetRefinedPatches() << " refined, "
        << filter->GetOriginalPatches() << " original), " << filter->GetNumberOfEars() << " ears, "
        << filter->GetNumberOfBites() << " bites, " << filter->GetNumberOfRepairs() << " repairs";
  f.Statistics = stats.str();
  if (measure)
  {
    f.Hausdorff = MeasureHausdorff(input, f.Output);
  }
  return f;
}

// Every output point is an input point (exact coordinates).
bool VerticesAreInputVertices(vtkPolyData* input, vtkPolyData* output)
{
  std::set<std::array<double, 3>> in;
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    in.insert({ p[0], p[1], p[2] });
  }
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    if (!in.count({ p[0], p[1], p[2] }))
    {
      return false;
    }
  }
  return true;
}

// Output triangles whose normal opposes the normal of the input surface at their centroid.
int FlippedTriangles(const TriangleMesh& original, const TriangleMesh& simplified)
{
  TriangleBVH bvh(original);
  int flipped = 0;
  for (Index t = 0; t < simplified.NumberOfTriangles(); ++t)
  {
    const Index* tri = simplified.Triangle(t);
    const Vec3 a = simplified.Point(tri[0]), b = simplified.Point(tri[1]), c = simplified.Point(tri[2]);
    const ClosestPointResult hit = bvh.ClosestPoint((1.0 / 3.0) * (a + b + c));
    if (Dot(Cross(b - a, c - a), original.TriangleAreaVector(hit.Triangle)) < 0)
    {
      std::cout << "flipped: triangle " << t << " distance " << std::sqrt(hit.Distance2) << " cos "
                << Dot(Normalized(Cross(b - a, c - a)), Normalized(original.TriangleAreaVector(hit.Triangle)))
                << " min angle " << MinimumAngle(a, b, c) * 180 / 3.14159265 << "\n";
      ++flipped;
    }
  }
  return flipped;
}

void ExpectValid(vtkPolyData* input, const Figures& f, const std::string& name)
{
  SCOPED_TRACE(name);
  const TriangleMesh in = slodtest::ToTriangleMesh(input);
  const TriangleMesh out = slodtest::RawTriangleMesh(f.Output);
  const MeshStatistics si = ComputeMeshStatistics(in);
  const MeshStatistics so = ComputeMeshStatistics(out);
  EXPECT_GT(out.NumberOfTriangles(), 0);
  EXPECT_LE(out.NumberOfTriangles(), in.NumberOfTriangles());
  EXPECT_EQ(so.NonManifoldEdges, 0);
  EXPECT_EQ(so.NonManifoldVertices, 0);
  EXPECT_EQ(so.BoundaryEdges, si.BoundaryEdges == 0 ? 0 : so.BoundaryEdges);
  EXPECT_EQ(so.BoundaryLoops, si.BoundaryLoops);
  EXPECT_EQ(so.Components, si.Components);
  EXPECT_EQ(so.Genus, si.Genus);
  EXPECT_EQ(so.EulerCharacteristic, si.EulerCharacteristic);
  EXPECT_EQ(so.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(so.DegenerateTriangles, 0);
  EXPECT_TRUE(VerticesAreInputVertices(input, f.Output));
  EXPECT_EQ(FlippedTriangles(in, out), 0);
  // The guarantee: two-sided Hausdorff <= epsilon (sampling can only under-estimate it; the tiny
  // slack is float storage of the measured surfaces).
  EXPECT_LE(f.Hausdorff, f.Bound * (1 + 1e-6) + 1e-9 * in.BoundingBoxDiagonal());
  vtkDataArray* patch = f.Output->GetCellData()->GetArray("PatchId");
  ASSERT_NE(patch, nullptr);
  EXPECT_EQ(patch->GetNumberOfTuples(), f.Output->GetNumberOfCells());
  vtkDataArray* bound = f.Output->GetFieldData()->GetArray("MaximumErrorBound");
  ASSERT_NE(bound, nullptr);
  EXPECT_DOUBLE_EQ(bound->GetTuple1(0), f.Bound);
}
} // namespace

TEST(ChainSimplification, DouglasPeuckerBound)
{
  TriangleMesh mesh;
  std::vector<Index> chain;
  for (int i = 0; i <= 100; ++i)
  {
    chain.push_back(mesh.AddPoint({ 0.01 * i, 0.05 * std::sin(0.2 * i), 0.0 }));
  }
  for (double eps : { 0.001, 0.01, 0.04 })
  {
    std::vector<unsigned char> keep;
    SimplifyChain(mesh, chain.data(), Index(chain.size()), eps, keep);
    EXPECT_TRUE(keep.front() && keep.back());
    Index last = 0;
    for (Index i = 1; i < Index(chain.size()); ++i)
    {
      if (keep[i])
      {
        for (Index j = last + 1; j < i; ++j)
        {
          EXPECT_LE(PointSegmentDistance(mesh.Point(chain[j]), mesh.Point(chain[last]), mesh.Point(chain[i])), eps);
        }
        last = i;
      }
    }
  }
}

TEST(GreedyCuts, TriangleWithinDistanceIsRigorous)
{
  // A unit square as two triangles; a triangle lifted by h is within eps iff h <= eps.
  TriangleMesh square;
  square.AddPoint({ 0, 0, 0 });
  square.AddPoint({ 1, 0, 0 });
  square.AddPoint({ 1, 1, 0 });
  square.AddPoint({ 0, 1, 0 });
  square.AddTriangle(0, 1, 2);
  square.AddTriangle(0, 2, 3);
  TriangleBVH bvh(square);
  EXPECT_TRUE(TriangleWithinDistance(bvh, { 0.1, 0.1, 0.05 }, { 0.9, 0.1, 0.05 }, { 0.5, 0.9, 0.05 }, 0.06, 10));
  EXPECT_FALSE(TriangleWithinDistance(bvh, { 0.1, 0.1, 0.05 }, { 0.9, 0.1, 0.05 }, { 0.5, 0.9, 0.05 }, 0.049, 10));
  // Sticking out over the border by 0.2: farther than 0.1 there.
  EXPECT_FALSE(TriangleWithinDistance(bvh, { 0.1, 0.1, 0 }, { 1.2, 0.1, 0 }, { 0.5, 0.9, 0 }, 0.1, 10));
}

// A flat 40x40 grid of unit squares, optionally without the two triangles of cell (20, 20).
TriangleMesh FlatGrid(bool withHole)
{
  TriangleMesh grid;
  const Index n = 41;
  for (Index j = 0; j < n; ++j)
  {
    for (Index i = 0; i < n; ++i)
    {
      grid.AddPoint({ double(i), double(j), 0 });
    }
  }
  for (Index j = 0; j + 1 < n; ++j)
  {
    for (Index i = 0; i + 1 < n; ++i)
    {
      if (!(withHole && i == 20 && j == 20))
      {
        const Index v = j * n + i;
        grid.AddTriangle(v, v + 1, v + n + 1);
        grid.AddTriangle(v, v + n + 1, v + n);
      }
    }
  }
  return grid;
}

TEST(GreedyCuts, TriangleOverAFlatRegionIsProvedAtATinyTolerance)
{
  // The piece spans hundreds of grid triangles and epsilon is 1e-5 of its size: subdividing until
  // the pieces are smaller than epsilon cannot finish within the bounded number of pieces.
  const double eps = 1e-4;
  const Vec3 a{ 1, 1, 0.5 * eps }, b{ 39, 1, 0.5 * eps }, c{ 20, 39, 0.5 * eps };
  const TriangleMesh grid = FlatGrid(false);
  const TriangleBVH bvh(grid);
  EXPECT_TRUE(TriangleWithinDistance(bvh, a, b, c, eps, 10));
  EXPECT_FALSE(TriangleWithinDistance(bvh, { 1, 1, 2 * eps }, { 39, 1, 2 * eps }, { 20, 39, 2 * eps }, eps, 10));
  // Over a missing cell the piece is farther than epsilon from the surface: never proved.
  const TriangleMesh holed = FlatGrid(true);
  const TriangleBVH holedBvh(holed);
  EXPECT_FALSE(TriangleWithinDistance(holedBvh, a, b, c, eps, 10));
  // Sticking out over the grid's border.
  EXPECT_FALSE(TriangleWithinDistance(bvh, { 1, 1, 0 }, { 40.5, 1, 0 }, { 20, 39, 0 }, eps, 10));
}

// A roof over the unit square, its ridge x = 0.5 at height h (slopes z = 2hx and 2h(1 - x)), two
// triangles a side; the left and right triangles at the ridge share its edge.
TriangleMesh Roof(double h)
{
  TriangleMesh roof;
  roof.AddPoint({ 0, 0, 0 });
  roof.AddPoint({ 0.5, 0, h });
  roof.AddPoint({ 0.5, 1, h });
  roof.AddPoint({ 0, 1, 0 });
  roof.AddPoint({ 1, 0, 0 });
  roof.AddPoint({ 1, 1, 0 });
  roof.AddTriangle(0, 1, 2);
  roof.AddTriangle(0, 2, 3);
  roof.AddTriangle(1, 4, 5);
  roof.AddTriangle(1, 5, 2);
  return roof;
}

// A flat triangle across a ridge, its corners on the slopes at 0.2 h: 0.8 h under the ridge, so
// within epsilon = h of the roof and not within 0.7 h. It spans the four roof triangles, so it is
// split once; each child lies on one slope or across the ridge's edge, proved by the two slopes
// (SharedEdgeProof): at most the piece and its four children are examined (base-s22: 26 pieces).
TEST(GreedyCuts, TriangleAcrossARidgeIsProvedByItsTwoSlopes)
{
  const double h = 1e-3;
  const TriangleMesh roof = Roof(h);
  const TriangleBVH bvh(roof);
  const Vec3 a{ 0.1, 0.1, 0.2 * h }, b{ 0.9, 0.5, 0.2 * h }, c{ 0.1, 0.9, 0.2 * h };
  long long pieces = 0;
  EXPECT_TRUE(TriangleWithinDistance(bvh, a, b, c, h, 10, &pieces));
  EXPECT_LE(pieces, 5);
  EXPECT_FALSE(TriangleWithinDistance(bvh, a, b, c, 0.7 * h, 10));
  // Lifted by 2 h its corners are about 2 h from the slopes.
  EXPECT_FALSE(TriangleWithinDistance(bvh, a + Vec3{ 0, 0, 2 * h }, b + Vec3{ 0, 0, 2 * h }, c + Vec3{ 0, 0, 2 * h }, h, 10));
}

// A shallow bowl z = d ((x - 1/2)^2 + (y - 1/2)^2) over the unit square, n x n cells of two triangles.
TriangleMesh Bowl(int n, double d)
{
  TriangleMesh bowl;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n, y = double(j) / n;
      bowl.AddPoint({ x, y, d * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5)) });
    }
  }
  for (Index j = 0; j < n; ++j)
  {
    for (Index i = 0; i < n; ++i)
    {
      const Index v = j * (n + 1) + i;
      bowl.AddTriangle(v, v + 1, v + n + 2);
      bowl.AddTriangle(v, v + n + 2, v + n + 1);
    }
  }
  return bowl;
}

// A set of triangles proved together (a collapse's): TrianglesWithinDistance gives the answer of
// the triangles' own proofs, and the same pieces when every one is proved; a set whose last
// triangle is refused at its first piece stops there, without the subdivisions the first one needs
// (proving the triangles one after the other spends those first).
TEST(GreedyCuts, TriangleSetsAreRefusedBeforeAnySubdivision)
{
  const double eps = 0.01;
  const TriangleMesh bowl = Bowl(24, 0.04); // 0 to 0.02 high
  const TriangleBVH bvh(bowl);
  // Flat triangles over the bowl at 0.006, within eps (the bowl's rim at the corners: about 0.01
  // high) but over too many of its triangles for a proof in one piece.
  const Vec3 a{ 0.1, 0.1, 0.006 }, b{ 0.9, 0.1, 0.006 }, c{ 0.5, 0.9, 0.006 }, d{ 0.9, 0.9, 0.006 };
  const Vec3 up{ 0, 0, 3 * eps };
  long long first = 0, second = 0, lifted = 0;
  ASSERT_TRUE(TriangleWithinDistance(bvh, a, b, c, eps, 10, &first));
  ASSERT_TRUE(TriangleWithinDistance(bvh, c, b, d, eps, 10, &second));
  ASSERT_FALSE(TriangleWithinDistance(bvh, a + up, b + up, c + up, eps, 10, &lifted));
  ASSERT_GT(first, 8); // subdivided
  ASSERT_LE(lifted, 2); // refused at its first piece

  long long pieces = 0;
  EXPECT_TRUE(TrianglesWithinDistance(bvh, { a, b, c, c, b, d }, eps, 10, &pieces));
  EXPECT_EQ(pieces, first + second);
  pieces = 0;
  EXPECT_FALSE(TrianglesWithinDistance(bvh, { a, b, c, a + up, b + up, c + up }, eps, 10, &pieces));
  EXPECT_LT(pieces, first);
  EXPECT_FALSE(TrianglesWithinDistance(bvh, { a, b, c, c, b, d }, 0.5 * eps, 10));
  EXPECT_TRUE(TrianglesWithinDistance(bvh, {}, eps, 10));
}

// A refused set names the triangle whose proof failed (the final collapses remember that answer):
// one that its own proof refuses, whichever position it holds in the set.
TEST(GreedyCuts, TriangleSetsNameTheRefusedTriangle)
{
  const double eps = 0.01;
  const TriangleMesh bowl = Bowl(24, 0.04);
  const TriangleBVH bvh(bowl);
  const Vec3 a{ 0.1, 0.1, 0.006 }, b{ 0.9, 0.1, 0.006 }, c{ 0.5, 0.9, 0.006 }, d{ 0.9, 0.9, 0.006 };
  const Vec3 up{ 0, 0, 3 * eps };
  size_t refused = 7;
  EXPECT_FALSE(TrianglesWithinDistance(bvh, { a, b, c, a + up, b + up, c + up }, eps, 10, nullptr, &refused));
  EXPECT_EQ(refused, 1u);
  EXPECT_FALSE(TrianglesWithinDistance(bvh, { a + up, b + up, c + up, a, b, c, c, b, d }, eps, 10, nullptr, &refused));
  EXPECT_EQ(refused, 0u);
  const std::vector<Vec3> pair = { a, b, c, c, b, d };
  refused = 7;
  EXPECT_FALSE(TrianglesWithinDistance(bvh, pair, 0.5 * eps, 10, nullptr, &refused));
  ASSERT_LT(refused, 2u);
  EXPECT_FALSE(TriangleWithinDistance(bvh, pair[3 * refused], pair[3 * refused + 1], pair[3 * refused + 2], 0.5 * eps, 10));
  refused = 7;
  EXPECT_TRUE(TrianglesWithinDistance(bvh, pair, eps, 10, nullptr, &refused));
  EXPECT_EQ(refused, 7u); // untouched when proved
}

// A scan of vtkScanSurfaceSource through the greedy cuts alone at 0.005 of its diagonal: the start
// of the final collapses, which do nearly all the work on scans.
struct ScanCuts
{
  vtkSmartPointer<vtkPolyData> Input;
  TriangleMesh Mesh;
  double Epsilon = 0;
  GreedyCutsResult Result;
};

ScanCuts CutScan(bool noisy, int resolution)
{
  vtkNew<vtkScanSurfaceSource> source;
  if (noisy)
  {
    source->SetKindToNoisyIsosurface();
  }
  else
  {
    source->SetKindToSegmentationMask();
  }
  source->SetResolution(resolution);
  source->Update();
  ScanCuts scan;
  scan.Input = source->GetOutput();
  scan.Mesh = slodtest::ToTriangleMesh(scan.Input);
  GreedyCuts cuts;
  cuts.Initialize(scan.Mesh, PatchificationParameters());
  GreedyCutsParameters parameters;
  parameters.Epsilon = scan.Epsilon = 0.005 * scan.Mesh.BoundingBoxDiagonal();
  parameters.FinalCollapses = false;
  EXPECT_TRUE(cuts.Run(parameters, scan.Result));
  return scan;
}

// A bite's front walk now carries each front vertex's sides of the bite's new edges from one
// front edge to the next (CarryFrontSides) instead of computing them twice. On an open scan (large
// patches, long fronts, many bites) the cuts alone give the same triangles and patches as the
// reference walk, with the same bites and feasibility tests; the output keeps the bound (measured).
TEST(GreedyCuts, BiteWalksCarryFrontSidesExactly)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKindToOpenScan();
  source->SetResolution(40);
  source->Update();
  const TriangleMesh mesh = slodtest::ToTriangleMesh(source->GetOutput());
  GreedyCuts cuts;
  cuts.Initialize(mesh, PatchificationParameters());
  GreedyCutsResult results[2];
  GreedyCutsParameters parameters;
  parameters.Epsilon = 0.005 * mesh.BoundingBoxDiagonal();
  parameters.FinalCollapses = false;
  for (const bool carry : { false, true })
  {
    parameters.CarryFrontSides = carry;
    ASSERT_TRUE(cuts.Run(parameters, results[carry]));
  }
  EXPECT_GT(results[1].Bites, 0);
  EXPECT_EQ(results[0].Bites, results[1].Bites);
  EXPECT_EQ(results[0].FeasibilityTests, results[1].FeasibilityTests);
  EXPECT_EQ(results[0].Triangles, results[1].Triangles);
  EXPECT_EQ(results[0].TrianglePatch, results[1].TrianglePatch);
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = results[1].Triangles;
  EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles());
  EXPECT_LE(MeasureHausdorff(source->GetOutput(), slodtest::ToPolyData(out)), parameters.Epsilon);
}

// The final collapses' passes try every refused vertex again with the same targets, and most of a
// star's new triangles are those of the last try: each new triangle's answer (facing and proof,
// which depend on its corners only) is now decided once per run and recalled after. On a
// segmentation-mask scan (where the collapses are nearly all the work) answers are recalled, and
// the output keeps the bound (measured) and is deterministic.
TEST(GreedyCuts, CollapsesDecideEachNewTriangleOnce)
{
  const ScanCuts scan = CutScan(false, 32);
  const vtkSmartPointer<vtkPolyData>& input = scan.Input;
  const TriangleMesh& mesh = scan.Mesh;
  const GreedyCutsResult& result = scan.Result;
  const TriangleBVH bvh(mesh);
  ProvedCollapseParameters collapse;
  collapse.Epsilon = scan.Epsilon;
  std::vector<Index> outputs[2];
  for (std::vector<Index>& triangles : outputs)
  {
    triangles = result.Triangles;
    std::vector<Index> patches = result.TrianglePatch;
    ProvedCollapseStatistics statistics;
    long long pieces = 0;
    ASSERT_TRUE(ProvedCollapses(mesh, bvh, collapse, triangles, patches, statistics, nullptr, &pieces));
    EXPECT_GT(statistics.Collapses, 0);
    EXPECT_GT(statistics.NewTriangleProofs, 0);
    EXPECT_GT(statistics.NewTrianglesRecalled, 0);
  }
  EXPECT_EQ(outputs[0], outputs[1]);
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = outputs[0];
  EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles() / 4);
  EXPECT_LE(MeasureHausdorff(input, slodtest::ToPolyData(out)), collapse.Epsilon);
}

// Every target tried for one vertex replaces the same star (the vertex's triangles) of the same
// mesh, so the input triangles that may rely on it and the unchanged output around it are now
// gathered once per vertex instead of once per target (ReuseStarGathering). On a mask and a noisy
// scan (where the final collapses are nearly all the work) the reference path (off: gathered per
// target) and the shared one give the same triangles, the same proof pieces and the same
// refusals, with fewer gatherings; the output keeps the bound (measured).
TEST(GreedyCuts, CollapsesGatherEachStarOncePerVertex)
{
  for (const bool noisy : { false, true })
  {
    const ScanCuts scan = CutScan(noisy, noisy ? 24 : 32);
    const TriangleMesh& mesh = scan.Mesh;
    const GreedyCutsResult& result = scan.Result;
    const TriangleBVH bvh(mesh);
    std::vector<Index> outputs[2], outputPatches[2];
    ProvedCollapseStatistics statistics[2];
    long long pieces[2] = { 0, 0 };
    for (int reuse = 0; reuse < 2; ++reuse)
    {
      ProvedCollapseParameters collapse;
      collapse.Epsilon = scan.Epsilon;
      collapse.ReuseStarGathering = reuse == 1;
      outputs[reuse] = result.Triangles;
      outputPatches[reuse] = result.TrianglePatch;
      ASSERT_TRUE(ProvedCollapses(
        mesh, bvh, collapse, outputs[reuse], outputPatches[reuse], statistics[reuse], nullptr, &pieces[reuse]));
    }
    const ProvedCollapseStatistics &reference = statistics[0], &shared = statistics[1];
    EXPECT_EQ(outputs[0], outputs[1]);
    EXPECT_EQ(outputPatches[0], outputPatches[1]);
    EXPECT_EQ(pieces[0], pieces[1]);
    EXPECT_EQ(reference.Collapses, shared.Collapses);
    EXPECT_EQ(reference.Attempts, shared.Attempts);
    EXPECT_EQ(reference.Flips, shared.Flips);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(reference.Rejected[k], shared.Rejected[k]);
    }
    EXPECT_GT(shared.Collapses, 0);
    EXPECT_GT(shared.InputGatherings, 0);
    EXPECT_LT(shared.InputGatherings, reference.InputGatherings);
    EXPECT_LT(shared.OutputGatherings, reference.OutputGatherings);
    TriangleMesh out;
    out.Points = mesh.Points;
    out.Triangles = outputs[1];
    EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles());
    EXPECT_LE(MeasureHausdorff(scan.Input, slodtest::ToPolyData(out)), scan.Epsilon);
  }
}

// At a tolerance much larger than the input's triangles (the target search's top level), every
// input triangle within epsilon of a change used to be proved again against a local output of
// every triangle within 3 epsilon: work per try growing with (epsilon / edge)^2, so with the
// input's size at a relative tolerance. Each input triangle now keeps a witness (one output
// triangle its corners are within epsilon of) or, lacking one, is registered on the output
// triangles near it; a change re-proves only the input registered on the triangles it replaces,
// read from an index (no gathering within epsilon). On a noisy scan collapsed from the input at
// 0.1 of the diagonal, the reference path (Witnesses off) and the witnessed one both keep the
// bound (measured) and the topology; the witnessed one examines far fewer input triangles and
// builds far smaller local outputs per try, and accepts most changes by witnesses alone.
TEST(GreedyCuts, CollapsesReproveOnlyTheInputTheirChangeWitnessed)
{
  const vtkSmartPointer<vtkPolyData> scan = slodtest::NoisyScanIsosurface(16, 1); // the source's default seed
  const TriangleMesh mesh = slodtest::ToTriangleMesh(scan);
  const TriangleBVH bvh(mesh);
  const MeshStatistics before = ComputeMeshStatistics(mesh);
  ProvedCollapseStatistics statistics[2];
  for (int witnesses = 0; witnesses < 2; ++witnesses)
  {
    SCOPED_TRACE(witnesses ? "witnesses" : "reference");
    ProvedCollapseParameters collapse;
    collapse.Epsilon = 0.1 * mesh.BoundingBoxDiagonal();
    collapse.Witnesses = witnesses == 1;
    std::vector<Index> triangles = mesh.Triangles, patches(size_t(mesh.NumberOfTriangles()), 0);
    long long pieces = 0;
    ASSERT_TRUE(ProvedCollapses(mesh, bvh, collapse, triangles, patches, statistics[witnesses], nullptr, &pieces));
    TriangleMesh out;
    out.Points = mesh.Points;
    out.Triangles = triangles;
    const MeshStatistics after = ComputeMeshStatistics(out);
    EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles() / 4);
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
    EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
    EXPECT_LE(MeasureHausdorff(scan, slodtest::ToPolyData(out)), collapse.Epsilon);
  }
  const ProvedCollapseStatistics &reference = statistics[0], &witnessed = statistics[1];
  EXPECT_EQ(reference.WitnessesKept + reference.AcceptedByWitnesses, 0);
  EXPECT_GT(witnessed.AcceptedByWitnesses, witnessed.Collapses / 2);
  // Per try, the local output triangles put in a BVH: a small fraction of the reference path's.
  // (The input examined per try is not compared: the witnessed run coarsens further, and its
  // larger stars, once wider than epsilon / 2, gather as the reference does.)
  EXPECT_GT(witnessed.InputTrianglesGathered, 0);
  EXPECT_LT(4 * witnessed.LocalOutputTriangles * reference.Attempts, reference.LocalOutputTriangles * witnessed.Attempts);
}

// Each new triangle's verdict (facing and proof) is remembered for the run, and the table of them
// used to keep every triangle ever tried: on the noisy scans, millions of entries read at random,
// growing with the input faster than the output. A verdict whose triangle lost a corner can never
// be asked again (removed vertices do not return), so such verdicts are dropped whenever the table
// would grow. On a noisy scan collapsed from the input at 0.1 of the diagonal the table ends with
// under a quarter of the verdicts the run made, and the output keeps the bound (measured) and
// the topology.
TEST(GreedyCuts, CollapsesHoldTheVerdictsOfTheLiveOutputOnly)
{
  const vtkSmartPointer<vtkPolyData> scan = slodtest::NoisyScanIsosurface(24, 1);
  const TriangleMesh mesh = slodtest::ToTriangleMesh(scan);
  const TriangleBVH bvh(mesh);
  ProvedCollapseParameters collapse;
  collapse.Epsilon = 0.1 * mesh.BoundingBoxDiagonal();
  std::vector<Index> triangles = mesh.Triangles, patches(size_t(mesh.NumberOfTriangles()), 0);
  ProvedCollapseStatistics statistics;
  long long pieces = 0;
  ASSERT_TRUE(ProvedCollapses(mesh, bvh, collapse, triangles, patches, statistics, nullptr, &pieces));
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = triangles;
  EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles() / 4);
  // Every verdict stored came from a proof (a refused set stores its refused triangle only).
  EXPECT_GT(statistics.VerdictsDropped, 0);
  EXPECT_LE(statistics.VerdictsHeld + statistics.VerdictsDropped, statistics.NewTriangleProofs);
  EXPECT_LT(4 * statistics.VerdictsHeld, statistics.NewTriangleProofs);
  const MeshStatistics before = ComputeMeshStatistics(mesh), after = ComputeMeshStatistics(out);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
  EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
  EXPECT_LE(MeasureHausdorff(scan, slodtest::ToPolyData(out)), collapse.Epsilon);
}

// A noisy scan (resolution N, seed 1), its triangles and a tolerance of `fraction` of its diagonal;
// Output starts as the input (same points).
struct NoisyScanAtTolerance
{
  NoisyScanAtTolerance(int resolution, double fraction)
    : Scan(slodtest::NoisyScanIsosurface(resolution, 1))
    , Input(slodtest::ToTriangleMesh(this->Scan))
    , Output(this->Input)
    , Epsilon(fraction * this->Input.BoundingBoxDiagonal())
  {
  }
  vtkSmartPointer<vtkPolyData> Scan;
  TriangleMesh Input, Output;
  double Epsilon = 0;
  bool Finished = false;
};

// ... whose input triangles are collapsed at 0.1 of its diagonal.
struct ScanCollapsedAtATenth : NoisyScanAtTolerance
{
  explicit ScanCollapsedAtATenth(int resolution)
    : NoisyScanAtTolerance(resolution, 0.1)
  {
    const TriangleBVH bvh(this->Input);
    ProvedCollapseParameters collapse;
    collapse.Epsilon = this->Epsilon;
    std::vector<Index> patches(size_t(this->Input.NumberOfTriangles()), 0);
    this->Finished = ProvedCollapses(this->Input, bvh, collapse, this->Output.Triangles, patches, this->Statistics);
  }
  ProvedCollapseStatistics Statistics;
};

// Every collapse try asked the degree of its vertex, its targets and the vertices around its star,
// each a walk over a vertex's references reading the triangles' alive flags at random (a share of
// the CPU that grew with the input). The collapser now keeps the degrees in a per-vertex array and
// walks only the corners of what each accepted change gathered: on noisy scans of two sizes,
// collapsed from the input at 0.1 of the diagonal, the walks are one per vertex plus at most
// 3 x 2 x 128 per change (two stars within the valence bound), whatever the number of tries, and
// about the same per input vertex at both sizes (linear); each result keeps the bound (measured) and the
// input's Euler characteristic, border loops and non-manifold edges.
TEST(GreedyCuts, CollapsesWalkTheDegreesOfTheirChangesOnly)
{
  double walksPerVertex[2] = { 0, 0 };
  const int resolutions[2] = { 16, 24 };
  for (int size = 0; size < 2; ++size)
  {
    const ScanCollapsedAtATenth run(resolutions[size]);
    ASSERT_TRUE(run.Finished);
    const long long points = static_cast<long long>(run.Input.NumberOfPoints());
    const long long changes = run.Statistics.Collapses + run.Statistics.Flips;
    ASSERT_GT(changes, 0);
    EXPECT_GE(run.Statistics.DegreeWalks, points);
    EXPECT_LE(run.Statistics.DegreeWalks, points + 3 * 2 * 128 * changes);
    walksPerVertex[size] = double(run.Statistics.DegreeWalks) / double(points);
    EXPECT_LT(run.Output.NumberOfTriangles(), run.Input.NumberOfTriangles() / 4);
    const MeshStatistics before = ComputeMeshStatistics(run.Input), after = ComputeMeshStatistics(run.Output);
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
    EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
    EXPECT_LE(MeasureHausdorff(run.Scan, slodtest::ToPolyData(run.Output)), run.Epsilon);
  }
  EXPECT_LE(walksPerVertex[1], 1.5 * walksPerVertex[0]);
  EXPECT_LE(walksPerVertex[0], 1.5 * walksPerVertex[1]);
}

// The collapse passes took their vertices shortest edge first, i.e. at random over the mesh, and
// each try read the mesh, the input's BVH, the witnesses and the index there: the cost per try
// grew with the input's size (memory). By bands of the shortest edge, in Morton order within a
// band, consecutive tries are near each other. On a noisy scan collapsed from the input at 0.1 of
// the diagonal, the banded walk's mean step is under half the exact order's, and the
// result is as good: within the bound (measured), the input's Euler characteristic, border loops
// and non-manifold edges, and no more triangles than the exact order's plus 5 %.
TEST(GreedyCuts, CollapsePassesWalkTheMeshInSpatialOrder)
{
  const vtkSmartPointer<vtkPolyData> scan = slodtest::NoisyScanIsosurface(24, 1);
  const TriangleMesh mesh = slodtest::ToTriangleMesh(scan);
  const TriangleBVH bvh(mesh);
  const MeshStatistics before = ComputeMeshStatistics(mesh);
  double meanStep[2] = { 0, 0 };
  Index counts[2] = { 0, 0 };
  for (int banded = 0; banded < 2; ++banded)
  {
    ProvedCollapseParameters collapse;
    collapse.Epsilon = 0.1 * mesh.BoundingBoxDiagonal();
    collapse.PassOrderBands = banded ? 2 : 0;
    std::vector<Index> triangles = mesh.Triangles, patches(size_t(mesh.NumberOfTriangles()), 0);
    ProvedCollapseStatistics statistics;
    ASSERT_TRUE(ProvedCollapses(mesh, bvh, collapse, triangles, patches, statistics));
    ASSERT_GT(statistics.PassSteps, mesh.NumberOfPoints() / 2);
    meanStep[banded] = statistics.PassStepLength / double(statistics.PassSteps);
    TriangleMesh out;
    out.Points = mesh.Points;
    out.Triangles = triangles;
    counts[banded] = out.NumberOfTriangles();
    EXPECT_LT(out.NumberOfTriangles(), mesh.NumberOfTriangles() / 4);
    const MeshStatistics after = ComputeMeshStatistics(out);
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
    EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
    EXPECT_LE(MeasureHausdorff(scan, slodtest::ToPolyData(out)), collapse.Epsilon);
  }
  EXPECT_LT(2 * meanStep[1], meanStep[0]);
  EXPECT_LE(double(counts[1]), 1.05 * double(counts[0]));
}

// The cuts repeat their rounds while patches escalate (released angles, careful mode, full chains,
// original triangles), and every round used to simplify every chain of the input again, although
// the chains' simplification changes only when a chain is refined to full resolution: the work of
// a round grew with the input, not with its escalated patches. On a noisy scan whose cuts take
// several rounds, the chains are simplified in fewer passes than rounds (once, then only after a
// refinement), and the result keeps the bound (measured).
TEST(GreedyCuts, CutsSimplifyTheChainsOnlyAfterARefinement)
{
  const vtkSmartPointer<vtkPolyData> scan = slodtest::NoisyScanIsosurface(24, 1);
  const TriangleMesh mesh = slodtest::ToTriangleMesh(scan);
  GreedyCuts cuts;
  cuts.Initialize(mesh, PatchificationParameters());
  GreedyCutsParameters parameters;
  parameters.Epsilon = 0.3 * mesh.BoundingBoxDiagonal();
  parameters.FinalCollapses = false;
  GreedyCutsResult result;
  ASSERT_TRUE(cuts.Run(parameters, result));
  EXPECT_GT(result.Rounds, 2);
  EXPECT_GE(result.ChainPasses, 1);
  EXPECT_LT(result.ChainPasses, result.Rounds);
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = result.Triangles;
  EXPECT_LE(out.NumberOfTriangles(), mesh.NumberOfTriangles());
  EXPECT_LE(MeasureHausdorff(scan, slodtest::ToPolyData(out)), parameters.Epsilon);
}

// Session 41: the 4M noisy scan's cuts cost 14x the 1M scan's because one patch of 3 triangles fell
// back and each split round ran the cuts again over the whole input; the trace (`--log-verbosity 9`)
// now shows it: one line per cuts run with its fallback patches and their triangles, and one per
// call of the final collapses with its work counts. ALSTOM_TEST4 at 0.01 splits in several rounds:
// the trace has one run line per split round plus one, the last one's fallback count is the
// result's, and the collapses' line counts the result's collapses.
namespace
{
void CollectTrace(void* lines, const vtkLogger::Message& message)
{
  static_cast<std::vector<std::string>*>(lines)->push_back(message.message);
}
}

TEST(GreedyCuts, TraceShowsEverySplitRoundAndTheCollapsesWork)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("ALSTOM_TEST4"));
  GreedyCuts cuts;
  cuts.Initialize(mesh, PatchificationParameters());
  GreedyCutsParameters parameters;
  parameters.Epsilon = 0.01 * mesh.BoundingBoxDiagonal();
  std::vector<std::string> lines;
  vtkLogger::AddCallback("greedy-cuts-trace", CollectTrace, &lines, vtkLogger::VERBOSITY_TRACE);
  GreedyCutsResult result;
  const bool ran = cuts.Run(parameters, result);
  vtkLogger::RemoveCallback("greedy-cuts-trace");
  ASSERT_TRUE(ran);
  ASSERT_GT(result.SplitRounds, 0);
  std::vector<std::string> runs, collapses;
  for (const std::string& line : lines)
  {
    if (line.find("greedy cuts: cuts run ") != std::string::npos)
    {
      runs.push_back(line);
    }
    if (line.find("greedy cuts: collapses at epsilon") != std::string::npos)
    {
      collapses.push_back(line);
    }
  }
  ASSERT_EQ(runs.size(), size_t(result.SplitRounds) + 1);
  for (size_t k = 0; k + 1 < runs.size(); ++k)
  {
    EXPECT_EQ(runs[k].find(" 0 fell back"), std::string::npos) << runs[k]; // each split round had a reason
  }
  EXPECT_NE(runs.back().find(", " + std::to_string(result.FallbackPatchIds.size()) + " fell back"), std::string::npos)
    << runs.back();
  ASSERT_EQ(collapses.size(), size_t(1));
  EXPECT_NE(collapses[0].find(" " + std::to_string(result.FinalCollapses) + " collapses"), std::string::npos)
    << collapses[0];
  EXPECT_NE(collapses[0].find(" tries"), std::string::npos) << collapses[0];
}

namespace
{
// One "greedy cuts: cuts run" trace line's figures: the input triangles of the patches that fell
// back, and those of the patches the run cut (-1 when the line does not give them).
struct CutsRunFigures
{
  long long FallbackTriangles = -1, CutTriangles = -1;
};

std::vector<CutsRunFigures> TracedCutsRuns(const TriangleMesh& mesh, GreedyCutsParameters parameters,
  bool local, GreedyCutsResult& result)
{
  GreedyCuts cuts;
  cuts.Initialize(mesh, PatchificationParameters());
  parameters.LocalSplitRounds = local;
  std::vector<std::string> lines;
  vtkLogger::AddCallback("greedy-cuts-split-trace", CollectTrace, &lines, vtkLogger::VERBOSITY_TRACE);
  const bool ran = cuts.Run(parameters, result);
  vtkLogger::RemoveCallback("greedy-cuts-split-trace");
  EXPECT_TRUE(ran);
  std::vector<CutsRunFigures> runs;
  for (const std::string& line : lines)
  {
    if (line.find("greedy cuts: cuts run ") == std::string::npos)
    {
      continue;
    }
    CutsRunFigures f;
    const size_t fell = line.find(" fell back with ");
    f.FallbackTriangles = fell == std::string::npos ? -1 : std::atoll(line.c_str() + fell + 16);
    const size_t cut = line.find(" input triangles cut");
    const size_t start = cut == std::string::npos ? cut : line.rfind("; ", cut);
    f.CutTriangles = start == std::string::npos ? -1 : std::atoll(line.c_str() + start + 2);
    runs.push_back(f);
  }
  return runs;
}
} // namespace

// Session 42: a split round (some patch fell back, is split in two and cut again) ran the cuts
// again over the whole input: on the 4M noisy scan two whole runs per level for one fallback patch
// of 3 input triangles. It now goes on from the run before and cuts only the pieces and the patches
// sharing a chain with them. ALSTOM_TEST4 at 0.01 and 0.008 of the diagonal splits (asserted): each
// split round cuts fewer input triangles than the input has (a whole run cuts every patch at least
// once: asserted on the whole-run rounds of the same input) and at most a few times the patches it
// split (their neighbours are cut again too). The output keeps no fallback patch and is proved
// within epsilon (the filter's runs of WrappedFansAreSplitSoNoPatchFallsBack). On base-s42 the trace
// line gives no count of triangles cut, so the first count assertion fails there.
TEST(GreedyCuts, SplitRoundsCutTheirPiecesNotTheInput)
{
  const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("ALSTOM_TEST4"));
  const long long input = mesh.NumberOfTriangles();
  for (double eps : { 0.01, 0.008 })
  {
    GreedyCutsParameters parameters;
    parameters.Epsilon = eps * mesh.BoundingBoxDiagonal();
    parameters.FinalCollapses = false; // the cuts alone: the split rounds are theirs
    GreedyCutsResult local, whole;
    const std::vector<CutsRunFigures> runs = TracedCutsRuns(mesh, parameters, true, local);
    const std::vector<CutsRunFigures> wholeRuns = TracedCutsRuns(mesh, parameters, false, whole);
    ASSERT_GT(local.SplitRounds, 0) << eps;
    ASSERT_EQ(runs.size(), size_t(local.SplitRounds) + 1) << eps;
    for (size_t r = 1; r < runs.size(); ++r)
    {
      ASSERT_GE(runs[r].CutTriangles, 0) << eps << " run " << r;
      ASSERT_GT(runs[r - 1].FallbackTriangles, 0) << eps << " run " << r;
      EXPECT_LT(runs[r].CutTriangles, input) << eps << " run " << r;
      EXPECT_LE(runs[r].CutTriangles, 4 * runs[r - 1].FallbackTriangles) << eps << " run " << r;
    }
    for (size_t r = 1; r < wholeRuns.size(); ++r)
    {
      EXPECT_GE(wholeRuns[r].CutTriangles, input) << eps << " whole run " << r;
    }
    EXPECT_EQ(local.OriginalPatches, 0) << eps;
    EXPECT_GT(local.SplitPatchTriangles, 0) << eps;
    EXPECT_LT(local.SplitRoundTriangles, whole.SplitRoundTriangles) << eps;
    EXPECT_GT(local.LocallyVerifiedTriangles, 0) << eps;
    EXPECT_LT(local.LocallyVerifiedTriangles, input * local.SplitRounds) << eps;
  }
}

// A pyramid: a flat hexagon (its border) around a centre lifted by 3 epsilon. Its only removable
// vertex is the centre (border collapses off), and every collapse of it leaves the centre 3 epsilon
// from the new flat triangles: refused at the removed vertex, before any triangle's proof, so no
// proof piece is spent (the triangles' proofs used to run first).
TEST(GreedyCuts, CollapsesFailingAtTheRemovedVertexSpendNoProof)
{
  const double eps = 1e-3;
  TriangleMesh pyramid;
  pyramid.AddPoint({ 0, 0, 3 * eps });
  for (int k = 0; k < 6; ++k)
  {
    pyramid.AddPoint({ std::cos(k * std::acos(-1.0) / 3), std::sin(k * std::acos(-1.0) / 3), 0 });
  }
  for (Index k = 0; k < 6; ++k)
  {
    pyramid.AddTriangle(0, 1 + k, 1 + (k + 1) % 6);
  }
  const TriangleBVH bvh(pyramid);
  ProvedCollapseParameters parameters;
  parameters.Epsilon = eps;
  parameters.BorderCollapses = false;
  std::vector<Index> triangles = pyramid.Triangles, patches(6, 0);
  ProvedCollapseStatistics statistics;
  long long pieces = 0;
  ASSERT_TRUE(ProvedCollapses(pyramid, bvh, parameters, triangles, patches, statistics, nullptr, &pieces));
  EXPECT_GT(statistics.Attempts, 0);
  EXPECT_EQ(statistics.Collapses, 0);
  EXPECT_EQ(triangles, pyramid.Triangles);
  EXPECT_EQ(pieces, 0);
}

TEST(GreedyCutsSimplification, SphereAndTorus)
{
  for (const auto& [name, shape] : { std::pair<std::string, TriangleMesh>{ "sphere", slodtest::Sphere(48, 48) },
         { "torus", slodtest::Torus(64, 32) } })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(shape);
    const Figures f = Simplify(input, 0.01);
    std::cout << "[greedy-cuts] " << name << " " << input->GetNumberOfCells() << " -> "
              << f.Output->GetNumberOfCells() << " tris, eps " << f.Bound << ", Hausdorff " << f.Hausdorff << ", " << f.Statistics << "\n";
    ExpectValid(input, f, name);
    EXPECT_LT(f.Output->GetNumberOfCells(), input->GetNumberOfCells() / 3);
  }
}

TEST(GreedyCutsSimplification, OpenDisk)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(slodtest::Disk(20, 48));
  const Figures f = Simplify(input, 0.01);
  ExpectValid(input, f, "disk");
  EXPECT_LT(f.Output->GetNumberOfCells(), input->GetNumberOfCells());
}

TEST(GreedyCutsSimplification, RealMeshesRespectEpsilon)
{
  // Monotone in epsilon on these ranges. (Not in general: bunny00 at 0.02 gives more than at 0.01,
  // fandisk at 0.006 more than at 0.005; see GreedyCuts.md.)
  for (const auto& [name, epsilons] : { std::pair<std::string, std::vector<double>>{ "fandisk", { 0.005, 0.01, 0.02 } },
         { "bunny00", { 0.005, 0.01 } } })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkIdType previous = std::numeric_limits<vtkIdType>::max();
    for (double eps : epsilons)
    {
      const Figures f = Simplify(input, eps);
      std::cout << "[greedy-cuts] " << name << " eps " << eps << " (" << f.Bound << "): " << input->GetNumberOfCells()
                << " -> " << f.Output->GetNumberOfCells() << " tris, measured Hausdorff " << f.Hausdorff << " ("
                << f.Hausdorff / f.Bound << " of eps), " << f.Seconds << " s, " << f.Statistics << "\n";
      ExpectValid(input, f, name + " eps " + std::to_string(eps));
      EXPECT_LT(f.Output->GetNumberOfCells(), previous);
      previous = f.Output->GetNumberOfCells();
    }
  }
}

TEST(GreedyCutsSimplification, Deterministic)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  const Figures a = Simplify(input, 0.01, false);
  const Figures b = Simplify(input, 0.01, false);
  ASSERT_EQ(a.Output->GetNumberOfCells(), b.Output->GetNumberOfCells());
  ASSERT_EQ(a.Output->GetNumberOfPoints(), b.Output->GetNumberOfPoints());
  const TriangleMesh ma = slodtest::RawTriangleMesh(a.Output), mb = slodtest::RawTriangleMesh(b.Output);
  EXPECT_EQ(ma.Triangles, mb.Triangles);
  EXPECT_EQ(ma.Points, mb.Points);
}

TEST(GreedyCutsSimplification, TargetSearchesEpsilon)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(0.05); // the search's upper end
  filter->SetTargetNumberOfTriangles(1500);
  filter->Update();
  vtkPolyData* output = filter->GetOutput();
  std::cout << "[greedy-cuts] fandisk target 1500: " << output->GetNumberOfCells() << " tris at eps "
            << filter->GetUsedMaximumError() << "\n";
  EXPECT_LE(output->GetNumberOfCells(), 1500);
  EXPECT_GT(output->GetNumberOfCells(), 500);
  EXPECT_LT(filter->GetUsedMaximumError(), 0.05 * slodtest::ToTriangleMesh(input).BoundingBoxDiagonal());
  EXPECT_LE(MeasureHausdorff(input, output), filter->GetUsedMaximumError() * (1 + 1e-6));
  // A reduction of 0 (target >= input) returns the input's triangles.
  filter->SetTargetNumberOfTriangles(0);
  filter->SetTargetReduction(0.0);
  filter->SetMaximumError(0.0);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), input->GetNumberOfCells());
  EXPECT_EQ(filter->GetUsedMaximumError(), 0.0);
  std::ostringstream print;
  filter->Print(print);
  EXPECT_NE(print.str().find("MaximumError"), std::string::npos);
  EXPECT_NE(print.str().find("BiteCandidates"), std::string::npos);
}

// Flat inputs made of slivers: a 1000-gon given as one polygon (triangulated by the input
// preparation) and a fan of 5,000 triangles around one centre. The distance proofs subdivided
// their candidates four ways down to the tolerance, each piece's closest-point query visiting
// hundreds of slivers: the target search never finished. Now each proof examines a bounded number
// of pieces; the result keeps every guarantee.
TEST(GreedyCutsSimplification, FlatSliverInputsFinishWithinTheBound)
{
  const int corners = 1000;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polygon;
  polygon->InsertNextCell(corners);
  for (int i = 0; i < corners; ++i)
  {
    const double a = 2 * M_PI * i / corners;
    polygon->InsertCellPoint(points->InsertNextPoint(std::cos(a), std::sin(a), 0));
  }
  vtkNew<vtkPolyData> ngon;
  ngon->SetPoints(points);
  ngon->SetPolys(polygon);
  const vtkSmartPointer<vtkPolyData> fan = slodtest::ToPolyData(slodtest::Disk(1, 5000));
  for (vtkPolyData* input : { static_cast<vtkPolyData*>(ngon), fan.Get() })
  {
    // As the command line runs it: half the triangles, epsilon searched below 0.1 of the diagonal.
    vtkNew<vtkGreedyCutsSimplification> filter;
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->SetInputData(input);
    filter->SetTargetReduction(0.5);
    filter->SetMaximumError(0.1);
    filter->Update();
    const Figures f = Collect(filter, input);
    vtkNew<vtkTriangleFilter> triangles; // the reference for ExpectValid: the polygon's triangles
    triangles->SetInputData(input);
    triangles->Update();
    ExpectValid(triangles->GetOutput(), f, input == fan.Get() ? "fan" : "1000-gon");
    EXPECT_LE(f.Output->GetNumberOfCells(), triangles->GetOutput()->GetNumberOfCells() / 2);
  }
}

// elephant (closed, genus 3) as the command line runs it: the target search's rounds refine chains
// (full resolution), which lets a neighbouring chain drop a vertex it had kept apart; the patch on
// its other side kept triangles on that vertex and a 3-edge hole opened. Closed stays closed.
// The cuts' own search (FinalCollapses off) tries the small tolerances where that happens; the
// collapsed counts' search stops at the ladder's bottom on this target.
TEST(GreedyCutsSimplification, ClosedInputStaysClosedWhenChainsChange)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("elephant");
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->FinalCollapsesOff();
  filter->SetTargetReduction(0.5);
  filter->SetMaximumError(0.1);
  filter->Update();
  const Figures f = Collect(filter, input);
  ExpectValid(input, f, "elephant");
  EXPECT_GT(filter->GetRefinedPatches(), 0); // the case above happened
}

TEST(GreedyCutsSimplification, BadInputGivesErrorAndEmptyOutput)
{
  vtkNew<vtkPolyData> empty;
  vtkSmartPointer<vtkPolyData> nan = slodtest::ToPolyData(slodtest::Sphere(8, 8));
  nan->GetPoints()->SetPoint(3, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  for (vtkPolyData* input : { static_cast<vtkPolyData*>(empty), nan.Get() })
  {
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetInputData(input);
    filter->GlobalWarningDisplayOff();
    filter->Update();
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
}

namespace
{
using EdgeEnds = std::pair<std::array<double, 3>, std::array<double, 3>>;

// Each edge of more than two triangles, by its end points' coordinates (so that an input and an
// output on other vertex ids compare), with its number of triangles.
std::map<EdgeEnds, int> NonManifoldEdgeUses(const TriangleMesh& mesh)
{
  std::map<std::pair<Index, Index>, int> uses;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      ++uses[std::minmax(tri[k], tri[(k + 1) % 3])];
    }
  }
  std::map<EdgeEnds, int> result;
  for (const auto& [edge, use] : uses)
  {
    if (use > 2)
    {
      const Vec3 a = mesh.Point(edge.first), b = mesh.Point(edge.second);
      result[std::minmax(std::array<double, 3>{ a[0], a[1], a[2] }, std::array<double, 3>{ b[0], b[1], b[2] })] = use;
    }
  }
  return result;
}

// The filter's output against its prepared input: every non-manifold edge still one edge with as
// many triangles, the border loops and the Euler characteristic kept, input vertices only, no patch
// kept as its original triangles, and the bound (measured).
void ExpectSeamsKept(vtkPolyData* input, vtkGreedyCutsSimplification* filter)
{
  TriangleMesh prepared;
  std::vector<Index> vertexToInputPoint;
  ASSERT_TRUE(PrepareTriangleMesh(input, PreparationOptions(), prepared, vertexToInputPoint).Valid);
  const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
  const MeshStatistics si = ComputeMeshStatistics(prepared), so = ComputeMeshStatistics(out);
  EXPECT_GT(si.NonManifoldEdges + si.NonManifoldVertices, 0) << "the test input must be non-manifold";
  EXPECT_EQ(NonManifoldEdgeUses(out), NonManifoldEdgeUses(prepared));
  EXPECT_EQ(so.NonManifoldVertices, si.NonManifoldVertices);
  EXPECT_EQ(so.BoundaryLoops, si.BoundaryLoops);
  EXPECT_EQ(so.EulerCharacteristic, si.EulerCharacteristic);
  EXPECT_EQ(so.Components, si.Components);
  EXPECT_EQ(so.DegenerateTriangles, 0);
  EXPECT_TRUE(VerticesAreInputVertices(input, filter->GetOutput()));
  EXPECT_EQ(filter->GetOriginalPatches(), 0);
  const double bound = filter->GetUsedMaximumError();
  EXPECT_LE(MeasureHausdorff(input, filter->GetOutput()), bound * (1 + 1e-6) + 1e-9 * prepared.BoundingBoxDiagonal());
}
} // namespace

// Non-manifold input (issue 10's rule: a non-manifold edge is never cut open) is simplified with the
// triangles at its non-manifold vertices kept as they are. On noisy scans (non-manifold edges and
// vertices, a border, handles) the output has fewer than half the triangles and keeps every
// non-manifold edge with its triangles, the border loops and the Euler characteristic; a fan of
// wings on one edge stays as it is. The filter refused all of them before (an empty output).
TEST(GreedyCutsSimplification, NonManifoldInputKeepsItsSeams)
{
  for (unsigned seed : { 2u, 5u })
  {
    SCOPED_TRACE(seed);
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetMaximumError(0.01);
    const MeshStatistics in = slodtest::SimplifyNoisyScan(filter, 40, seed);
    EXPECT_GT(in.NonManifoldVertices, 0);
    EXPECT_LT(filter->GetOutput()->GetNumberOfPolys(), in.Triangles / 2);
    ExpectSeamsKept(slodtest::NoisyScanIsosurface(40, seed), filter);
  }
  // A sphere and three wings on one edge away from it; a sphere and a torus sharing one vertex (a
  // pinch: two fans), the torus's lowest vertex along the sphere's first vertex (a pole) moved there.
  const TriangleMesh sphere = slodtest::Sphere(24, 16);
  TriangleMesh pinched = slodtest::Concatenate(sphere, slodtest::Torus(32, 16));
  const Vec3 pole = pinched.Point(0);
  Index lowest = sphere.NumberOfPoints();
  for (Index v = lowest; v < pinched.NumberOfPoints(); ++v)
  {
    lowest = Dot(pinched.Point(v), pole) < Dot(pinched.Point(lowest), pole) ? v : lowest;
  }
  const Vec3 shift = pole - pinched.Point(lowest);
  for (Index v = sphere.NumberOfPoints(); v < pinched.NumberOfPoints(); ++v)
  {
    pinched.SetPoint(v, pinched.Point(v) + shift);
  }
  for (Index& v : pinched.Triangles)
  {
    v = v == lowest ? 0 : v;
  }
  for (const TriangleMesh& mesh : { slodtest::Concatenate(sphere, slodtest::NonManifoldFan(3)), pinched })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(mesh);
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetInputData(input);
    filter->SetMaximumError(0.02);
    filter->Update();
    EXPECT_LT(filter->GetOutput()->GetNumberOfPolys(), mesh.NumberOfTriangles() / 2);
    ExpectSeamsKept(input, filter);
  }
}

TEST(GreedyCutsSimplification, AgainstVTKDecimatorsAtTheSameCount)
{
  for (const auto& [name, eps] : { std::pair<std::string, double>{ "fandisk", 0.01 }, { "bunny00", 0.005 } })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const auto start = std::chrono::steady_clock::now();
    const Figures ours = Simplify(input, eps);
    const double oursSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const vtkIdType count = ours.Output->GetNumberOfCells();
    const double reduction = 1.0 - double(count) / double(input->GetNumberOfCells());
    vtkNew<vtkQuadricDecimation> quadric;
    quadric->SetInputData(input);
    quadric->SetTargetReduction(reduction);
    const auto qStart = std::chrono::steady_clock::now();
    quadric->Update();
    const double qSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - qStart).count();
    vtkNew<vtkDecimatePro> pro;
    pro->SetInputData(input);
    pro->SetTargetReduction(reduction);
    pro->PreserveTopologyOn();
    pro->Update();
    const double hq = MeasureHausdorff(input, quadric->GetOutput());
    const double hp = MeasureHausdorff(input, pro->GetOutput());
    std::cout << "[greedy-cuts] " << name << " at " << count << " tris (eps " << ours.Bound << "): Hausdorff ours "
              << ours.Hausdorff << ", vtkQuadricDecimation " << hq << " (" << quadric->GetOutput()->GetNumberOfCells()
              << " tris, ratio ours/quadric " << ours.Hausdorff / hq << "), vtkDecimatePro " << hp << " ("
              << pro->GetOutput()->GetNumberOfCells() << " tris, ratio " << ours.Hausdorff / hp << "); time ours "
              << oursSeconds << " s vs quadric " << qSeconds << " s\n";
    EXPECT_LE(ours.Hausdorff, ours.Bound * (1 + 1e-6));
  }
}

TEST(GreedyCutsSimplification, ProgressAndAbort)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  struct State
  {
    int Events = 0;
    bool Abort = false;
  } state;
  vtkNew<vtkCallbackCommand> callback;
  callback->SetClientData(&state);
  callback->SetCallback([](vtkObject* caller, unsigned long, void* clientData, void*) {
    auto* s = static_cast<State*>(clientData);
    ++s->Events;
    if (s->Abort)
    {
      static_cast<vtkGreedyCutsSimplification*>(caller)->SetAbortExecute(1);
    }
  });
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(0.01);
  filter->AddObserver(vtkCommand::ProgressEvent, callback);
  filter->Update();
  EXPECT_GT(state.Events, 10);
  // Observing progress changes nothing: the same triangles as a run without an observer.
  {
    vtkNew<vtkGreedyCutsSimplification> plain;
    plain->SetInputData(input);
    plain->SetMaximumError(0.01);
    plain->Update();
    EXPECT_EQ(slodtest::RawTriangleMesh(filter->GetOutput()).Triangles,
      slodtest::RawTriangleMesh(plain->GetOutput()).Triangles);
    EXPECT_LT(filter->GetOutput()->GetNumberOfCells(), input->GetNumberOfCells() / 10);
  }
  // Aborted at the first progress report: a defined (empty) output.
  state = State{ 0, true };
  filter->SetMaximumError(0.011);
  filter->Update();
  EXPECT_GE(state.Events, 1);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
}

// Chapter 3's own patchification (section 3.4.1): few large terrain-like patches, each a disk and
// a height field over its height direction (every triangle faces it), small patches merged. On
// mushroom the dissertation reports 6 patches; chapter 4's near-planar patches are many more.
TEST(GreedyCuts, Chapter3TerrainPatches)
{
  for (const std::string name : { "mushroom", "fandisk", "elephant" })
  {
    SCOPED_TRACE(name);
    const TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh(name));
    const MeshTopology topology(mesh);
    TerrainPatchificationParameters parameters;
    TerrainPatches terrain;
    ASSERT_TRUE(BuildTerrainPatches(mesh, topology, parameters, terrain));
    ASSERT_EQ(terrain.TrianglePatch.size(), size_t(mesh.NumberOfTriangles()));
    ASSERT_EQ(terrain.HeightDirection.size(), size_t(terrain.NumberOfPatches));
    EXPECT_LE(terrain.NumberOfPatches, terrain.GrownPatches);
    std::vector<Index> sizes(size_t(terrain.NumberOfPatches), 0);
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      const Index p = terrain.TrianglePatch[t];
      ASSERT_LT(p, terrain.NumberOfPatches);
      ++sizes[p];
      EXPECT_GE(Dot(Normalized(mesh.TriangleAreaVector(t)), terrain.HeightDirection[p]),
        parameters.MinimumHeightCosine - 1e-12);
    }
    Patchification labelled;
    labelled.BuildFromLabels(mesh, topology, terrain.TrianglePatch, terrain.NumberOfPatches);
    std::vector<Index> loop;
    for (Index p = 0; p < terrain.NumberOfPatches; ++p)
    {
      EXPECT_GT(sizes[p], 0);
      EXPECT_TRUE(labelled.PatchBoundaryLoop(p, loop)) << "patch " << p << " is not a disk";
    }
    Patchification chapter4;
    chapter4.Build(mesh, topology, PatchificationParameters());
    std::cout << "[greedy-cuts] " << name << ": " << terrain.GrownPatches << " terrain patches grown, "
              << terrain.NumberOfPatches << " after merging; chapter 4: " << chapter4.NumberOfPatches() << "\n";
    EXPECT_LT(4 * terrain.NumberOfPatches, chapter4.NumberOfPatches());
  }
}

TEST(GreedyCutsSimplification, Chapter3PatchificationKeepsTheBound)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("mushroom");
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(0.02);
  filter->SetPatchification(vtkGreedyCutsSimplification::CHAPTER3_TERRAIN_PATCHES);
  filter->Update();
  const Figures f = Collect(filter, input);
  std::cout << "[greedy-cuts] mushroom chapter 3 patches eps 0.02: " << f.Output->GetNumberOfCells() << " tris, "
            << filter->GetNumberOfPatches() << " patches, " << filter->GetOriginalPatches() << " original\n";
  ExpectValid(input, f, "mushroom chapter 3");
  EXPECT_LT(filter->GetNumberOfPatches(), 20);
  EXPECT_EQ(f.Output->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0);
}

// Front repair (section 3.4.3): a stuck front is repaired (edge swap, face split, vertex deletion)
// instead of its patch falling back to its original triangles. fandisk at 0.005 and 0.007 had one
// patch kept original (about 3,900 triangles where 0.01 gives about 800).
TEST(GreedyCutsSimplification, StuckFrontsAreRepairedNotKeptOriginal)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  for (double eps : { 0.005, 0.007 })
  {
    const Figures f = Simplify(input, eps);
    std::cout << "[greedy-cuts] fandisk eps " << eps << ": " << f.Output->GetNumberOfCells() << " tris, " << f.Statistics
              << "\n";
    ExpectValid(input, f, "fandisk eps " + std::to_string(eps));
    vtkDataArray* fallbacks = f.Output->GetFieldData()->GetArray("FallbackPatches");
    vtkDataArray* repairs = f.Output->GetFieldData()->GetArray("FrontRepairs");
    ASSERT_NE(fallbacks, nullptr);
    ASSERT_NE(repairs, nullptr);
    EXPECT_EQ(fallbacks->GetTuple1(0), 0);
    EXPECT_GT(repairs->GetTuple1(0), 0);
    // Kept original, one patch alone would leave more than a fifth of the input's triangles.
    EXPECT_LT(f.Output->GetNumberOfCells(), input->GetNumberOfCells() / 5);
  }
}

namespace
{
// Share of triangles whose smallest angle is under `degrees`.
double SliverShare(vtkPolyData* mesh, double degrees)
{
  const TriangleMesh m = slodtest::RawTriangleMesh(mesh);
  Index thin = 0;
  for (Index t = 0; t < m.NumberOfTriangles(); ++t)
  {
    const Index* tri = m.Triangle(t);
    thin += MinimumAngle(m.Point(tri[0]), m.Point(tri[1]), m.Point(tri[2])) < degrees * M_PI / 180;
  }
  return double(thin) / double(std::max<Index>(m.NumberOfTriangles(), 1));
}
} // namespace

// Session 21: an input triangle thinner than MinimumTriangleAngle (0.5 degrees) was infeasible
// even as itself, so its patch got stuck, fell back to its original triangles and was split, run
// after run, until it stood alone (CAD meshes: anchor 16 fallback patches at every tolerance,
// oblong 8). A stuck patch may now keep its own thin input triangles before any other escalation.
// anchor and oblong are used by no other test; their inputs hold such triangles (asserted).
TEST(GreedyCutsSimplification, ThinInputTrianglesDoNotMakeTheirPatchFallBack)
{
  for (const std::string name : { "anchor", "oblong" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkNew<vtkGreedyCutsSimplification> defaults;
    EXPECT_GT(SliverShare(input, defaults->GetMinimumTriangleAngle()), 0.0) << name;
    for (double eps : { 0.005, 0.01, 0.02 })
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(eps);
      filter->Update();
      const Figures f = Collect(filter, input);
      const std::string run = name + " eps " + std::to_string(eps);
      std::cout << "[greedy-cuts] " << run << ": " << f.Output->GetNumberOfCells() << " tris, "
                << filter->GetOriginalPatches() << " original patches of " << filter->GetNumberOfPatches() << "\n";
      ExpectValid(input, f, run);
      EXPECT_EQ(f.Output->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0) << run;
      EXPECT_EQ(filter->GetOriginalPatches(), 0) << run;
    }
  }
}

// ShapedTriangleAngle: a patch first asks for triangles no thinner than 5 degrees and releases
// that bound only when its front gets stuck (the paper's minimal aspect ratio, released
// gradually). dino is used by no other test.
TEST(GreedyCutsSimplification, ShapedTrianglesHaveFewerSlivers)
{
  double plainShares = 0;
  for (const std::string name : { "dino", "mushroom" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    double share[2] = { 0, 0 };
    for (int shaped = 0; shaped < 2; ++shaped)
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(0.01);
      filter->SetShapedTriangleAngle(shaped ? 5.0 : 0.0);
      // Against the chapter's largest-area ears (the default shaped ears of session 17 leave
      // fewer slivers to halve).
      filter->SetEarShapeAngle(0.0);
      filter->Update();
      const Figures f = Collect(filter, input);
      ExpectValid(input, f, name + (shaped ? " shaped" : " plain"));
      EXPECT_EQ(f.Output->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0);
      share[shaped] = SliverShare(f.Output, 5.0);
      std::cout << "[greedy-cuts] " << name << (shaped ? " shaped 5 deg" : " plain") << ": "
                << f.Output->GetNumberOfCells() << " tris, " << 100 * share[shaped] << "% under 5 degrees\n";
    }
    // Since session 17's collapse order dino has no sliver even in the plain run: at most half
    // of none; the plain runs together must still have some (mushroom's), or nothing is tested.
    EXPECT_LE(share[1], 0.5 * share[0]) << name;
    plainShares += share[0];
  }
  EXPECT_GT(plainShares, 0.0);
}

// Session 17: most slivers of a single-epsilon run on fandisk were caps in flat parts, cut as fans
// by the largest-area ear rule. Ranking thin ears below their area (EarShapeAngle, default 15
// degrees) must cut the sliver share of the cuts themselves (FinalCollapsesOff: the ears are their
// triangles) by a third against the pure largest-area rule (EarShapeAngle 0) at two tolerances.
// With the final collapses (which since session 19 remove most fans either way) the shaped run
// must stay under the issue's 5 % slivers, for at most 10 % more triangles than the plain rule;
// both with the full ExpectValid (the bound measured).
TEST(GreedyCutsSimplification, ShapedEarsCutFewerFansOfCaps)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  for (const double epsilon : { 0.01, 0.02 })
  {
    double cutShare[2] = { 0, 0 }, finalShare[2] = { 0, 0 };
    vtkIdType count[2] = { 0, 0 };
    for (int shaped = 0; shaped < 2; ++shaped)
    {
      for (const bool collapses : { false, true })
      {
        vtkNew<vtkGreedyCutsSimplification> filter;
        filter->SetInputData(input);
        filter->SetMaximumError(epsilon);
        filter->SetFinalCollapses(collapses);
        if (!shaped)
        {
          filter->SetEarShapeAngle(0.0);
        }
        filter->Update();
        const Figures f = Collect(filter, input);
        const std::string label = "fandisk " + std::to_string(epsilon) + (shaped ? " shaped ears" : " largest ears") +
          (collapses ? "" : ", cuts alone");
        ExpectValid(input, f, label);
        const double share = SliverShare(f.Output, 5.0);
        (collapses ? finalShare : cutShare)[shaped] = share;
        if (collapses)
        {
          count[shaped] = f.Output->GetNumberOfCells();
        }
        std::cout << "[greedy-cuts] " << label << ": " << f.Output->GetNumberOfCells() << " tris, " << 100 * share
                  << "% under 5 degrees\n";
      }
    }
    EXPECT_LT(cutShare[1], (2.0 / 3.0) * cutShare[0]) << epsilon;
    EXPECT_LT(finalShare[1], 0.05) << epsilon;
    EXPECT_LE(count[1], 1.1 * double(count[0])) << epsilon;
  }
}

// A patch whose front stays stuck after the repairs is split in two and retried instead of being
// kept as its original triangles. Before: fandisk at 0.003 kept one patch original (3,988
// triangles), bunny00 at 0.02 four (10,324), mushroom's largest terrain patch one at 0.05.
TEST(GreedyCutsSimplification, StuckPatchesAreSplitNotKeptOriginal)
{
  for (const auto& [name, eps, chapter3] : { std::tuple<std::string, double, bool>{ "fandisk", 0.003, false },
         { "bunny00", 0.02, false }, { "mushroom", 0.05, true } })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetInputData(input);
    filter->SetMaximumError(eps);
    filter->SetPatchification(chapter3 ? vtkGreedyCutsSimplification::CHAPTER3_TERRAIN_PATCHES
                                       : vtkGreedyCutsSimplification::CHAPTER4_PATCHES);
    filter->Update();
    const Figures f = Collect(filter, input);
    std::cout << "[greedy-cuts] " << name << " eps " << eps << (chapter3 ? " chapter 3" : "") << ": "
              << f.Output->GetNumberOfCells() << " tris, " << filter->GetNumberOfPatches() << " patches\n";
    ExpectValid(input, f, name);
    EXPECT_EQ(f.Output->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0);
    EXPECT_LT(f.Output->GetNumberOfCells(), input->GetNumberOfCells() / 8);
  }
}

// A piece split from a chapter 4 patch is triangulated along its own mean normal, not its parent's:
// a patch holds triangles up to TwoEdgePatchAngle (90 degrees) from its normal, and a small piece
// of them projected along it may not be triangulable. lion-head kept two such pieces (1 and 6
// triangles) as their original triangles at every tolerance before.
TEST(GreedyCutsSimplification, SplitPiecesUseTheirOwnNormal)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("lion-head");
  for (double eps : { 0.006, 0.015 })
  {
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetInputData(input);
    filter->SetMaximumError(eps);
    filter->Update();
    ExpectValid(input, Collect(filter, input), "lion-head");
    EXPECT_EQ(filter->GetOriginalPatches(), 0) << eps;
  }
}

// One default run at eps (relative): every property of ExpectValid, and no fallback patch (the
// field data and the statistic agree).
namespace
{
void ExpectNoFallbackPatch(vtkPolyData* input, double eps, const std::string& run)
{
  vtkNew<vtkGreedyCutsSimplification> filter;
  filter->SetInputData(input);
  filter->SetMaximumError(eps);
  filter->Update();
  ExpectValid(input, Collect(filter, input), run);
  EXPECT_EQ(filter->GetOutput()->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0) << run;
  EXPECT_EQ(filter->GetOriginalPatches(), 0) << run;
}
} // namespace

// Session 26: a fallback patch with a vertex whose triangles, projected along the patch's
// direction, turn more than 360 degrees around it is split through that vertex's fan (each half
// takes half of the turn). ALSTOM_TEST4 kept one such piece as its original triangles at every
// tolerance before, however often it was halved: the overlap stayed in one of the halves.
// ALSTOM_TEST4 is used by no other test.
TEST(GreedyCutsSimplification, WrappedFansAreSplitSoNoPatchFallsBack)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("ALSTOM_TEST4");
  for (double eps : { 0.006, 0.008, 0.01, 0.012 })
  {
    ExpectNoFallbackPatch(input, eps, "ALSTOM_TEST4 eps " + std::to_string(eps));
  }
}

// Session 33: at small tolerances (0.002, 0.003 of the diagonal) dragknob and part kept 12
// fallback patches each: a three-triangle piece holding a 0.09 degree input sliver whose normal
// turns away from the piece's direction got stuck, and its split gave the whole piece to the half
// (one breadth-first step added two neighbours), leaving an empty patch, itself counted as a
// fallback, and the same stuck piece in every later round. Now the half never takes the whole
// patch, an empty patch is no fallback, and a stuck patch's own input triangle need only face
// its side. part is used by no other test.
TEST(GreedyCutsSimplification, SmallTolerancesLeaveNoFallbackPatch)
{
  for (const std::string name : { "dragknob", "part" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    for (double eps : { 0.002, 0.003 })
    {
      ExpectNoFallbackPatch(input, eps, name + " eps " + std::to_string(eps));
    }
  }
}

// Session 33: mpi's polygons over collinear vertices triangulate to a zero-area triangle that the
// patchification leaves as a patch of its own; without a normal it cannot be projected and fell
// back to its original triangle at every tolerance. It now joins the patch across its longest
// edge. The filter gets mpi's polygons (the project's own triangulation, shared by ExpectValid's
// reference, makes that triangle). mpi is used by no other test.
TEST(GreedyCutsSimplification, ZeroAreaTrianglesJoinANeighbouringPatch)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("mpi");
  for (double eps : { 0.002, 0.01, 0.03 })
  {
    ExpectNoFallbackPatch(input, eps, "mpi eps " + std::to_string(eps));
  }
}

// Session 26: staged final collapses (CollapseStages, off by default). A lower stage accepts only
// the collapses whose new triangles lie within MaximumError / 2^k of the input, while the input's
// proofs stay at MaximumError (the bound the cuts' output holds on entry): every property of the
// default run holds, and the stages change the output (they are run). pinion and dragknob are used
// by no other test.
TEST(GreedyCutsSimplification, StagedCollapsesKeepTheBound)
{
  for (const std::string name : { "pinion", "dragknob" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkNew<vtkGreedyCutsSimplification> plain;
    plain->SetInputData(input);
    plain->SetMaximumError(0.01);
    plain->Update();
    for (int stages : { 1, 2 })
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(0.01);
      filter->SetCollapseStages(stages);
      filter->Update();
      const std::string run = name + " stages " + std::to_string(stages);
      ExpectValid(input, Collect(filter, input), run);
      const TriangleMesh a = slodtest::RawTriangleMesh(filter->GetOutput());
      const TriangleMesh b = slodtest::RawTriangleMesh(plain->GetOutput());
      EXPECT_TRUE(a.Triangles != b.Triangles) << run;
      std::cout << "[greedy-cuts] " << run << ": " << filter->GetOutput()->GetNumberOfCells() << " tris (unstaged "
                << plain->GetOutput()->GetNumberOfCells() << ")\n";
    }
  }
}

// EarlySliverStep (session 31): the final collapses begin with a sliver step on the cuts' output,
// while the collapses have not used the bound up around the cuts' slivers. joint (a CAD mesh, 58 %
// of its input triangles under 5 degrees; used by no other test) at three tolerances: every
// property of ExpectValid (the bound measured) and fewer triangles under 5 degrees than without.
TEST(GreedyCutsSimplification, EarlySliverStepLeavesFewerSlivers)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("joint");
  for (double epsilon : { 0.005, 0.01, 0.02 })
  {
    double slivers[2] = { 0, 0 };
    for (int early = 0; early < 2; ++early)
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(epsilon);
      filter->SetEarlySliverStep(early != 0);
      filter->Update();
      const Figures f = Collect(filter, input);
      const std::string run = "joint " + std::to_string(epsilon) + (early ? " early sliver step" : " without");
      ExpectValid(input, f, run);
      slivers[early] = SliverShare(f.Output, 5.0) * double(f.Output->GetNumberOfCells());
      std::cout << "[greedy-cuts] " << run << ": " << f.Output->GetNumberOfCells() << " tris, " << slivers[early]
                << " under 5 degrees, H/eps " << f.Hausdorff / f.Bound << "\n";
    }
    EXPECT_LT(slivers[1], slivers[0]) << epsilon;
  }
}

// The final pass of proved collapses and flips (FinalCollapses, on by default) keeps every
// property of the greedy cuts (measured Hausdorff within the bound, manifold, same genus, Euler
// characteristic, orientation, original vertices) with fewer triangles. cow and elk are used by no
// other test.
TEST(GreedyCutsSimplification, FinalCollapsesKeepTheBoundWithFewerTriangles)
{
  for (const std::string name : { "cow", "elk" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkIdType count[2] = { 0, 0 };
    for (int collapses = 0; collapses < 2; ++collapses)
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(0.01);
      filter->SetFinalCollapses(collapses != 0);
      filter->Update();
      const Figures f = Collect(filter, input);
      ExpectValid(input, f, name + (collapses ? " with final collapses" : " without"));
      count[collapses] = f.Output->GetNumberOfCells();
      EXPECT_EQ(filter->GetNumberOfFinalCollapses() > 0, collapses != 0);
      std::cout << "[greedy-cuts] " << name << (collapses ? " with" : " without") << " final collapses: "
                << count[collapses] << " tris, H/eps " << f.Hausdorff / f.Bound << ", "
                << 100 * SliverShare(f.Output, 5.0) << "% under 5 degrees\n";
    }
    EXPECT_LT(count[1], count[0]);
  }
}

// RunLevels: along increasing tolerances the counts never rise (each level starts from the finer
// one when that has fewer triangles, and the collapses only remove), and every level keeps its
// own bound. On two meshes no test tunes for (cow, elk); the sweep crosses tolerances where
// single runs are not monotone on other meshes (fandisk 0.02 -> 0.05).
TEST(GreedyCuts, LevelsNeverRiseAndKeepTheirBounds)
{
  for (const std::string name : { "cow", "elk" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    const MeshStatistics before = ComputeMeshStatistics(mesh);
    GreedyCuts cuts;
    cuts.Initialize(mesh, PatchificationParameters());
    const std::vector<double> relative = { 0.003, 0.005, 0.01, 0.02, 0.05 };
    std::vector<double> epsilons;
    for (double e : relative)
    {
      epsilons.push_back(e * mesh.BoundingBoxDiagonal());
    }
    std::vector<GreedyCutsResult> levels;
    ASSERT_TRUE(cuts.RunLevels(epsilons, GreedyCutsParameters(), levels));
    ASSERT_EQ(levels.size(), epsilons.size());
    vtkSmartPointer<vtkPolyData> reference = slodtest::ToPolyData(mesh);
    for (size_t i = 0; i < levels.size(); ++i)
    {
      TriangleMesh out;
      out.Points = mesh.Points;
      out.Triangles = levels[i].Triangles;
      const double hausdorff = MeasureHausdorff(reference, slodtest::ToPolyData(out));
      out.RemoveUnusedPoints();
      const MeshStatistics after = ComputeMeshStatistics(out);
      std::cout << "[greedy-cuts] " << name << " level eps " << relative[i] << ": " << out.NumberOfTriangles()
                << " tris, H/eps " << hausdorff / epsilons[i] << (levels[i].StartedFromFinerLevel ? " (from the finer level)" : "")
                << "\n";
      EXPECT_LE(hausdorff, epsilons[i] * (1 + 1e-6));
      EXPECT_EQ(levels[i].TrianglePatch.size(), levels[i].Triangles.size() / 3);
      EXPECT_EQ(after.NonManifoldEdges, 0);
      EXPECT_EQ(after.Genus, before.Genus);
      EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
      EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
      if (i > 0)
      {
        EXPECT_LE(levels[i].Triangles.size(), levels[i - 1].Triangles.size());
      }
    }
    EXPECT_LT(levels.back().Triangles.size(), levels.front().Triangles.size());
  }
}

// Single filter runs are monotone in epsilon with MonotoneInEpsilon on: a fine sweep of
// tolerances that are not ladder values, each a separate filter run, never gives more triangles at
// a larger epsilon, and each keeps its bound (at most the asked epsilon; the last one measured). Before, single runs rose
// (fandisk 0.02 -> 0.05: 122 -> 132; bunny00 0.01 -> 0.02). Meshes no other test uses.
TEST(GreedyCutsSimplification, SingleRunsNeverRiseWithEpsilon)
{
  for (const std::string name : { "hand", "knot" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const double diagonal = slodtest::ToTriangleMesh(input).BoundingBoxDiagonal();
    vtkIdType previous = std::numeric_limits<vtkIdType>::max();
    std::cout << "[greedy-cuts] " << name << " sweep:";
    // 0.0043 to 0.0094 by a factor 1.3: steps within and across ladder values (0.005, 0.006, 0.008);
    // short, as every run repeats the ladder's first levels.
    for (double eps = 0.0043; eps <= 0.0095; eps *= 1.3)
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(eps);
      filter->MonotoneInEpsilonOn();
      filter->Update();
      const vtkIdType count = filter->GetOutput()->GetNumberOfCells();
      std::cout << " " << eps << ":" << count << std::flush;
      EXPECT_GT(count, 0);
      EXPECT_LE(count, previous) << "eps " << eps;
      EXPECT_LE(filter->GetUsedMaximumError(), eps * diagonal * (1 + 1e-12));
      EXPECT_GE(filter->GetUsedMaximumError(), eps * diagonal / 1.34); // the ladder's widest step
      EXPECT_EQ(filter->GetOutput()->GetFieldData()->GetArray("FallbackPatches")->GetTuple1(0), 0);
      previous = count;
      if (eps * 1.3 > 0.0095)
      {
        std::cout << "\n";
        ExpectValid(input, Collect(filter, input), name + " at the sweep's last tolerance");
      }
    }
  }
}

// One level of a chain of tolerances: its measured Hausdorff within `bound`, and the input's
// topology kept (no non-manifold or misoriented edge, its Euler characteristic and border loops).
void ExpectLevelWithinBound(vtkPolyData* input, const TriangleMesh& mesh, const std::vector<Index>& triangles,
  double bound, const std::string& what)
{
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = triangles;
  EXPECT_LE(MeasureHausdorff(input, slodtest::ToPolyData(out)), bound * (1 + 1e-6)) << what;
  out.RemoveUnusedPoints();
  const MeshStatistics before = ComputeMeshStatistics(mesh), after = ComputeMeshStatistics(out);
  EXPECT_EQ(after.NonManifoldEdges, 0) << what;
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic) << what;
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops) << what;
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0) << what;
}

// Separate RunMonotone runs at tolerances off the ladder (0.0045 x 1.28^k of the diagonal up to
// 0.0125, across its steps) with two settings: `checked`'s count never rises with epsilon, its
// bound is the same ladder value as `other`'s (at most epsilon, at least epsilon / 1.34) and is
// measured at every run, with the topology kept, and it ends below the input. Returns the
// distance-proof pieces of each over the sweep.
std::pair<long long, long long> SweepTwoChains(const std::string& name, const GreedyCutsParameters& checked,
  const GreedyCutsParameters& other, const std::string& what)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
  const TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  const double diagonal = mesh.BoundingBoxDiagonal();
  size_t previous = std::numeric_limits<size_t>::max();
  std::pair<long long, long long> work(0, 0);
  std::cout << "[greedy-cuts] " << name << " " << what << ":";
  for (double eps = 0.0045; eps <= 0.0125; eps *= 1.28)
  {
    GreedyCutsParameters first = checked, second = other;
    first.Epsilon = second.Epsilon = eps * diagonal;
    GreedyCutsResult result, compared;
    GreedyCuts firstCuts, secondCuts;
    firstCuts.Initialize(mesh, PatchificationParameters());
    secondCuts.Initialize(mesh, PatchificationParameters());
    EXPECT_TRUE(firstCuts.RunMonotone(first, result));
    EXPECT_TRUE(secondCuts.RunMonotone(second, compared));
    work.first += firstCuts.ProofPiecesExamined();
    work.second += secondCuts.ProofPiecesExamined();
    EXPECT_FALSE(firstCuts.WorkBoundReached());
    EXPECT_EQ(result.ErrorBound, compared.ErrorBound); // the same ladder value
    EXPECT_LE(result.ErrorBound, first.Epsilon * (1 + 1e-12));
    EXPECT_GE(result.ErrorBound, first.Epsilon / 1.34);
    const size_t count = result.Triangles.size() / 3;
    std::cout << " " << eps << ":" << count << " (" << compared.Triangles.size() / 3 << ")" << std::flush;
    EXPECT_GT(count, 0u);
    EXPECT_LE(count, previous) << "eps " << eps;
    previous = count;
    ExpectLevelWithinBound(input, mesh, result.Triangles, result.ErrorBound, "eps " + std::to_string(eps));
  }
  std::cout << "\n[greedy-cuts] " << name << " proof pieces: " << work.first << " against " << work.second << "\n";
  EXPECT_LT(previous, size_t(mesh.NumberOfTriangles()));
  return work;
}

// Session 30: the cheap chain (LadderOwnRuns off): each level above the bottom is the finer level's
// output collapsed at its own tolerance, with no cuts or fresh runs of its own: monotone, within
// its bound, and fewer distance-proof pieces than the nested run with its own runs at the same
// epsilon (in brackets). Meshes no other GreedyCuts test uses (spool: CAD, helmet: smooth).
TEST(GreedyCuts, CheapLadderChainNeverRisesForLessWork)
{
  for (const std::string name : { "spool", "helmet" })
  {
    SCOPED_TRACE(name);
    GreedyCutsParameters chain, own;
    chain.LadderOwnRuns = false;
    const auto [chainWork, ownWork] = SweepTwoChains(name, chain, own, "cheap chain (own runs)");
    EXPECT_LT(chainWork, ownWork);
  }
}

// Session 35: a chain of ladder levels (the cheap chain, 0.002 to 0.03 of the diagonal) recalls the
// new triangles its finer levels proved (a triangle within a smaller tolerance is within every
// larger one) instead of proving them again: the same triangles at every level as a chain that
// proves each level's own, a count that never rises along the sweep, the bound measured at every
// level with the topology kept, and fewer distance-proof pieces. Meshes no GreedyCuts test uses
// (itemb: CAD, pig: smooth).
TEST(GreedyCuts, LadderChainRecallsTheProofsOfFinerLevels)
{
  for (const std::string name : { "itemb", "pig" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    std::vector<double> levels = GreedyCuts::ToleranceLadder(0.002, 0.03);
    ASSERT_GT(levels.size(), 10u);
    for (double& level : levels)
    {
      level *= mesh.BoundingBoxDiagonal();
    }
    GreedyCutsParameters parameters;
    parameters.LadderOwnRuns = false;
    std::vector<GreedyCutsResult> carried, own;
    GreedyCuts carrying, proving;
    carrying.Initialize(mesh, PatchificationParameters());
    proving.Initialize(mesh, PatchificationParameters());
    ASSERT_TRUE(carrying.RunLevels(levels, parameters, carried));
    parameters.CarryProofs = false;
    ASSERT_TRUE(proving.RunLevels(levels, parameters, own));
    ASSERT_EQ(carried.size(), levels.size());
    ASSERT_EQ(own.size(), levels.size());
    size_t previous = size_t(mesh.NumberOfTriangles());
    std::cout << "[greedy-cuts] " << name << " chain:";
    for (size_t i = 0; i < levels.size(); ++i)
    {
      const size_t count = carried[i].Triangles.size() / 3;
      std::cout << " " << count << std::flush;
      EXPECT_EQ(carried[i].Triangles, own[i].Triangles) << "level " << i;
      EXPECT_EQ(carried[i].ErrorBound, levels[i]);
      EXPECT_GT(count, 0u);
      EXPECT_LE(count, previous) << "level " << i;
      previous = count;
      ExpectLevelWithinBound(input, mesh, carried[i].Triangles, levels[i], "level " + std::to_string(i));
    }
    std::cout << "\n[greedy-cuts] " << name << " proof pieces: carried " << carrying.ProofPiecesExamined()
              << ", each level its own " << proving.ProofPiecesExamined() << "\n";
    EXPECT_LT(carrying.ProofPiecesExamined(), proving.ProofPiecesExamined());
    EXPECT_LT(previous, size_t(mesh.NumberOfTriangles()));
  }
}

// Session 36: the chain in collapse-only steps (LadderCollapsesOnly): every level, the bottom's too,
// runs only the collapse passes, and the level returned is finished by proved flips: monotone,
// within its bound, and fewer distance-proof pieces over the sweep than the chain in full steps (in
// brackets). Meshes no other GreedyCuts test uses (rotor: CAD, cactus: smooth).
TEST(GreedyCuts, CollapseOnlyChainNeverRisesForLessWork)
{
  for (const std::string name : { "rotor", "cactus" })
  {
    SCOPED_TRACE(name);
    GreedyCutsParameters steps, full;
    steps.LadderOwnRuns = full.LadderOwnRuns = false;
    steps.LadderCollapsesOnly = true;
    const auto [stepsWork, fullWork] = SweepTwoChains(name, steps, full, "collapse-only chain (full steps)");
    EXPECT_LT(stepsWork, fullWork);
  }
}

// The ladder: 10 round values per decade, ascending, each the largest at most the asked value.
TEST(GreedyCuts, ToleranceLadderIsFixedAndRound)
{
  const std::vector<double> ladder = GreedyCuts::ToleranceLadder(0.004, 0.05);
  const std::vector<double> expected = { 0.004, 0.005, 0.006, 0.008, 0.01, 0.012, 0.015, 0.02, 0.025, 0.03, 0.04, 0.05 };
  ASSERT_EQ(ladder.size(), expected.size());
  for (size_t i = 0; i < ladder.size(); ++i)
  {
    EXPECT_NEAR(ladder[i], expected[i], 1e-15);
  }
  EXPECT_NEAR(GreedyCuts::LadderFloor(0.0199), 0.015, 1e-15);
  EXPECT_LE(GreedyCuts::LadderFloor(0.02), 0.02);
  EXPECT_NEAR(GreedyCuts::LadderFloor(0.07), 0.06, 1e-15);
  EXPECT_EQ(GreedyCuts::LadderFloor(0.0), 0.0);
  EXPECT_EQ(GreedyCuts::ToleranceLadder(0.01, 0.003).size(), 1u); // below the bottom: one level
}

// Session 21: the target search tries the level where the count is predicted to reach the target
// (the count as a power of the tolerance through the bracketing results) instead of the middle one.
// Counts that follow such a power exactly are bracketed in one step.
TEST(GreedyCuts, TargetSearchPredictsTheLevel)
{
  const std::vector<double> ladder = GreedyCuts::ToleranceLadder(0.004, 0.1);
  const int top = int(ladder.size()) - 1;
  auto levelOf = [&](double relative) {
    return int(std::find_if(ladder.begin(), ladder.end(), [&](double x) { return x >= relative * (1 - 1e-9); }) - ladder.begin());
  };
  // From the input (down = -1) and the top alone: count ~ 1 / epsilon; 20 at 0.1 gives 200 at 0.01.
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, -1, top, 100000, 20, 200), levelOf(0.01));
  // Below the bottom: the bottom level.
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, -1, top, 100000, 20, 5000), 0);
  // Between two results of count = 1 / epsilon^2: 0.005 -> 40,000, 0.05 -> 400; 2,500 at 0.02.
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, levelOf(0.005), levelOf(0.05), 40000, 400, 2500), levelOf(0.02));
  // Always strictly inside the bracket.
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, 3, 5, 1000, 10, 1), 4);
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, 3, 5, 1000, 999, 999), 4);
  // A wide bracket, so that the clamps are what is tested: a target under the coarse count gives
  // the level next to the coarse end, one over the fine count the level next to the fine end.
  ASSERT_GE(top, 4);
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, 0, top, 1000, 10, 1), top - 1);
  EXPECT_EQ(GreedyCuts::PredictedLevel(ladder, 0, top, 1000, 10, 5000), 1);
}

// On a mesh no other test uses, a target inside the ladder: the search brackets it in fewer level
// runs than a bisection needs to get down to adjacent levels (log2 of the levels, plus the top),
// within its work bound; the result is N or N - 1 triangles within its bound (measured).
TEST(GreedyCuts, TargetSearchRunsFewerLevelsThanABisection)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("head");
  const TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  GreedyCuts cuts;
  cuts.Initialize(mesh, PatchificationParameters());
  const double diagonal = mesh.BoundingBoxDiagonal();
  const Index target = mesh.NumberOfTriangles() / 10;
  GreedyCutsResult result;
  ASSERT_TRUE(cuts.RunForTarget(target, GreedyCutsParameters(), 1e-5 * diagonal, 0.1 * diagonal, 10, result));
  const size_t levels = GreedyCuts::ToleranceLadder(GreedyCutsParameters().LadderBottom, 0.1).size();
  const int bisection = 1 + int(std::ceil(std::log2(double(levels))));
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = result.Triangles;
  const double hausdorff = MeasureHausdorff(slodtest::ToPolyData(mesh), slodtest::ToPolyData(out));
  std::cout << "[greedy-cuts] head target " << target << ": " << out.NumberOfTriangles() << " tris at eps "
            << result.ErrorBound / diagonal << " of the diagonal, H/eps " << hausdorff / result.ErrorBound << ", "
            << cuts.TargetLevelsRun() << " levels run (a bisection: " << bisection << ")\n";
  EXPECT_FALSE(cuts.WorkBoundReached());
  EXPECT_LE(out.NumberOfTriangles(), target);
  EXPECT_GE(out.NumberOfTriangles(), target - 1);
  EXPECT_LE(hausdorff, result.ErrorBound * (1 + 1e-6));
  EXPECT_LT(cuts.TargetLevelsRun(), bisection);
}

// A target counts the final collapses: asked for N, the filter gives N or N - 1 triangles (a
// collapse removes one or two), each result within its bound. Before, the search compared the
// cuts' counts and the collapses then overshot (fandisk, target 1,500: 498). Meshes no other test
// uses; targets above and below what the ladder's bottom level gives.
TEST(GreedyCutsSimplification, TargetCountsTheFinalCollapses)
{
  for (const auto& [name, fraction] : { std::pair<std::string, double>{ "homer", 0.05 }, { "homer", 0.4 },
         { "handle", 0.1 }, { "blobby", 0.03 } })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const vtkIdType target = vtkIdType(fraction * double(input->GetNumberOfCells()));
    const Figures f = SimplifyToTarget(input, target);
    std::cout << "[greedy-cuts] " << name << " target " << target << ": " << f.Output->GetNumberOfCells()
              << " tris at eps " << f.Bound << ", H/eps " << f.Hausdorff / f.Bound << "\n";
    EXPECT_LE(f.Output->GetNumberOfCells(), target);
    EXPECT_GE(f.Output->GetNumberOfCells(), target - 1);
    ExpectValid(input, f, name);
  }
}

// The proved collapses' work bound: with MaximumProofPieces they stop once the caller's piece
// counter passes it, with fewer collapses than without, and what they did keep is within the
// bound (every accepted collapse was proved). Starting from the input itself (within any epsilon).
TEST(GreedyCuts, ProvedCollapsesStopAtTheirWorkBound)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("cow");
  const TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  TriangleBVH bvh;
  bvh.Build(mesh);
  ProvedCollapseParameters parameters;
  parameters.Epsilon = 0.01 * mesh.BoundingBoxDiagonal();
  std::vector<Index> free = mesh.Triangles, freePatches(mesh.Triangles.size() / 3, 0);
  long long freePieces = 0;
  ProvedCollapseStatistics unbounded, bounded;
  ASSERT_TRUE(ProvedCollapses(mesh, bvh, parameters, free, freePatches, unbounded, nullptr, &freePieces));
  EXPECT_FALSE(unbounded.WorkBoundReached);
  parameters.MaximumProofPieces = freePieces / 10;
  std::vector<Index> triangles = mesh.Triangles, patches(mesh.Triangles.size() / 3, 0);
  long long pieces = 0;
  ASSERT_TRUE(ProvedCollapses(mesh, bvh, parameters, triangles, patches, bounded, nullptr, &pieces));
  EXPECT_TRUE(bounded.WorkBoundReached);
  EXPECT_LT(pieces, freePieces / 2);
  EXPECT_GT(bounded.Collapses, 0);
  EXPECT_LT(bounded.Collapses, unbounded.Collapses);
  TriangleMesh out;
  out.Points = mesh.Points;
  out.Triangles = triangles;
  EXPECT_LE(MeasureHausdorff(input, slodtest::ToPolyData(out)), parameters.Epsilon);
}

// A target finer than a ladder level is collapsed at doubling tolerances from a sixteenth of the
// level up, so it carries the smallest tolerance that reached it instead of the level's whole
// bound (session 13: fandisk asked for 1,500 used the ladder's bottom, 0.004 of the diagonal, and
// measured 11 times vtkQuadricDecimation's Hausdorff at that count). Asserted: N or N - 1
// triangles with the full ExpectValid (measured Hausdorff within the reported bound), a bound below
// the ladder's bottom on fandisk with fewer than 5 % of triangles under 5 degrees (issue 15's goal),
// and on couplingdown (no other test uses it) at most twice vtkQuadricDecimation's triangles at
// equal measured Hausdorff: vtkQD at half our count does not measure below ours.
TEST(GreedyCutsSimplification, TargetsBelowALevelUseASmallerTolerance)
{
  for (const auto& [name, target] : { std::pair<std::string, vtkIdType>{ "fandisk", 1500 }, { "couplingdown", 1500 } })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const Figures f = SimplifyToTarget(input, target);
    vtkNew<vtkQuadricDecimation> quadric;
    quadric->SetInputData(input);
    quadric->SetTargetReduction(1.0 - 0.5 * double(f.Output->GetNumberOfCells()) / double(input->GetNumberOfCells()));
    quadric->Update();
    const double halfCountHausdorff = MeasureHausdorff(input, quadric->GetOutput());
    const double diagonal = input->GetLength();
    std::cout << "[greedy-cuts] " << name << " target " << target << ": " << f.Output->GetNumberOfCells()
              << " tris, bound " << f.Bound / diagonal << " of the diagonal, H/bound " << f.Hausdorff / f.Bound
              << ", " << 100 * SliverShare(f.Output, 5.0) << "% under 5 degrees; vtkQD at "
              << quadric->GetOutput()->GetNumberOfCells() << " tris: H " << halfCountHausdorff / diagonal << "\n";
    EXPECT_LE(f.Output->GetNumberOfCells(), target);
    EXPECT_GE(f.Output->GetNumberOfCells(), target - 1);
    ExpectValid(input, f, name);
    if (name == "fandisk")
    {
      vtkNew<vtkGreedyCutsSimplification> defaults; // SimplifyToTarget keeps the default ladder
      EXPECT_LT(f.Bound, defaults->GetLadderBottom() * diagonal * (1 - 1e-9));
      EXPECT_LT(SliverShare(f.Output, 5.0), 0.05);
    }
    else
    {
      EXPECT_GE(halfCountHausdorff, f.Hausdorff);
    }
  }
}

// The count rose with the tolerance at the search's own levels: a collapse whose input
// neighbourhood held more than 4,096 input triangles was refused, which bound more the coarser the
// output (femur 0.1 -> 268 triangles but 0.05 -> 216 and 0.02 -> 242; bunny00 0.1 -> 4,058 but 0.02 -> 600). Since
// session 19 the cap follows the input per output triangle. Asserted on three meshes: single runs
// at the ladder's top and the two levels the descent below it tries first never rise, each output
// with the full ExpectValid (measured Hausdorff within the bound). (The descent itself then finds
// no level over the target on these inputs; it stays for inputs whose collapses stall otherwise.)
TEST(GreedyCutsSimplification, SingleRunsDoNotRiseBetweenTheSearchLevels)
{
  for (const char* name : { "femur", "mushroom", "knot" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    vtkIdType finer = std::numeric_limits<vtkIdType>::max();
    for (const double relativeError : { 0.02, 0.05, 0.1 })
    {
      vtkNew<vtkGreedyCutsSimplification> filter;
      filter->SetInputData(input);
      filter->SetMaximumError(relativeError);
      filter->MonotoneInEpsilonOff();
      filter->Update();
      const Figures f = Collect(filter, input);
      const vtkIdType count = f.Output->GetNumberOfCells();
      std::cout << "[greedy-cuts] " << name << " " << relativeError << ": " << count << " tris, H/bound "
                << f.Hausdorff / f.Bound << "\n";
      EXPECT_LE(count, finer) << name << " rises at " << relativeError;
      ExpectValid(input, f, std::string(name) + " " + std::to_string(relativeError));
      finer = count;
    }
  }
}

// Border vertices are collapsed along their loops (by default since session 20): fewer border
// edges and triangles than with every border vertex the cuts kept, the same loops, components and
// genus, the bound measured.
TEST(GreedyCutsSimplification, BorderVerticesCollapseAlongTheirLoops)
{
  EXPECT_TRUE(vtkNew<vtkGreedyCutsSimplification>()->GetBorderCollapses());
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("elephant-with-holes");
  auto run = [&](bool border) {
    vtkNew<vtkGreedyCutsSimplification> filter;
    filter->SetInputData(input);
    filter->SetMaximumError(0.01);
    filter->SetBorderCollapses(border);
    filter->Update();
    return Collect(filter, input);
  };
  const Figures kept = run(false), collapsed = run(true);
  const MeshStatistics before = ComputeMeshStatistics(slodtest::RawTriangleMesh(kept.Output));
  const MeshStatistics after = ComputeMeshStatistics(slodtest::RawTriangleMesh(collapsed.Output));
  std::cout << "[greedy-cuts] elephant-with-holes 0.01: border kept " << kept.Output->GetNumberOfCells() << " tris, "
            << before.BoundaryEdges << " border edges; collapsed " << collapsed.Output->GetNumberOfCells() << " tris, "
            << after.BoundaryEdges << " border edges, H/bound " << collapsed.Hausdorff / collapsed.Bound << "\n";
  EXPECT_LT(after.BoundaryEdges, before.BoundaryEdges);
  EXPECT_LT(collapsed.Output->GetNumberOfCells(), kept.Output->GetNumberOfCells());
  ExpectValid(input, kept, "border kept");
  ExpectValid(input, collapsed, "border collapsed");
}

// The guard of border collapses, on a flat strip of 24 x 1 squares (every vertex on the border, so
// every collapse is a border collapse, and every collapse that keeps the strip's outline is within
// any epsilon: without the guard the long sides collapse onto a few vertices, into fans of
// triangles of about 2 degrees). With it: collapses are made, some are refused for their star, no
// triangle is thinner than 5 degrees (the input's are 45) and no vertex has more than 12
// triangles; the loop, the Euler characteristic and the measured bound are kept.
TEST(GreedyCuts, BorderCollapsesMakeNoSliverAndNoLargeFan)
{
  TriangleMesh strip = slodtest::Grid(24, 1);
  for (Index v = 0; v < strip.NumberOfPoints(); ++v)
  {
    strip.Points[size_t(3 * v + 1)] /= 24.0; // squares
  }
  TriangleBVH bvh;
  bvh.Build(strip);
  ProvedCollapseParameters parameters;
  parameters.Epsilon = 0.01 * strip.BoundingBoxDiagonal();
  parameters.BorderCollapses = true;
  std::vector<Index> triangles = strip.Triangles, patches(strip.Triangles.size() / 3, 0);
  ProvedCollapseStatistics statistics;
  ASSERT_TRUE(ProvedCollapses(strip, bvh, parameters, triangles, patches, statistics));
  TriangleMesh out;
  out.Points = strip.Points;
  out.Triangles = triangles;
  double smallest = HUGE_VAL;
  std::map<Index, int> valence;
  for (Index t = 0; t < out.NumberOfTriangles(); ++t)
  {
    const Index* tri = out.Triangle(t);
    smallest = std::min(smallest, MinimumAngle(out.Point(tri[0]), out.Point(tri[1]), out.Point(tri[2])));
    for (int k = 0; k < 3; ++k)
    {
      ++valence[tri[k]];
    }
  }
  int largest = 0;
  for (const auto& [vertex, count] : valence)
  {
    largest = std::max(largest, count);
  }
  std::cout << "[greedy-cuts] strip 24 x 1: " << out.NumberOfTriangles() << " tris, " << statistics.Collapses
            << " collapses, " << statistics.BorderGuardRejections << " refused by the guard, smallest angle "
            << smallest * 180 / 3.14159265358979 << " degrees, largest valence " << largest << "\n";
  EXPECT_GT(statistics.Collapses, 0);
  EXPECT_GT(statistics.BorderGuardRejections, 0);
  EXPECT_LT(out.NumberOfTriangles(), strip.NumberOfTriangles());
  EXPECT_GE(smallest, Radians(5.0) * (1 - 1e-12));
  EXPECT_LE(largest, 12);
  EXPECT_LE(MeasureHausdorff(slodtest::ToPolyData(strip), slodtest::ToPolyData(out)), parameters.Epsilon);
  const MeshStatistics before = ComputeMeshStatistics(strip);
  out.RemoveUnusedPoints();
  const MeshStatistics after = ComputeMeshStatistics(out);
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.NonManifoldEdges, 0);
  EXPECT_EQ(after.InconsistentlyOrientedEdges, 0);
}
