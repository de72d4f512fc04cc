// SPDX-License-Identifier: BSD-3-Clause
// vtkQuadricTriangleCollapse: properties on real meshes (counts, topology, orientation, flips,
// borders, determinism, point data, error arrays, stop criteria), bad input, and quality against
// vtkQuadricDecimation measured in the same run with vtkSurfaceDeviation.
#include "BadInputCorpus.h"
#include "TestSupport.h"

#include "slodBucketQueue.h"
#include "slodCollapsePasses.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodTriangleCollapse.h"
#include "slodUnionFind.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkScanSurfaceSource.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFlyingEdges3D.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSMPTools.h"
#include "vtkStaticCellLocator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <limits>
#include <tuple>

using namespace slod;

namespace
{
vtkSmartPointer<vtkPolyData> Collapse(vtkPolyData* input, vtkIdType target, double reduction = 0.0)
{
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(target);
  filter->SetTargetReduction(reduction);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

// Two-sided deviation of `output` from `input` (relative to the diagonal; `samples` per side plus
// the vertices).
void Deviation(vtkPolyData* input, vtkPolyData* output, double& hausdorff, double& mean, vtkIdType samples = 300000)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(input);
  deviation->SetComparedData(output);
  deviation->SetNumberOfSamples(samples);
  deviation->Update();
  hausdorff = deviation->GetHausdorffRelative();
  mean = deviation->GetMeanRelative();
}

vtkSmartPointer<vtkPolyData> Mesh(const std::string& name)
{
  if (name == "marching-cubes")
  {
    static vtkSmartPointer<vtkPolyData> mc = slodtest::SyntheticIsosurface(112);
    return mc;
  }
  return slodtest::LoadTestMesh(name);
}

// A copy of `mesh` with the point array "f" = dot(g, p).
vtkSmartPointer<vtkPolyData> WithLinearField(vtkPolyData* mesh, const Vec3& g)
{
  vtkSmartPointer<vtkPolyData> out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(mesh);
  vtkNew<vtkDoubleArray> f;
  f->SetName("f");
  f->SetNumberOfTuples(out->GetNumberOfPoints());
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    f->SetValue(i, g[0] * p[0] + g[1] * p[1] + g[2] * p[2]);
  }
  out->GetPointData()->AddArray(f);
  return out;
}

// Area fraction of `out` whose triangles face against the closest triangle of `input`.
double FlippedAreaFraction(vtkPolyData* input, const TriangleMesh& out)
{
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(input);
  locator->BuildLocator();
  double flippedArea = 0, totalArea = 0;
  for (Index t = 0; t < out.NumberOfTriangles(); ++t)
  {
    const Index* tri = out.Triangle(t);
    const Vec3 a = out.Point(tri[0]), b = out.Point(tri[1]), c = out.Point(tri[2]);
    const Vec3 n = Cross(b - a, c - a);
    Vec3 centroid = (1.0 / 3.0) * (a + b + c);
    double closest[3], dist2;
    vtkIdType cell;
    int subId;
    locator->FindClosestPoint(centroid.data(), closest, cell, subId, dist2);
    const vtkIdType* ids;
    vtkIdType npts;
    input->GetCellPoints(cell, npts, ids);
    double p[3][3];
    for (int k = 0; k < 3; ++k)
    {
      input->GetPoint(ids[k], p[k]);
    }
    const Vec3 on = Cross(Vec3{ p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] },
      Vec3{ p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] });
    totalArea += Norm(n);
    flippedArea += Dot(n, on) < 0 ? Norm(n) : 0.0;
  }
  return totalArea > 0 ? flippedArea / totalArea : 0.0;
}

} // namespace

class TriangleCollapseOnMesh : public ::testing::TestWithParam<const char*>
{
};

TEST_P(TriangleCollapseOnMesh, KeepsTopologyOrientationAndHitsTarget)
{
  vtkSmartPointer<vtkPolyData> input = Mesh(GetParam());
  const TriangleMesh in = slodtest::ToTriangleMesh(input);
  for (double fraction : { 0.1, 0.01 })
  {
    const vtkIdType target = std::max<vtkIdType>(4, vtkIdType(fraction * in.NumberOfTriangles()));
    vtkSmartPointer<vtkPolyData> output = Collapse(input, target);
    const TriangleMesh out = slodtest::RawTriangleMesh(output);
    SCOPED_TRACE(std::string(GetParam()) + " to " + std::to_string(target));
    // The target is met within one collapse (at most 4 triangles per collapse).
    EXPECT_LE(out.NumberOfTriangles(), target);
    EXPECT_GE(out.NumberOfTriangles(), target - 3);
    slodtest::ExpectSameTopology(in, out);
    EXPECT_EQ(ComputeMeshStatistics(out).Vertices, out.NumberOfPoints()); // no unused points

    // No flipped triangles: each output triangle faces the same way as the original surface at
    // its centroid. Where a coarse surface cuts across thin parts the closest original triangle
    // can face elsewhere, so the flipped area fraction is compared with vtkQuadricDecimation's
    // at the same count (same measure, same run): at most twice it plus 0.5 %.
    vtkNew<vtkQuadricDecimation> reference;
    reference->SetInputData(input);
    reference->SetTargetReduction(1.0 - double(target) / in.NumberOfTriangles());
    reference->Update();
    const double ours = FlippedAreaFraction(input, out);
    const double theirs = FlippedAreaFraction(input, slodtest::RawTriangleMesh(reference->GetOutput()));
    std::printf("[flips] %s to %lld: flipped area fraction %.5f (vtkQuadricDecimation %.5f)\n", GetParam(),
      (long long)target, ours, theirs);
    EXPECT_LE(ours, 2.0 * theirs + 0.005);
  }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, TriangleCollapseOnMesh,
  ::testing::Values("fandisk", "femur", "bunny00", "armadillo", "marching-cubes", "holes", "mech-holes-shark"));

TEST(QuadricTriangleCollapse, OpenGridKeepsItsBorder)
{
  // A bumpy open grid: the border must stay on the square's sides and its corners must stay.
  TriangleMesh grid = slodtest::Grid(40, 40);
  for (Index v = 0; v < grid.NumberOfPoints(); ++v)
  {
    Vec3 p = grid.Point(v);
    p[2] = 0.05 * std::sin(6 * p[0]) * std::cos(5 * p[1]);
    grid.SetPoint(v, p);
  }
  vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(grid);
  vtkSmartPointer<vtkPolyData> output = Collapse(input, grid.NumberOfTriangles() / 10);
  const TriangleMesh out = slodtest::RawTriangleMesh(output);
  const MeshStatistics s = ComputeMeshStatistics(out);
  EXPECT_EQ(s.BoundaryLoops, 1);
  EXPECT_EQ(s.Genus, 0);
  MeshTopology topology(out);
  int corners = 0;
  for (Index v = 0; v < out.NumberOfPoints(); ++v)
  {
    if (!topology.IsBoundaryVertex(v))
    {
      continue;
    }
    const Vec3 p = out.Point(v);
    const double side = std::min({ std::fabs(p[0]), std::fabs(p[0] - 1), std::fabs(p[1]), std::fabs(p[1] - 1) });
    // The boundary planes stand perpendicular to the (bumpy, tilted) border triangles, so the
    // border may move by a tiny fraction of the grid spacing (1/40), never more.
    EXPECT_LT(side, 1e-3) << "border vertex left the border";
    const bool corner = (std::fabs(p[0]) < 1e-3 || std::fabs(p[0] - 1) < 1e-3) && (std::fabs(p[1]) < 1e-3 || std::fabs(p[1] - 1) < 1e-3);
    corners += corner ? 1 : 0;
  }
  EXPECT_EQ(corners, 4);
}

// An open range scan with holes (vtkScanSurfaceSource, two resolutions): with the default
// BoundaryWeight the borders are held at least as tightly as vtkQuadricDecimation holds them, so
// the Hausdorff distance at the same count is no larger (with Garland and Heckbert's weight 1 the
// outline and the holes' rims were cut: 1.7-2.1x vtkQuadricDecimation's), the mean no worse and
// every border loop kept.
TEST(QuadricTriangleCollapse, OpenScanBordersHeldAsTightlyAsQuadricDecimation)
{
  // The filter's default is the core's (the ParaView XML's is checked against the filter's).
  vtkNew<vtkQuadricTriangleCollapse> defaults;
  EXPECT_EQ(defaults->GetBoundaryWeight(), DefaultBorderPlaneWeight);
  EXPECT_EQ(TriangleCollapseOptions().BoundaryWeight, DefaultBorderPlaneWeight);
  for (int resolution : { 120, 200 })
  {
    vtkNew<vtkScanSurfaceSource> source;
    source->SetKindToOpenScan();
    source->SetResolution(resolution);
    source->Update();
    vtkPolyData* input = source->GetOutput();
    vtkNew<vtkQuadricDecimation> reference;
    reference->SetInputData(input);
    reference->SetTargetReduction(0.9);
    reference->Update();
    const vtkIdType count = reference->GetOutput()->GetNumberOfPolys();
    vtkSmartPointer<vtkPolyData> ours = Collapse(input, count);
    ASSERT_LE(ours->GetNumberOfPolys(), count);
    double hOurs, mOurs, hVtk, mVtk;
    Deviation(input, reference->GetOutput(), hVtk, mVtk, 100000);
    Deviation(input, ours, hOurs, mOurs, 100000);
    std::printf("[open scan] resolution %d to %lld: Hausdorff %.4e vs vtkQuadricDecimation %.4e, mean %.4e vs %.4e\n",
      resolution, (long long)count, hOurs, hVtk, mOurs, mVtk);
    EXPECT_LE(hOurs, hVtk) << "resolution " << resolution;
    EXPECT_LE(mOurs, 1.01 * mVtk) << "resolution " << resolution;
    const MeshStatistics in = ComputeMeshStatistics(slodtest::RawTriangleMesh(input));
    const MeshStatistics out = ComputeMeshStatistics(slodtest::RawTriangleMesh(ours));
    EXPECT_EQ(out.BoundaryLoops, in.BoundaryLoops) << "resolution " << resolution;
    EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic) << "resolution " << resolution;
  }
}

TEST(QuadricTriangleCollapse, Deterministic)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("bunny00");
  vtkSmartPointer<vtkPolyData> a = Collapse(input, 2306), b = Collapse(input, 2306);
  const TriangleMesh ma = slodtest::RawTriangleMesh(a), mb = slodtest::RawTriangleMesh(b);
  EXPECT_EQ(ma.Points, mb.Points);
  EXPECT_EQ(ma.Triangles, mb.Triangles);
}

// The initial costs are computed in parallel: the output must not depend on the thread count.
TEST(QuadricTriangleCollapse, SameOutputForAnyThreadCount)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("armadillo");
  std::vector<TriangleMesh> outputs;
  slodtest::ForOneTwoAndEightThreads([&](int) { outputs.push_back(slodtest::RawTriangleMesh(Collapse(input, 5000))); });
  for (size_t i = 1; i < outputs.size(); ++i)
  {
    EXPECT_EQ(outputs[0].Points, outputs[i].Points);
    EXPECT_EQ(outputs[0].Triangles, outputs[i].Triangles);
  }
}

// The filter's output, set up by configure (and looked at by inspect after its update), with 1, 2
// and 8 threads; the thread count is restored afterwards.
template <typename Configure, typename Inspect = void (*)(vtkQuadricTriangleCollapse*)>
std::vector<TriangleMesh> OutputsForOneTwoAndEightThreads(
  vtkPolyData* input, Configure&& configure, Inspect&& inspect = [](vtkQuadricTriangleCollapse*) {})
{
  std::vector<TriangleMesh> outputs;
  slodtest::ForOneTwoAndEightThreads([&](int) {
    vtkNew<vtkQuadricTriangleCollapse> filter;
    filter->SetInputData(input);
    configure(filter.Get());
    filter->Update();
    inspect(filter.Get());
    outputs.push_back(slodtest::RawTriangleMesh(filter->GetOutput()));
  });
  return outputs;
}

// The algorithm on `input` with `options`, run with 1, 2 and 8 threads (restored afterwards).
std::vector<TriangleCollapseResult> ResultsForOneTwoAndEightThreads(
  vtkPolyData* input, const TriangleCollapseOptions& options)
{
  std::vector<TriangleCollapseResult> results;
  slodtest::ForOneTwoAndEightThreads([&](int) {
    TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    results.emplace_back();
    SimplifyByTriangleCollapse(mesh, options, results.back());
  });
  return results;
}

// The input surface is kept through the collapses for the passes after them (fit, refinement),
// in floats when every coordinate is a float (a float input read into doubles), and packed
// through the collapses (nobody reads it before they end); without those passes it is not kept.
// Bounds from the layout: the sphere has under 2^13 vertices, so every difference of two vertex
// ids, zigzagged, is below 2^14 and takes at most 2 varint bytes: a packed triangle at most 6
// bytes (12 unpacked), and a coordinate at most 5 bytes as a float's bits (4 unpacked), 10 as a
// double's. With the passes the collapser also keeps a parent id per vertex (4 bytes).
TEST(QuadricTriangleCollapse, KeepsTheInputPackedAndInFloatsWhenItsCoordinatesAreFloats)
{
  const TriangleMesh floats = slodtest::Sphere(90, 80);
  ASSERT_LT(floats.NumberOfPoints(), 1 << 13);
  TriangleMesh doubles = floats;
  // One coordinate that a float cannot hold: 2^-40 of a coordinate of 0.5 or more.
  const auto large = std::find_if(doubles.Points.begin(), doubles.Points.end(), [](double x) { return x >= 0.5; });
  ASSERT_NE(large, doubles.Points.end());
  *large += std::ldexp(*large, -40);
  ASSERT_NE(static_cast<double>(static_cast<float>(*large)), *large);
  const double vertices = floats.NumberOfPoints(), triangles = floats.NumberOfTriangles();
  size_t withoutPasses[2] = { 0, 0 }, withPasses[2] = { 0, 0 };
  for (const bool passes : { false, true })
  {
    TriangleCollapseOptions options;
    options.TargetTriangles = floats.NumberOfTriangles() / 10;
    options.FitToOriginal = options.RefineDeviation = passes;
    TriangleMesh a = floats, b = doubles;
    TriangleCollapseResult fromFloats, fromDoubles;
    SimplifyByTriangleCollapse(a, options, fromFloats);
    SimplifyByTriangleCollapse(b, options, fromDoubles);
    (passes ? withPasses : withoutPasses)[0] = fromFloats.PeakWorkingBytes;
    (passes ? withPasses : withoutPasses)[1] = fromDoubles.PeakWorkingBytes;
  }
  const double keptFloats = (double(withPasses[0]) - double(withoutPasses[0])) / vertices;
  const double keptDoubles = (double(withPasses[1]) - double(withoutPasses[1])) / vertices;
  std::printf("[input kept] bytes per vertex: floats %.2f, doubles %.2f; without the passes %.2f apart\n", keptFloats,
    keptDoubles, (double(withoutPasses[1]) - double(withoutPasses[0])) / vertices);
  // Unpacked it was 12 bytes per triangle and 12 (floats) or 24 (doubles) per vertex.
  EXPECT_LE(keptFloats, (6 * triangles + 15 * vertices) / vertices + 4);
  EXPECT_LE(keptDoubles, (6 * triangles + 30 * vertices) / vertices + 4);
  EXPECT_LT(keptFloats, keptDoubles) << "the float input is not kept in floats";
  EXPECT_LT(std::abs(double(withoutPasses[1]) - double(withoutPasses[0])) / vertices, 1.0);
}

// With ReloadInput (the filter's, when its preparation changed nothing) the passes after the
// collapses read the input again once the collapses end, so no copy of it is held through them:
// the peak is below the kept run's by at least the packed copy's least size (each corner and each
// coordinate is a varint of at least one byte), the reload is asked for once, and the output is
// the same (the passes see the same surface). Before session 39 the input was always kept.
TEST(QuadricTriangleCollapse, ReloadedInputIsNotKeptThroughTheCollapses)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  const double vertices = sphere.NumberOfPoints(), triangles = sphere.NumberOfTriangles();
  size_t peak[2] = { 0, 0 };
  TriangleMesh output[2];
  Index moved[2] = { 0, 0 };
  int reloads = 0;
  for (const bool reload : { false, true })
  {
    TriangleMesh mesh = sphere;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    if (reload)
    {
      options.ReloadInput = [&sphere, &reloads](TriangleMesh& input) {
        input = sphere;
        ++reloads;
      };
    }
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    peak[reload ? 1 : 0] = result.PeakWorkingBytes;
    moved[reload ? 1 : 0] = result.FittedVertices + result.RefinedVertices;
    output[reload ? 1 : 0] = result.Mesh;
  }
  std::printf("[reloaded input] peak %.2f bytes per vertex less than with the input kept\n",
    (double(peak[0]) - double(peak[1])) / vertices);
  EXPECT_EQ(reloads, 1);
  EXPECT_GT(moved[0], 0) << "the passes after the collapses moved nothing: the test sees no use of the input";
  EXPECT_EQ(moved[1], moved[0]);
  EXPECT_EQ(output[1].Points, output[0].Points);
  EXPECT_EQ(output[1].Triangles, output[0].Triangles);
  EXPECT_GE(double(peak[0]) - double(peak[1]), 3 * (vertices + triangles));
}

// The working set's peak (PeakWorkingBytes) within the sum of its arrays' layouts, with the
// packed parts at their bounds (above). Per vertex: points 24, quadrics 88, reference starts and
// counts 8, flags 4 (alive, border, locked, pending), the kept points packed 15, the input ids
// packed 2; per triangle: corners 12, references 3 x 4 with the room factor, state 16 (with the
// queue's bucket number since session 44), queue 12 (entry 8, slot 4; 14 before, with an array of
// bucket numbers), alive 1, the kept corners packed 6, the input ids packed 2; and the
// queue's 2^15 bucket headers. Not in it (session 31): the mesh's per-vertex link marks (12 bytes;
// the checks use small tables of their own) and an array of parents (4 bytes; a merged-away
// vertex's quadric slot holds its parent): with either the bound is exceeded. Unpacked through
// the collapses (before session 24) the kept input and the ids were 8 bytes per triangle and 1
// per vertex more. The topology-changing mode still uses the marks (checked below).
TEST(QuadricTriangleCollapse, PeakWorkingBytesWithinTheLayoutOfItsArrays)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  ASSERT_LT(sphere.NumberOfPoints(), 1 << 13);
  const double vertices = sphere.NumberOfPoints(), triangles = sphere.NumberOfTriangles();
  const double references = 3 * 4 * EditableMesh::ShrinkingMeshRoomFactor;
  const double scratch = 4096; // the mesh's scratch lists: a few fans
  const double bound = vertices * (24 + 88 + 8 + 4 + 15 + 2) +
    triangles * (12 + references + 16 + 12 + 1 + 6 + 2) + double(1 << 15) * sizeof(std::vector<int>) + scratch;
  size_t peak[2] = { 0, 0 };
  for (const bool topologyChange : { false, true })
  {
    TriangleMesh mesh = sphere;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    options.AllowTopologyChange = topologyChange;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    EXPECT_LE(mesh.NumberOfTriangles(), options.TargetTriangles);
    peak[topologyChange ? 1 : 0] = result.PeakWorkingBytes;
  }
  std::printf("[peak] %.1f bytes per vertex (with AllowTopologyChange %.1f), bound %.1f\n", double(peak[0]) / vertices,
    double(peak[1]) / vertices, bound / vertices);
  EXPECT_LE(double(peak[0]), bound);
  // With the mesh's marks: 12 bytes per vertex more, less the locked flags (1), which that mode
  // does not hold.
  EXPECT_GE(double(peak[1]) - double(peak[0]), 11 * vertices);
}

// The queue's share of the working set's peak is its slot and its entry (key, id) per triangle and
// its 2^15 bucket headers, nothing more: each triangle's bucket number lives in the two bytes of
// its 16-byte state that were padding (BasicBucketQueue::LendBucketIds, session 44; before, an
// array of the queue's own, 2 bytes per triangle). Measured as the difference between the peaks of
// the same mesh simplified with the queue and with the pass schedule, which holds the same arrays
// (the same triangle state included) but no queue and no pending flags (a byte per vertex).
TEST(QuadricTriangleCollapse, QueueHoldsOnlyItsSlotsEntriesAndBucketHeaders)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  const double vertices = sphere.NumberOfPoints(), triangles = sphere.NumberOfTriangles();
  size_t peak[2] = { 0, 0 };
  for (const bool passes : { false, true })
  {
    TriangleMesh mesh = sphere;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    options.Schedule = passes ? CollapseSchedule::Passes : CollapseSchedule::Queue;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    EXPECT_LE(mesh.NumberOfTriangles(), options.TargetTriangles);
    EXPECT_EQ(result.Passes > 0, passes);
    peak[passes ? 1 : 0] = result.PeakWorkingBytes;
  }
  const double queue = double(peak[0]) - double(peak[1]);
  const double headers = double(1 << BucketQueue::BucketBits) * sizeof(std::vector<std::pair<float, Index>>);
  const double slotAndEntry = triangles * (sizeof(Index) + sizeof(float) + sizeof(Index));
  std::printf("[queue] %.2f bytes per triangle beyond its bucket headers (slot and entry %.0f)\n",
    (queue - headers - vertices) / triangles, slotAndEntry / triangles);
  EXPECT_GE(queue, slotAndEntry + headers);
  EXPECT_LE(queue, slotAndEntry + headers + vertices); // (the pending flags)
}

// The locked flags (a byte per vertex) are held through the collapses only when a vertex is
// locked: a closed manifold sphere has none, the same sphere with one vertex locked by the caller
// has one. The working sets at the loop's start differ by those flags alone (the same arrays
// otherwise; the queue's entries are one per triangle either way), so by at least a byte per vertex.
// Before session 37 a manifold input held an all-zero array and the two differed by nothing.
TEST(QuadricTriangleCollapse, HoldsLockedFlagsOnlyWhenAVertexIsLocked)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  const double vertices = sphere.NumberOfPoints();
  std::vector<unsigned char> oneLocked(sphere.NumberOfPoints(), 0);
  oneLocked[oneLocked.size() / 2] = 1;
  size_t peak[2] = { 0, 0 };
  for (const bool lock : { false, true })
  {
    TriangleMesh mesh = sphere;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    options.LockedVertices = lock ? &oneLocked : nullptr;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    EXPECT_LE(mesh.NumberOfTriangles(), options.TargetTriangles);
    peak[lock ? 1 : 0] = result.PeakWorkingBytes;
  }
  std::printf("[locked flags] %.2f bytes per vertex more with one vertex locked\n",
    (double(peak[1]) - double(peak[0])) / vertices);
  EXPECT_GE(double(peak[1]) - double(peak[0]), vertices);
}

// A mesh as vtkQuadricTriangleCollapse hands it to the collapses, with the input preparation's
// per-vertex flags: a bumpy open grid (one border loop) or a closed sphere.
static TriangleMesh PreparedWithFlags(bool open, PreparationReport& report)
{
  TriangleMesh raw = open ? slodtest::Grid(40, 40) : slodtest::Sphere(90, 80);
  for (Index v = 0; open && v < raw.NumberOfPoints(); ++v)
  {
    Vec3 p = raw.Point(v);
    p[2] = 0.05 * std::sin(6 * p[0]) * std::cos(5 * p[1]);
    raw.SetPoint(v, p);
  }
  TriangleMesh mesh;
  std::vector<Index> vertexToInput;
  report = PrepareTriangleMesh(slodtest::ToPolyData(raw), PreparationOptions(), mesh, vertexToInput);
  EXPECT_TRUE(report.Valid);
  EXPECT_EQ(report.NonManifoldVertexFlags.size(), size_t(mesh.NumberOfPoints()));
  return mesh;
}

// The prepared mesh to 10 %: result[0] without the caller's flags, result[1] with them (`give`
// sets them in the options).
template <class Give>
static void CollapseWithoutAndWithFlags(const TriangleMesh& prepared, Give&& give, TriangleCollapseResult result[2])
{
  for (const bool given : { false, true })
  {
    TriangleMesh mesh = prepared;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    if (given)
    {
      give(options);
    }
    SimplifyByTriangleCollapse(mesh, options, result[given ? 1 : 0]);
  }
}

// The caller's non-manifold flags (a byte per input vertex) are read by the collapses' set-up and
// released there: held by the filter until the end (before session 43) they sat beside the
// working set at its peak. The output is the same as with the flags computed by the collapses.
TEST(QuadricTriangleCollapse, CallersNonManifoldFlagsAreReleasedBeforeTheCollapses)
{
  for (const bool open : { true, false })
  {
    PreparationReport report;
    const TriangleMesh prepared = PreparedWithFlags(open, report);
    TriangleCollapseResult result[2];
    CollapseWithoutAndWithFlags(
      prepared, [&](TriangleCollapseOptions& options) { options.NonManifoldVertices = &report.NonManifoldVertexFlags; },
      result);
    EXPECT_TRUE(report.NonManifoldVertexFlags.empty()) << "the caller's flags were held through the collapses";
    EXPECT_EQ(report.NonManifoldVertexFlags.capacity(), 0u);
    EXPECT_EQ(result[1].Mesh.Points, result[0].Mesh.Points);
    EXPECT_EQ(result[1].Mesh.Triangles, result[0].Mesh.Triangles);
  }
}

// With the preparation's border flags (session 43) the quadrics search for border edges only at
// the flagged vertices' fans (none on a closed mesh; before, every vertex's fan was sorted), the
// flags are released by the set-up, and the output is bit for bit the one without them.
TEST(QuadricTriangleCollapse, BorderFlagsLimitTheQuadricsBorderSearch)
{
  for (const bool open : { true, false })
  {
    PreparationReport report;
    const TriangleMesh prepared = PreparedWithFlags(open, report);
    const long long flagged = std::count(report.BoundaryVertexFlags.begin(), report.BoundaryVertexFlags.end(), 1);
    EXPECT_EQ(flagged > 0, open);
    TriangleCollapseResult result[2];
    CollapseWithoutAndWithFlags(
      prepared, [&](TriangleCollapseOptions& options) { options.BorderVertices = &report.BoundaryVertexFlags; }, result);
    std::printf("[border search] %s: %lld of %lld vertices searched with the flags\n", open ? "open grid" : "sphere",
      result[1].BorderSearches, result[0].BorderSearches);
    EXPECT_EQ(result[0].BorderSearches, prepared.NumberOfPoints());
    EXPECT_EQ(result[1].BorderSearches, flagged);
    EXPECT_TRUE(report.BoundaryVertexFlags.empty()) << "the caller's flags were held through the collapses";
    EXPECT_EQ(result[1].Mesh.Points, result[0].Mesh.Points);
    EXPECT_EQ(result[1].Mesh.Triangles, result[0].Mesh.Triangles);
    EXPECT_EQ(result[1].MaximumError, result[0].MaximumError);
  }
}

// The quadrics compute each triangle's plane for its three corners together (session 43), not
// once per corner: on the sphere and the marching-cubes mesh (vertices in Morton order, blocks of
// 4,096) well under two planes per triangle (before, exactly three), and the output is the one
// of the runs before (the same values summed in the same order: the other tests' outputs).
TEST(QuadricTriangleCollapse, QuadricsComputeEachTrianglePlaneAboutOnce)
{
  for (const bool sphere : { true, false })
  {
    TriangleMesh mesh = sphere ? slodtest::Sphere(90, 80) : slodtest::ToTriangleMesh(Mesh("marching-cubes"));
    const double triangles = mesh.NumberOfTriangles();
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    std::printf("[triangle planes] %s: %.3f per triangle\n", sphere ? "sphere" : "marching cubes",
      double(result.TrianglePlanes) / triangles);
    EXPECT_GE(double(result.TrianglePlanes), triangles);
    EXPECT_LT(double(result.TrianglePlanes), 1.5 * triangles);
  }
}

// Session 44's counters, read where the library has them; -1 where it does not (the test then
// fails by its assertions on a library without them, e.g. base-s44, instead of not compiling).
struct LoopCounters
{
  long long Reused = -1, Gathers = -1;
};
template <class R>
auto LoopCountersOf(const R& r, int) -> decltype(r.TopologyTestsReused + r.OneRingGathers, LoopCounters())
{
  return { r.TopologyTestsReused, r.OneRingGathers };
}
template <class R>
LoopCounters LoopCountersOf(const R&, long)
{
  return {};
}

// The strict order's validity tests on a noisy scan (handles, non-manifold edges): an edge whose
// collapse would make a non-manifold edge is popped by its two triangles one after the other, and
// the second test, with no collapse in between, takes the first one's status instead of gathering
// and walking the one-ring again (session 44). Each test gathers its set's triangles at most once
// (the alternative placements of a folding optimum borrow the check's), a reused one never: the
// gatherings are bounded by the tests that were not reused.
TEST(QuadricTriangleCollapse, FailedTopologiesAreNotTestedAgainBeforeACollapse)
{
  for (const unsigned seed : { 3u, 11u })
  {
    TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::NoisyScanIsosurface(40, seed));
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    const LoopCounters counters = LoopCountersOf(result, 0);
    const long long reused = counters.Reused, gathers = counters.Gathers;
    std::printf("[failed topologies] seed %u: %d collapses, %lld validity tests (%d rejected), %lld reused, "
                "%lld one-ring gathers\n",
      seed, int(result.Collapses), result.ValidityTests, int(result.RejectedCollapses), reused, gathers);
    EXPECT_GT(result.Collapses, 0);
    EXPECT_GT(result.RejectedCollapses, 0) << "the scan's handles should refuse some collapses";
    EXPECT_GT(reused, 0) << "no repeated failed test was answered without a check";
    EXPECT_LE(reused, static_cast<long long>(result.RejectedCollapses)) << "only failed sets are remembered";
    EXPECT_GT(gathers, 0);
    EXPECT_LE(gathers + reused, result.ValidityTests) << "a test gathered its set more than once";
  }
}

// The sphere to 10 % with the records, which are then replayed on the input: per collapse the
// triangles around its new vertex right after it (the fan) and that vertex's distinct
// neighbours (the spokes), summed over the collapses.
struct ReplayedFans
{
  TriangleCollapseResult Result;
  long long Fans = 0, Spokes = 0;
};
static ReplayedFans CollapseAndReplayFans(const TriangleMesh& sphere, bool edges, bool triangleCostBound = false)
{
  TriangleCollapseOptions options;
  options.TargetTriangles = sphere.NumberOfTriangles() / 10;
  options.RecordHistory = true;
  options.EdgeCollapses = edges;
  options.TriangleCostBound = triangleCostBound;
  ReplayedFans replayed;
  TriangleCollapseResult& result = replayed.Result;
  TriangleMesh consumed = sphere;
  SimplifyByTriangleCollapse(consumed, options, result);
  EXPECT_GT(result.Collapses, 0);
  EXPECT_EQ(result.History.NumberOfCollapses(), result.Collapses);
  EXPECT_EQ(result.History.NumberOfFlips(), 0);
  EditableMesh replay(sphere);
  CollapseRecord scratch;
  std::vector<Index> neighbours;
  for (Index k = 0; k < result.History.NumberOfCollapses(); ++k)
  {
    result.History.Redo(k, replay, scratch);
    const Index kept = result.History.Vertices[3 * size_t(k)];
    neighbours.clear();
    replay.ForEachTriangle(kept, [&](Index t) {
      ++replayed.Fans;
      for (int c = 0; c < 3; ++c)
      {
        const Index v = replay.Triangle(t)[c];
        if (v != kept && std::find(neighbours.begin(), neighbours.end(), v) == neighbours.end())
        {
          neighbours.push_back(v);
        }
      }
    });
    replayed.Spokes += static_cast<long long>(neighbours.size());
  }
  // The records replay the run: the replayed mesh has the output's triangles.
  EXPECT_EQ(replay.NumberOfLiveTriangles(), result.Mesh.NumberOfTriangles());
  return replayed;
}

// The loop's work per collapse (session 38): a collapse rewrites the queue keys of the triangles
// around its new vertex, each once, and no others. KeyUpdates must equal the sum of those fans,
// counted by replaying the records on the input (each fan right after its collapse); a wider
// update or a triangle keyed twice per collapse would exceed it.
TEST(QuadricTriangleCollapse, KeyUpdatesAreTheFansOfTheNewVertices)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  for (const bool edges : { true, false })
  {
    const ReplayedFans replayed = CollapseAndReplayFans(sphere, edges);
    const TriangleCollapseResult& result = replayed.Result;
    ASSERT_GT(result.Collapses, 0);
    std::printf("[key updates] edge collapses %s: %.2f per collapse\n", edges ? "on" : "off",
      double(result.KeyUpdates) / double(result.Collapses));
    EXPECT_EQ(result.KeyUpdates, replayed.Fans);
  }
}

// The placements (quadric solves) behind those keys (session 39): with the edge cache each
// triangle of the new vertex's fan is placed once and each spoke (new vertex, neighbour) once,
// shared by its two triangles; without it (edge collapses off) each triangle's one operation.
// FanPlacements must equal that count from the replayed records: a spoke placed for each of its
// triangles, or a placement repeated, exceeds it. Each validity test ends in a collapse, a
// rejection or an alternative placement, so the tests are at least the collapses and rejections.
TEST(QuadricTriangleCollapse, FanPlacementsAreEachTriangleAndSpokeOnce)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  const ReplayedFans cached = CollapseAndReplayFans(sphere, true), uncached = CollapseAndReplayFans(sphere, false);
  EXPECT_EQ(cached.Result.FanPlacements, cached.Fans + cached.Spokes);
  EXPECT_EQ(uncached.Result.FanPlacements, uncached.Fans);
  for (const ReplayedFans* replayed : { &cached, &uncached })
  {
    const TriangleCollapseResult& result = replayed->Result;
    const double collapses = std::max<Index>(1, result.Collapses);
    std::printf("[fan placements] %.2f placements and %.4f validity tests per collapse\n",
      double(result.FanPlacements) / collapses, double(result.ValidityTests) / collapses);
    EXPECT_GE(result.ValidityTests, static_cast<long long>(result.Collapses) + result.RejectedCollapses);
  }
}

// TriangleCostBound (session 40): a fan triangle's own collapse is placed only when the bound from
// its edges' costs lets it win, so the placements per collapse are the spokes and a few triangles,
// not every fan triangle (on the sphere about 0.8 triangle placements per collapse instead of 7);
// the records still replay the run (CollapseAndReplayFans), and the result stays as close to the
// input as without the bound (within 2 % at 10 %: the bound is exact up to rounding and fallbacks).
TEST(QuadricTriangleCollapse, TriangleCostBoundPlacesFewTrianglesSameQuality)
{
  const TriangleMesh sphere = slodtest::Sphere(90, 80);
  const ReplayedFans plain = CollapseAndReplayFans(sphere, true), bounded = CollapseAndReplayFans(sphere, true, true);
  const double collapses = std::max<Index>(1, bounded.Result.Collapses);
  const double triangles = double(bounded.Result.FanPlacements - bounded.Spokes) / collapses;
  std::printf("[triangle cost bound] %.2f triangle placements per collapse of %.2f fan triangles\n", triangles,
    double(bounded.Fans) / collapses);
  EXPECT_GE(bounded.Result.FanPlacements, bounded.Spokes);
  EXPECT_LT(bounded.Result.FanPlacements - bounded.Spokes, bounded.Fans / 4) << "the bound skipped few placements";
  EXPECT_EQ(plain.Result.FanPlacements, plain.Fans + plain.Spokes);
  EXPECT_EQ(bounded.Result.Mesh.NumberOfTriangles(), plain.Result.Mesh.NumberOfTriangles());
  vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(sphere);
  double hPlain, mPlain, hBounded, mBounded;
  Deviation(input, slodtest::ToPolyData(plain.Result.Mesh), hPlain, mPlain, 100000);
  Deviation(input, slodtest::ToPolyData(bounded.Result.Mesh), hBounded, mBounded, 100000);
  std::printf("[triangle cost bound] Hausdorff %.4e (without %.4e), mean %.4e (without %.4e)\n", hBounded, hPlain,
    mBounded, mPlain);
  EXPECT_LE(hBounded, 1.02 * hPlain);
  EXPECT_LE(mBounded, 1.02 * mPlain);
}

// After the collapses (the fit, the refinement, the extraction) the working set holds the
// quadrics of the surviving vertices only, with a 4-byte parent or slot per input vertex, instead
// of a quadric per input vertex (88 bytes): before session 32 that made the passes the filter's
// peak on the MRI. Bound from the layout (per vertex: mesh points 24, reference starts and counts
// 8, flags 5, the kept points unpacked at most 24, parent or slot 4, ancestry 12, the input ids 6;
// per triangle: corners 12, references 3 x 4 with the room factor, alive 1, the kept corners 12,
// each original vertex's triangles 12, the input ids 6; 88 per output vertex): a quadric per input
// vertex exceeds it by about 75 bytes per vertex at 10 %. The passes stay below the loop's peak.
TEST(QuadricTriangleCollapse, PassesAfterTheCollapsesHoldTheSurvivorsQuadricsOnly)
{
  TriangleMesh mesh = slodtest::Sphere(90, 80);
  const double vertices = mesh.NumberOfPoints(), triangles = mesh.NumberOfTriangles();
  TriangleCollapseOptions options;
  options.TargetTriangles = mesh.NumberOfTriangles() / 10;
  TriangleCollapseResult result;
  SimplifyByTriangleCollapse(mesh, options, result);
  ASSERT_LE(mesh.NumberOfTriangles(), options.TargetTriangles);
  const double references = 3 * 4 * EditableMesh::ShrinkingMeshRoomFactor;
  const double bound = vertices * (24 + 8 + 5 + 24 + 4 + 12 + 6) + triangles * (12 + references + 1 + 12 + 12 + 6) +
    88.0 * double(result.Mesh.NumberOfPoints()) + 4096;
  std::printf("[passes] %.1f bytes per vertex, bound %.1f, the loop's peak %.1f\n",
    double(result.PassesWorkingBytes) / vertices, bound / vertices, double(result.PeakWorkingBytes) / vertices);
  EXPECT_GT(result.PassesWorkingBytes, 0u);
  EXPECT_LE(double(result.PassesWorkingBytes), bound);
  EXPECT_LT(result.PassesWorkingBytes, result.PeakWorkingBytes);
}

// The fit to the original fits the vertices far from the rest of their chunk concurrently and the
// others in order (ChunkedSweep), and stops at its work budget: the moves, their count and the
// stop must be the same for 1, 2 and 8 threads. armadillo to 10 %: the fit reaches its budget (so
// where it stops depends on the order its work is counted in) and, asserted, its visits ran on
// several threads (fandisk, used before, reached neither: it passed with thread-dependent code).
TEST(QuadricTriangleCollapse, FitToOriginalSameMovesForOneTwoAndEightThreads)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("armadillo");
  TriangleCollapseOptions options;
  options.TargetTriangles = input->GetNumberOfPolys() / 10;
  options.RefineDeviation = false; // the fit's moves alone
  const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
  EXPECT_GT(results[0].FittedVertices, 0) << "the fit moved nothing: the test would not see a difference";
  for (size_t i = 0; i < results.size(); ++i)
  {
    EXPECT_TRUE(results[i].FitBudgetReached) << "the fit did not reach its budget: its stop is not tested";
  }
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_GE(results[i].FitThreads, 2) << "the fit's work was not split among threads";
    EXPECT_EQ(results[0].FittedVertices, results[i].FittedVertices);
    EXPECT_EQ(results[0].Mesh.Points, results[i].Mesh.Points);
    EXPECT_EQ(results[0].Mesh.Triangles, results[i].Mesh.Triangles);
  }
}

// The fit and the refinement visit every member of a chunk concurrently, step by step (a member
// within two edges of an earlier one in a later step), and take each result as the sequential
// sweep would have computed it; a visit in order happens only where the work budget runs out
// (at most once per pass: the sweep stops there). Defaults (fit and refinement) to 10 %: the same
// mesh, moves and visits for 1, 2 and 8 threads, some members waited for an earlier one (else the
// steps are not tested), and at most one visit in order per pass. Before session 20 every member
// near another was visited in order (mc1m's refinement: 123 of 151).
TEST(QuadricTriangleCollapse, PassesAfterTheCollapsesVisitInOrderOnlyAtTheBudget)
{
  for (const char* name : { "armadillo", "bunny00" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    TriangleCollapseOptions options;
    options.TargetTriangles = input->GetNumberOfPolys() / 10;
    const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
    const TriangleCollapseResult& first = results[0];
    EXPECT_GT(first.RefinedVertices, 0) << name << ": the refinement moved nothing";
    EXPECT_GT(first.FitVisits.AfterEarlier + first.RefinementVisits.AfterEarlier, 0)
      << name << ": no member waited for an earlier one: the steps are not tested";
    for (const TriangleCollapseResult& result : results)
    {
      EXPECT_LE(result.FitVisits.InOrder, result.FitBudgetReached ? 1 : 0) << name;
      EXPECT_LE(result.RefinementVisits.InOrder, 1) << name;
    }
    for (size_t i = 1; i < results.size(); ++i)
    {
      EXPECT_EQ(first.FittedVertices, results[i].FittedVertices) << name;
      EXPECT_EQ(first.RefinedVertices, results[i].RefinedVertices) << name;
      EXPECT_EQ(first.FitVisits.Visits, results[i].FitVisits.Visits) << name;
      EXPECT_EQ(first.RefinementVisits.Visits, results[i].RefinementVisits.Visits) << name;
      EXPECT_EQ(first.Mesh.Points, results[i].Mesh.Points) << name;
      EXPECT_EQ(first.Mesh.Triangles, results[i].Mesh.Triangles) << name;
    }
    std::printf("%s: fit %d visits, %d after an earlier member, %d in order; refinement %d, %d, %d\n", name,
      int(first.FitVisits.Visits), int(first.FitVisits.AfterEarlier), int(first.FitVisits.InOrder),
      int(first.RefinementVisits.Visits), int(first.RefinementVisits.AfterEarlier), int(first.RefinementVisits.InOrder));
  }
}

// The strict order's test meshes: many ties (marching cubes), a scan, and a noisy scan-like
// isosurface (rejections and retried triangles).
std::vector<std::pair<const char*, vtkSmartPointer<vtkPolyData>>> StrictOrderMeshes()
{
  vtkNew<vtkScanSurfaceSource> scan;
  scan->SetResolution(48);
  scan->Update();
  return { { "marching-cubes", Mesh("marching-cubes") }, { "bunny00", Mesh("bunny00") },
    { "scan", vtkSmartPointer<vtkPolyData>(scan->GetOutput()) } };
}

// The strict order's prefetches of the next pops' neighbourhoods (UpcomingPrefetches, session 31)
// are hints: without them, with the default and with the widest window the collapses are the same,
// to the bit, on a mesh with many ties (marching cubes), a scan and a noisy scan-like isosurface
// (rejections, retries), with the history recorded (its replay reads the same queue).
TEST(QuadricTriangleCollapse, UpcomingPrefetchesGiveTheReferenceCollapses)
{
  const auto meshes = StrictOrderMeshes();
  for (const auto& named : meshes)
  {
    const char* name = named.first;
    vtkPolyData* input = named.second;
    std::vector<TriangleCollapseResult> results;
    for (int width : { 0, TriangleCollapseOptions().UpcomingPrefetches, 16 })
    {
      TriangleCollapseOptions options;
      options.TargetTriangles = input->GetNumberOfPolys() / 10;
      options.RecordHistory = true;
      options.UpcomingPrefetches = width;
      TriangleMesh mesh = slodtest::ToTriangleMesh(input);
      results.emplace_back();
      SimplifyByTriangleCollapse(mesh, options, results.back());
    }
    const TriangleCollapseResult& reference = results[0];
    EXPECT_GT(TriangleCollapseOptions().UpcomingPrefetches, 0) << "the default prefetches nothing: nothing tested";
    EXPECT_GT(reference.Collapses, 0) << name;
    EXPECT_LE(reference.Mesh.NumberOfTriangles(), input->GetNumberOfPolys() / 10) << name;
    for (size_t i = 1; i < results.size(); ++i)
    {
      EXPECT_EQ(reference.Collapses, results[i].Collapses) << name;
      EXPECT_EQ(reference.RejectedCollapses, results[i].RejectedCollapses) << name;
      EXPECT_EQ(reference.Mesh.Points, results[i].Mesh.Points) << name;
      EXPECT_EQ(reference.Mesh.Triangles, results[i].Mesh.Triangles) << name;
      EXPECT_EQ(reference.OutputToInput, results[i].OutputToInput) << name;
      EXPECT_EQ(reference.History.NewPositions, results[i].History.NewPositions) << name;
    }
  }
}

// The strict order's look-ahead (LookAheadEvaluations, session 33) evaluates upcoming pops in
// parallel and lets a pop take its evaluation: the same collapses, rejections, points, triangles,
// ids and recorded positions as without it, for 1, 2 and 8 threads, on a mesh with many ties
// (marching cubes), bunny00 and a noisy scan-like surface (rejections, retried triangles, which end
// a look-ahead). With more than one thread most pops must take an evaluation made ahead, and most
// collapses their new keys computed ahead (session 36; else the test would check nothing); with
// one thread there is none (nothing to run it on). Session 37: the evaluations run on one worker
// beside the loop, one parallel region per run (session 36 started two vtkSMPTools loops per
// look-ahead), and the loop evaluates whatever the worker has not claimed: the counts of
// evaluations, takes and new keys are the same for 2 and 8 threads however the work was split.
TEST(QuadricTriangleCollapse, LookAheadEvaluationsGiveTheStrictCollapsesForAnyThreadCount)
{
  const auto meshes = StrictOrderMeshes();
  for (const auto& named : meshes)
  {
    const char* name = named.first;
    TriangleCollapseOptions options;
    options.TargetTriangles = named.second->GetNumberOfPolys() / 10;
    options.RecordHistory = true;
    options.LookAheadEvaluations = 0;
    const std::vector<TriangleCollapseResult> strict = ResultsForOneTwoAndEightThreads(named.second, options);
    options.LookAheadEvaluations = 32;
    const std::vector<TriangleCollapseResult> ahead = ResultsForOneTwoAndEightThreads(named.second, options);
    const TriangleCollapseResult& reference = strict[0];
    ASSERT_GT(reference.Collapses, 0) << name;
    EXPECT_EQ(reference.LookAheadTaken, 0) << name;
    EXPECT_EQ(ahead[0].LookAheadTaken, 0) << name << ": one thread evaluated ahead";
    EXPECT_EQ(ahead[0].LookAheadKeysTaken, 0) << name;
    EXPECT_EQ(ahead[0].LookAheadRegions, 0) << name;
    for (size_t i = 1; i < ahead.size(); ++i)
    {
      EXPECT_EQ(ahead[i].LookAheadRegions, 1) << name << ": not one region with its worker per run";
      EXPECT_LE(ahead[i].LookAheadWorkerEvaluations, ahead[i].LookAheadEvaluated) << name;
      EXPECT_EQ(ahead[i].LookAheadEvaluated, ahead[1].LookAheadEvaluated) << name;
      EXPECT_EQ(ahead[i].LookAheadTaken, ahead[1].LookAheadTaken) << name;
      EXPECT_EQ(ahead[i].LookAheadKeysTaken, ahead[1].LookAheadKeysTaken) << name;
      EXPECT_GT(2 * ahead[i].LookAheadTaken, reference.Collapses) << name << ": few pops took an evaluation made ahead";
      EXPECT_LE(ahead[i].LookAheadTaken, ahead[i].LookAheadEvaluated) << name;
      // Session 36: most collapses also take their new keys computed ahead (in parallel, before
      // the collapse), and the outputs below are still the strict order's.
      EXPECT_GT(2 * ahead[i].LookAheadKeysTaken, reference.Collapses) << name << ": few collapses took new keys made ahead";
      EXPECT_LE(ahead[i].LookAheadKeysTaken, reference.Collapses) << name;
    }
    for (const std::vector<TriangleCollapseResult>* runs : { &strict, &ahead })
    {
      for (const TriangleCollapseResult& result : *runs)
      {
        EXPECT_EQ(reference.Collapses, result.Collapses) << name;
        EXPECT_EQ(reference.RejectedCollapses, result.RejectedCollapses) << name;
        EXPECT_EQ(reference.Mesh.Points, result.Mesh.Points) << name;
        EXPECT_EQ(reference.Mesh.Triangles, result.Mesh.Triangles) << name;
        EXPECT_EQ(reference.OutputToInput, result.OutputToInput) << name;
        EXPECT_EQ(reference.History.NewPositions, result.History.NewPositions) << name;
      }
    }
    std::printf("%s: %lld collapses; 2 threads: %lld evaluated ahead (%lld by the worker), %lld taken, %lld new keys taken\n",
      name, static_cast<long long>(reference.Collapses), ahead[1].LookAheadEvaluated,
      ahead[1].LookAheadWorkerEvaluations, ahead[1].LookAheadTaken, ahead[1].LookAheadKeysTaken);
  }
}

// The look-ahead's worker is a thread of its own whose scratch comes from vtkSMPTools' thread-local
// storage (session 37): with each threaded backend (TBB, the default, and STDThread) and 2 threads
// the strict order's collapses, points, triangles and recorded positions, with one region per run.
TEST(QuadricTriangleCollapse, LookAheadWorkerGivesTheStrictCollapsesWithEachThreadedBackend)
{
  vtkSmartPointer<vtkPolyData> input = Mesh("marching-cubes");
  TriangleCollapseOptions options;
  options.TargetTriangles = input->GetNumberOfPolys() / 10;
  options.RecordHistory = true;
  TriangleMesh strictMesh = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult strict;
  SimplifyByTriangleCollapse(strictMesh, options, strict);
  ASSERT_GT(strict.Collapses, 0);
  const std::string backend = vtkSMPTools::GetBackend();
  const int threads = vtkSMPTools::GetEstimatedNumberOfThreads();
  options.LookAheadEvaluations = 32;
  for (const char* name : { "TBB", "STDThread" })
  {
    SCOPED_TRACE(name);
    ASSERT_TRUE(vtkSMPTools::SetBackend(name));
    vtkSMPTools::Initialize(2);
    ASSERT_EQ(vtkSMPTools::GetEstimatedNumberOfThreads(), 2);
    TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    EXPECT_EQ(result.LookAheadRegions, 1);
    EXPECT_GT(2 * result.LookAheadTaken, strict.Collapses) << "few pops took an evaluation made ahead";
    EXPECT_EQ(strict.Collapses, result.Collapses);
    EXPECT_EQ(strict.RejectedCollapses, result.RejectedCollapses);
    EXPECT_EQ(strict.Mesh.Points, result.Mesh.Points);
    EXPECT_EQ(strict.Mesh.Triangles, result.Mesh.Triangles);
    EXPECT_EQ(strict.OutputToInput, result.OutputToInput);
    EXPECT_EQ(strict.History.NewPositions, result.History.NewPositions);
  }
  vtkSMPTools::SetBackend(backend.c_str());
  vtkSMPTools::Initialize(threads);
}

// The pass schedule (CollapseSchedule::Passes) checks and collapses each round's independent set
// in parallel: bit-identical points and triangles for 1, 2 and 8 threads on a mesh whose rounds
// are split among the threads (asserted), with the count target met within one collapse and the
// topology kept. The marching-cubes mesh (ties of equal costs in flat regions) and bunny00. The
// window fills test their ranked entries in parallel (session 25; they were walked in rank order):
// the same tests and waiting entries for any thread count, split among the threads, and some
// entries do wait (else the test would check nothing).
TEST(QuadricTriangleCollapse, PassScheduleSameOutputForOneTwoAndEightThreads)
{
  for (const char* name : { "marching-cubes", "bunny00" })
  {
    vtkSmartPointer<vtkPolyData> input = Mesh(name);
    TriangleCollapseOptions options;
    options.Schedule = CollapseSchedule::Passes;
    options.TargetTriangles = input->GetNumberOfPolys() / 10;
    const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
    const MeshStatistics before = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
    const MeshStatistics after = ComputeMeshStatistics(results[0].Mesh);
    EXPECT_GT(results[0].Passes, 1) << name;
    EXPECT_LE(results[0].Mesh.NumberOfTriangles(), options.TargetTriangles) << name;
    EXPECT_GE(results[0].Mesh.NumberOfTriangles(), options.TargetTriangles - 3) << name;
    EXPECT_EQ(after.NonManifoldEdges, 0) << name;
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic) << name;
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops) << name;
    EXPECT_EQ(after.InconsistentlyOrientedEdges, 0) << name;
    EXPECT_GT(results[0].WaitingEntries, 0) << name << ": no ranked entry waited for the next pass";
    EXPECT_GT(results[0].WindowTests, results[0].WaitingEntries) << name;
    for (size_t i = 1; i < results.size(); ++i)
    {
      EXPECT_GE(results[i].PassThreads, 2) << name << ": the rounds were not split among threads";
      EXPECT_GE(results[i].WindowTestThreads, 2) << name << ": the window fills were not split among threads";
      EXPECT_EQ(results[0].WindowTests, results[i].WindowTests) << name;
      EXPECT_EQ(results[0].WaitingEntries, results[i].WaitingEntries) << name;
      EXPECT_EQ(results[0].Passes, results[i].Passes) << name;
      EXPECT_EQ(results[0].Collapses, results[i].Collapses) << name;
      EXPECT_EQ(results[0].Mesh.Points, results[i].Mesh.Points) << name;
      EXPECT_EQ(results[0].Mesh.Triangles, results[i].Mesh.Triangles) << name;
    }
  }
}

// The pass schedule's parallel rounds on a scan-like surface (a border, handles, non-manifold edges
// and pinched vertices, which the collapses must leave as they are, locked): bit-identical for 1,
// 2 and 8 threads, the rounds split among the threads, and the non-manifold edges, the Euler
// characteristic and the components of the input kept.
TEST(QuadricTriangleCollapse, PassScheduleSameOutputForAnyThreadCountOnANoisyScan)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::NoisyScanIsosurface(48, 5);
  TriangleCollapseOptions options;
  options.Schedule = CollapseSchedule::Passes;
  options.TargetTriangles = input->GetNumberOfPolys() / 10;
  const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
  ASSERT_EQ(results.size(), 3u);
  const MeshStatistics before = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
  const MeshStatistics after = ComputeMeshStatistics(results[0].Mesh);
  ASSERT_GT(before.NonManifoldEdges, 0) << "the scan has no non-manifold edge: nothing locked is tested";
  ASSERT_GT(before.BoundaryEdges, 0);
  EXPECT_GT(results[0].Passes, 1);
  EXPECT_LE(results[0].Mesh.NumberOfTriangles(), options.TargetTriangles + options.TargetTriangles / 10);
  EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.Components, before.Components);
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_GE(results[i].PassThreads, 2) << "the rounds were not split among threads";
    EXPECT_EQ(results[0].Passes, results[i].Passes);
    EXPECT_EQ(results[0].Collapses, results[i].Collapses);
    EXPECT_EQ(results[0].Mesh.Points, results[i].Mesh.Points);
    EXPECT_EQ(results[0].Mesh.Triangles, results[i].Mesh.Triangles);
  }
}

// The pass schedule keeps the filter's quality against vtkQuadricDecimation at the same count
// (marching-cubes mesh and fandisk to 10 %: Hausdorff at most 1.02x, mean at most 1.01x,
// vtkSurfaceDeviation, as TriangleCollapseQuality), falls back to the queue when progressive
// records are asked for (the queue's output), and honours MaximumError.
TEST(QuadricTriangleCollapse, PassScheduleQualityFallbackAndErrorBound)
{
  for (const char* name : { "marching-cubes", "fandisk" })
  {
    vtkSmartPointer<vtkPolyData> input = Mesh(name);
    vtkNew<vtkQuadricDecimation> reference;
    reference->SetInputData(input);
    reference->SetTargetReduction(0.9);
    reference->Update();
    vtkNew<vtkQuadricTriangleCollapse> filter;
    filter->SetInputData(input);
    filter->SetTargetNumberOfTriangles(reference->GetOutput()->GetNumberOfPolys());
    filter->SetCollapseScheduleToPasses();
    filter->Update();
    double hausdorff[2], mean[2];
    Deviation(input, reference->GetOutput(), hausdorff[0], mean[0]);
    Deviation(input, filter->GetOutput(), hausdorff[1], mean[1]);
    EXPECT_LE(hausdorff[1], 1.02 * hausdorff[0]) << name;
    EXPECT_LE(mean[1], 1.01 * mean[0]) << name;
  }
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("fandisk");
  TriangleCollapseOptions options;
  options.TargetTriangles = 1000;
  options.RecordHistory = true;
  TriangleMesh queueMesh = slodtest::ToTriangleMesh(input), passMesh = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult queue, passes;
  SimplifyByTriangleCollapse(queueMesh, options, queue);
  options.Schedule = CollapseSchedule::Passes;
  SimplifyByTriangleCollapse(passMesh, options, passes);
  EXPECT_EQ(passes.Passes, 0) << "records are asked for: the queue runs";
  EXPECT_EQ(passes.Mesh.Points, queue.Mesh.Points);
  EXPECT_EQ(passes.History.NumberOfCollapses(), queue.History.NumberOfCollapses());
  options.RecordHistory = false;
  options.TargetTriangles = 0;
  options.MaximumError = 1e-3 * slodtest::ToTriangleMesh(input).BoundingBoxDiagonal();
  TriangleMesh bounded = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult result;
  SimplifyByTriangleCollapse(bounded, options, result);
  EXPECT_GT(result.Passes, 0);
  EXPECT_GT(result.Collapses, 0);
  EXPECT_TRUE(result.StoppedByError);
  EXPECT_LE(result.MaximumError, options.MaximumError);
}

// The pass schedule where every ring holds one vertex (a closed cone and a fan disk whose apex has
// 5,000 triangles): a round decides only a few entries there (the rounds hand over to a walk one
// entry at a time); the count target is still met within one collapse and the topology kept.
TEST(QuadricTriangleCollapse, PassScheduleReachesTheTargetAroundHighValence)
{
  for (const char* name : { "valence-5000-closed-cone", "valence-5000-fan-disk" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::MakeBadInput(name).Surface;
    vtkNew<vtkQuadricTriangleCollapse> filter;
    filter->SetInputData(input);
    const vtkIdType target = input->GetNumberOfPolys() / 10;
    filter->SetTargetNumberOfTriangles(target);
    filter->SetCollapseScheduleToPasses();
    filter->Update();
    const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
    EXPECT_LE(out.NumberOfTriangles(), target) << name;
    EXPECT_GE(out.NumberOfTriangles(), target - 3) << name;
    const MeshStatistics before = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
    const MeshStatistics after = ComputeMeshStatistics(out);
    EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic) << name;
    EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops) << name;
    EXPECT_EQ(after.NonManifoldEdges, 0) << name;
  }
}

// Small passes are nearly the queue's greedy order: a pass whose few ranked entries are all rejected
// must not be followed by one that performs everything at once (it took every candidate before
// session 17: femur at 10 % with share 0.001, a collapse error 1.56x the queue's largest). The
// collapses alone (no fit, no refinement), the largest collapse error of each schedule.
TEST(QuadricTriangleCollapse, SmallPassesKeepTheQueuesLargestError)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("femur");
  TriangleCollapseResult results[2];
  for (int schedule = 0; schedule < 2; ++schedule)
  {
    TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    options.FitToOriginal = false;
    options.RefineDeviation = false;
    options.Schedule = schedule == 0 ? CollapseSchedule::Queue : CollapseSchedule::Passes;
    options.PassGoalShare = 0.001;
    options.PassErrorFactor = 1.0;
    SimplifyByTriangleCollapse(mesh, options, results[schedule]);
    EXPECT_LE(results[schedule].Mesh.NumberOfTriangles(), options.TargetTriangles);
  }
  std::printf("[passes] femur 10%%, share 0.001: largest collapse error queue %.4e, %d passes %.4e\n",
    results[0].MaximumError, int(results[1].Passes), results[1].MaximumError);
  ASSERT_GT(results[0].MaximumError, 0.0);
  EXPECT_GT(results[1].Passes, 100) << "the passes were not small";
  EXPECT_LE(results[1].MaximumError, 1.1 * results[0].MaximumError);
}

// The pass schedule to 10 % of the triangles, with the options `set` changes.
template <typename Set>
TriangleCollapseResult SimplifyInPassesToATenth(const TriangleMesh& original, Set&& set)
{
  TriangleMesh mesh = original;
  TriangleCollapseOptions options;
  options.TargetTriangles = mesh.NumberOfTriangles() / 10;
  options.Schedule = CollapseSchedule::Passes;
  set(options);
  TriangleCollapseResult result;
  SimplifyByTriangleCollapse(mesh, options, result);
  return result;
}

// PassRemovalShare ends a pass once it removed that share of what is left to remove: on the
// femur at 10 % a share of 0.1 takes more passes than running each ranking through, reaches the
// target, keeps the genus, and gives the same mesh for 1, 2 and 8 threads; the filter's pass
// defaults are the options' (0.1 the default).
TEST(QuadricTriangleCollapse, PassRemovalShareSplitsPassesTheSameForAnyThreadCount)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("femur");
  const TriangleMesh original = slodtest::ToTriangleMesh(input);
  auto run = [&](double share) {
    TriangleCollapseResult result =
      SimplifyInPassesToATenth(original, [&](TriangleCollapseOptions& options) { options.PassRemovalShare = share; });
    EXPECT_LE(result.Mesh.NumberOfTriangles(), original.NumberOfTriangles() / 10);
    return result;
  };
  const TriangleCollapseResult whole = run(1.0);
  std::vector<TriangleCollapseResult> split;
  slodtest::ForOneTwoAndEightThreads([&](int) { split.push_back(run(0.1)); });
  // 0.1 is the default since session 26 (finer passes, nearer the queue's order), in both layers.
  vtkNew<vtkQuadricTriangleCollapse> defaults;
  EXPECT_EQ(TriangleCollapseOptions().PassRemovalShare, 0.1);
  EXPECT_EQ(defaults->GetPassRemovalShare(), TriangleCollapseOptions().PassRemovalShare);
  EXPECT_EQ(defaults->GetPassGoalShare(), TriangleCollapseOptions().PassGoalShare);
  EXPECT_EQ(defaults->GetPassErrorFactor(), TriangleCollapseOptions().PassErrorFactor);
  std::printf("[passes] femur 10%%: %d passes, with PassRemovalShare 0.1 %d\n", int(whole.Passes), int(split[0].Passes));
  EXPECT_GT(split[0].Passes, whole.Passes);
  for (size_t i = 1; i < split.size(); ++i)
  {
    EXPECT_EQ(split[0].Mesh.Points, split[i].Mesh.Points);
    EXPECT_EQ(split[0].Mesh.Triangles, split[i].Mesh.Triangles);
  }
  EXPECT_EQ(ComputeMeshStatistics(split[0].Mesh).EulerCharacteristic, ComputeMeshStatistics(original).EulerCharacteristic);
}

// Session 27: after the first pass, the pass schedule costs again only the triangles the last pass
// changed (around its collapses' kept vertices, those it removed, those with an excluded
// operation) instead of every triangle each pass. The same output as the visit of every triangle
// (PassCostSweepsEveryTriangle) on meshes with borders, a noisy scan with locked non-manifold
// vertices and many rejected operations, for 1, 2 and 8 threads; and the visits after the first
// pass follow the changes, far below a sweep per pass (measured: a sixth to a tenth of it here).
TEST(QuadricTriangleCollapse, PassCostsVisitOnlyTheChangedTriangles)
{
  const std::vector<std::pair<const char*, vtkSmartPointer<vtkPolyData>>> inputs = { { "bunny00", Mesh("bunny00") },
    { "elephant-with-holes", Mesh("elephant-with-holes") }, { "noisy scan", slodtest::NoisyScanIsosurface(48, 5) } };
  for (const auto& named : inputs)
  {
    const char* name = named.first;
    const TriangleMesh original = slodtest::ToTriangleMesh(named.second);
    auto run = [&](bool sweeps) {
      return SimplifyInPassesToATenth(
        original, [&](TriangleCollapseOptions& options) { options.PassCostSweepsEveryTriangle = sweeps; });
    };
    const TriangleCollapseResult swept = run(true);
    const long long triangles = original.NumberOfTriangles();
    ASSERT_GE(swept.Passes, 10) << name << ": too few passes to tell a sweep per pass from the changes";
    EXPECT_GE(swept.CostPassVisits, triangles * swept.Passes) << name;
    std::vector<TriangleCollapseResult> changed;
    slodtest::ForOneTwoAndEightThreads([&](int) { changed.push_back(run(false)); });
    for (const TriangleCollapseResult& result : changed)
    {
      EXPECT_EQ(result.Passes, swept.Passes) << name;
      EXPECT_EQ(result.Collapses, swept.Collapses) << name;
      EXPECT_EQ(result.RejectedCollapses, swept.RejectedCollapses) << name;
      EXPECT_EQ(result.Mesh.Points, swept.Mesh.Points) << name;
      EXPECT_EQ(result.Mesh.Triangles, swept.Mesh.Triangles) << name;
      EXPECT_EQ(result.CostPassVisits, changed[0].CostPassVisits) << name;
    }
    std::printf("[passes] %s: %d passes, cost visits %lld (every triangle each pass: %lld)\n", name,
      int(changed[0].Passes), changed[0].CostPassVisits, swept.CostPassVisits);
    EXPECT_LT(changed[0].CostPassVisits, swept.CostPassVisits / 3) << name;
  }
}

// Session 28: the adjacency lists of the stages around the collapses (the reordering's triangle
// order, the editable mesh's vertex -> triangle blocks at the start and at each rebuild in the
// loop, the ancestry of the fit and the refinement) are built in parallel. The same output as
// their serial loops (ParallelStages off) for 1, 2 and 8 threads, with the fit and the refinement
// moving vertices, with the queue and the pass schedule: mesh, ids back to the input, errors and
// the passes' moves and visits.
TEST(QuadricTriangleCollapse, ParallelStagesGiveTheSerialOutputForAnyThreadCount)
{
  const std::vector<std::pair<const char*, vtkSmartPointer<vtkPolyData>>> inputs = { { "bunny00", Mesh("bunny00") },
    { "noisy scan", slodtest::NoisyScanIsosurface(48, 5) } };
  for (const auto& named : inputs)
  {
    const char* name = named.first;
    const TriangleMesh original = slodtest::ToTriangleMesh(named.second);
    for (const CollapseSchedule schedule : { CollapseSchedule::Queue, CollapseSchedule::Passes })
    {
      auto run = [&](bool parallel) {
        TriangleMesh mesh = original;
        TriangleCollapseOptions options;
        options.TargetTriangles = mesh.NumberOfTriangles() / 10;
        options.Schedule = schedule;
        options.ParallelStages = parallel;
        TriangleCollapseResult result;
        SimplifyByTriangleCollapse(mesh, options, result);
        return result;
      };
      TriangleCollapseResult serial;
      slodtest::ForOneTwoAndEightThreads([&](int threads) {
        if (threads == 1)
        {
          serial = run(false);
          ASSERT_GT(serial.FittedVertices + serial.RefinedVertices, 0) << name << ": the passes moved nothing";
        }
        const TriangleCollapseResult result = run(true);
        EXPECT_EQ(result.Mesh.Points, serial.Mesh.Points) << name << ", " << threads << " threads";
        EXPECT_EQ(result.Mesh.Triangles, serial.Mesh.Triangles) << name << ", " << threads << " threads";
        EXPECT_EQ(result.OutputToInput, serial.OutputToInput) << name << ", " << threads << " threads";
        EXPECT_EQ(result.OutputTriangleIds, serial.OutputTriangleIds) << name << ", " << threads << " threads";
        EXPECT_EQ(result.VertexError, serial.VertexError) << name << ", " << threads << " threads";
        EXPECT_EQ(result.FittedVertices, serial.FittedVertices) << name << ", " << threads << " threads";
        EXPECT_EQ(result.RefinedVertices, serial.RefinedVertices) << name << ", " << threads << " threads";
        EXPECT_EQ(result.FitVisits.Visits, serial.FitVisits.Visits) << name << ", " << threads << " threads";
        EXPECT_EQ(result.RefinementVisits.Visits, serial.RefinementVisits.Visits) << name << ", " << threads << " threads";
      });
    }
  }
}

// The pass ranking (chunked counts, radix select of the goal key, chunked collection; session 19)
// against the plain definition: sort every candidate by (key, index), the limit is the factor
// times the key of the goal rank (at least the floor), the ranking is the sorted candidates up to
// it. Keys with many ties, zeros, negatives (ranked as 0), infinities and NaN (no candidate), over
// several chunks, with and without a mask, for 1, 2 and 8 threads.
TEST(QuadricTriangleCollapse, PassRankingIsTheSortedCandidatesUnderTheLimit)
{
  std::mt19937 random(19);
  std::vector<float> keys(300000);
  std::vector<unsigned char> alive(keys.size());
  for (size_t i = 0; i < keys.size(); ++i)
  {
    const unsigned r = random() % 100;
    keys[i] = r < 5 ? std::numeric_limits<float>::infinity()
      : r < 7       ? std::numeric_limits<float>::quiet_NaN()
      : r < 10      ? -1.0f
      : r < 20      ? 0.0f
      : r < 50      ? float(random() % 50) * 1e-6f
                    : std::ldexp(float(random() % 1000 + 1), -int(random() % 40));
    alive[i] = random() % 4 != 0;
  }
  for (const unsigned char* mask : { static_cast<const unsigned char*>(nullptr), static_cast<const unsigned char*>(alive.data()) })
  {
    std::vector<std::pair<float, Index>> sorted;
    for (size_t i = 0; i < keys.size(); ++i)
    {
      if ((!mask || mask[i]) && std::isfinite(keys[i]))
      {
        sorted.emplace_back(std::max(0.0f, keys[i]), static_cast<Index>(i));
      }
    }
    std::sort(sorted.begin(), sorted.end());
    for (const Index goal : { Index(-1), Index(0), Index(7), Index(sorted.size() / 3), Index(sorted.size() - 1),
           Index(sorted.size()) })
    {
      for (const float floor : { 0.0f, 2e-5f })
      {
        float limit = std::numeric_limits<float>::infinity();
        if (goal >= 0 && size_t(goal) < sorted.size())
        {
          limit = std::max(floor, static_cast<float>(1.5 * double(sorted[size_t(goal)].first)));
        }
        std::vector<Index> expected;
        for (const auto& entry : sorted)
        {
          if (entry.first <= limit)
          {
            expected.push_back(entry.second);
          }
        }
        ASSERT_FALSE(expected.empty());
        slodtest::ForOneTwoAndEightThreads([&](int threads) {
          PassRanking ranking;
          RankPassCandidates(keys, mask, goal, 1.5, floor, ranking);
          EXPECT_EQ(ranking.Candidates, Index(sorted.size()));
          EXPECT_EQ(ranking.Limit, limit) << "goal " << goal << ", " << threads << " threads";
          EXPECT_EQ(ranking.Everything, expected.size() == sorted.size());
          std::vector<Index> got;
          for (std::uint64_t entry : ranking.Order)
          {
            got.push_back(RankedElement(entry));
          }
          EXPECT_EQ(got, expected) << "goal " << goal << ", " << threads << " threads";
        });
      }
    }
  }
}

// Batches are selected, checked and performed so that the thread count cannot change them: the
// same output for 1, 2 and 8 threads on a mesh whose batches are large enough to be split among
// threads, and the batches keep the topology.
TEST(QuadricTriangleCollapse, BatchCollapsesSameOutputForOneTwoAndEightThreads)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("armadillo");
  const std::vector<TriangleMesh> outputs = OutputsForOneTwoAndEightThreads(input, [](vtkQuadricTriangleCollapse* filter) {
    filter->SetTargetNumberOfTriangles(5000);
    filter->BatchCollapsesOn();
  });
  for (size_t i = 1; i < outputs.size(); ++i)
  {
    EXPECT_EQ(outputs[0].Points, outputs[i].Points);
    EXPECT_EQ(outputs[0].Triangles, outputs[i].Triangles);
  }
  const MeshStatistics before = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
  const MeshStatistics after = ComputeMeshStatistics(outputs[0]);
  EXPECT_LE(outputs[0].NumberOfTriangles(), 5000);
  EXPECT_EQ(after.NonManifoldEdges, 0);
  EXPECT_EQ(after.Genus, before.Genus);
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
}

// The batches' collapses run in parallel (ParallelApply): on a marching-cubes mesh, whose equal
// costs make large batches, with point data (merged in the sequential settle) the output points,
// triangles and point data are the same for 1, 2 and 8 threads; the topology is kept and the
// two-sided deviation stays within 2 % of the strict order's (the tolerance reorders ties only).
TEST(QuadricTriangleCollapse, ParallelBatchesSameOutputAndPointDataForAnyThreadCount)
{
  vtkSmartPointer<vtkPolyData> input = WithLinearField(Mesh("marching-cubes"), { 1, -3, 0.5 });
  const vtkIdType target = input->GetNumberOfPolys() / 10;
  std::vector<vtkSmartPointer<vtkPolyData>> outputs;
  slodtest::ForOneTwoAndEightThreads([&](int) {
    vtkNew<vtkQuadricTriangleCollapse> filter;
    filter->SetInputData(input);
    filter->SetTargetNumberOfTriangles(target);
    filter->BatchCollapsesOn();
    filter->Update();
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(filter->GetOutput());
    outputs.push_back(out);
  });
  const TriangleMesh first = slodtest::RawTriangleMesh(outputs[0]);
  vtkDataArray* firstField = outputs[0]->GetPointData()->GetArray("f");
  ASSERT_NE(firstField, nullptr);
  for (size_t i = 1; i < outputs.size(); ++i)
  {
    const TriangleMesh other = slodtest::RawTriangleMesh(outputs[i]);
    EXPECT_EQ(first.Points, other.Points);
    EXPECT_EQ(first.Triangles, other.Triangles);
    vtkDataArray* field = outputs[i]->GetPointData()->GetArray("f");
    ASSERT_NE(field, nullptr);
    ASSERT_EQ(field->GetNumberOfTuples(), firstField->GetNumberOfTuples());
    for (vtkIdType k = 0; k < field->GetNumberOfTuples(); ++k)
    {
      ASSERT_EQ(field->GetTuple1(k), firstField->GetTuple1(k));
    }
  }
  const MeshStatistics before = ComputeMeshStatistics(slodtest::ToTriangleMesh(input));
  const MeshStatistics after = ComputeMeshStatistics(first);
  EXPECT_LE(first.NumberOfTriangles(), target);
  EXPECT_GE(first.NumberOfTriangles(), target - 3);
  EXPECT_EQ(after.NonManifoldEdges, 0);
  EXPECT_EQ(after.Genus, before.Genus);
  EXPECT_EQ(after.Components, before.Components);
  double batchHausdorff = 0, batchMean = 0, strictHausdorff = 0, strictMean = 0;
  Deviation(input, outputs[0], batchHausdorff, batchMean, 100000);
  Deviation(input, Collapse(input, target), strictHausdorff, strictMean, 100000);
  EXPECT_LE(batchHausdorff, 1.02 * strictHausdorff);
  EXPECT_LE(batchMean, 1.02 * strictMean);
}

// The batches' selection (entries popped, entries that ran) and the output of every result equal
// the first's (the thread counts of ResultsForOneTwoAndEightThreads).
void ExpectTheSameBatchesAndOutputs(const std::vector<TriangleCollapseResult>& results)
{
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_EQ(results[i].SelectedEntries, results[0].SelectedEntries);
    EXPECT_EQ(results[i].RanEntries, results[0].RanEntries);
    EXPECT_EQ(results[i].Mesh.Points, results[0].Mesh.Points);
    EXPECT_EQ(results[i].Mesh.Triangles, results[0].Mesh.Triangles);
  }
}

// The marching-cubes mesh (its equal costs make large, overlapping batches) to a tenth in
// batches, for 1, 2 and 8 threads; input and options are set to those of the runs.
std::vector<TriangleCollapseResult> MarchingCubesInBatches(
  vtkSmartPointer<vtkPolyData>& input, TriangleCollapseOptions& options)
{
  input = Mesh("marching-cubes");
  options = TriangleCollapseOptions();
  options.TargetTriangles = static_cast<Index>(input->GetNumberOfPolys() / 10);
  options.BatchCollapses = true;
  return ResultsForOneTwoAndEightThreads(input, options);
}

// Session 41: a batch entry claims the ring of its operation, which needs the operation only; an
// edge operation's placement waits until the entry holds its claims, so the entries that lose
// them to an earlier entry (most of the others on a marching-cubes mesh: ties) are not placed.
// Every entry that ran was placed; only entries that did not run skip it; the counts, like the
// output, are the same for 1, 2 and 8 threads. The strict order's lone entries always run.
TEST(QuadricTriangleCollapse, BatchEntriesThatLoseTheirClaimsAreNotPlaced)
{
  vtkSmartPointer<vtkPolyData> input;
  TriangleCollapseOptions options;
  const std::vector<TriangleCollapseResult> results = MarchingCubesInBatches(input, options);
  const TriangleCollapseResult& first = results[0];
  const long long lost = first.SelectedEntries - first.RanEntries;
  std::printf("[batch placements] %lld entries, %lld ran, %lld lost, %lld not placed\n", first.SelectedEntries,
    first.RanEntries, lost, first.PlacementsNotMade);
  ASSERT_GT(lost, 0) << "no entry lost its claims: the test needs overlapping batches";
  EXPECT_GT(first.PlacementsNotMade, 0);
  EXPECT_LE(first.PlacementsNotMade, lost);
  EXPECT_GT(2 * first.PlacementsNotMade, lost) << "most lost entries are edge operations (bias 2)";
  EXPECT_GE(first.RanEntries, static_cast<long long>(first.Collapses));
  ExpectTheSameBatchesAndOutputs(results);
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_EQ(results[i].PlacementsNotMade, first.PlacementsNotMade);
  }
  options.BatchCollapses = false;
  TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult strict;
  SimplifyByTriangleCollapse(mesh, options, strict);
  EXPECT_EQ(strict.PlacementsNotMade, 0);
  EXPECT_EQ(strict.RanEntries, strict.SelectedEntries);
}

// Session 42: on one thread (or for a batch of one task) the claims are made in selection order,
// so each entry learns from its own walk whether an earlier entry holds a vertex of its ring: every
// entry's ring is walked at most once (concurrent claims need a second walk, the holders' check).
// Every batch is formed here (BatchMinimumSize 1). The same selection and output for 1, 2 and 8
// threads; on more threads the larger batches claim concurrently, so they walk more.
// To a tenth in batches, every batch formed as selected (session 41's batches).
TriangleCollapseOptions EveryBatchToATenth(vtkPolyData* input)
{
  TriangleCollapseOptions options;
  options.TargetTriangles = static_cast<Index>(input->GetNumberOfPolys() / 10);
  options.BatchCollapses = true;
  options.BatchMinimumSize = 1;
  return options;
}

TEST(QuadricTriangleCollapse, BatchClaimsWalkEachRingOnceOnOneThread)
{
  vtkSmartPointer<vtkPolyData> input = Mesh("marching-cubes");
  const TriangleCollapseOptions options = EveryBatchToATenth(input);
  const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
  const TriangleCollapseResult& first = results[0];
  std::printf("[ring walks] %lld entries, %lld ran, %lld ring walks\n", first.SelectedEntries, first.RanEntries,
    first.RingWalks);
  ASSERT_GT(first.SelectedEntries - first.RanEntries, 0) << "no entry lost its claims: the test needs overlapping batches";
  EXPECT_GT(first.RingWalks, 0);
  EXPECT_LE(first.RingWalks, first.SelectedEntries) << "a ring was walked twice on one thread";
  ExpectTheSameBatchesAndOutputs(results);
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_GE(results[i].RingWalks, first.RingWalks);
  }
}

// Session 42: a batch that will hold fewer than BatchMinimumSize entries (counted in the queue
// within the tolerance, before the batch is formed) is performed as a lone pop, without claims.
// Against every batch formed (1): some batches are popped alone, fewer rings are walked, and the
// outputs are the same for 1, 2 and 8 threads.
TEST(QuadricTriangleCollapse, SmallBatchesArePoppedAlone)
{
  vtkSmartPointer<vtkPolyData> input = Mesh("bunny00");
  TriangleCollapseOptions options = EveryBatchToATenth(input);
  TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult every;
  SimplifyByTriangleCollapse(mesh, options, every);
  options.BatchMinimumSize = 16;
  const std::vector<TriangleCollapseResult> results = ResultsForOneTwoAndEightThreads(input, options);
  const TriangleCollapseResult& first = results[0];
  std::printf("[small batches] every batch: %lld ring walks; minimum 16: %lld popped alone, %lld ring walks\n",
    every.RingWalks, first.BatchesPoppedAlone, first.RingWalks);
  EXPECT_EQ(every.BatchesPoppedAlone, 0);
  EXPECT_GT(first.BatchesPoppedAlone, 0);
  EXPECT_LT(first.RingWalks, every.RingWalks);
  for (size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_EQ(results[i].BatchesPoppedAlone, first.BatchesPoppedAlone);
    EXPECT_EQ(results[i].Mesh.Points, first.Mesh.Points);
    EXPECT_EQ(results[i].Mesh.Triangles, first.Mesh.Triangles);
  }
}

// Session 45's counters of the batches' work that several threads share, read where the library
// has them; -1 where it does not (the test then fails by its assertions on base-s45).
struct SharedCounters
{
  long long Batches = -1, Entries = -1, Collapses = -1;
};
template <class R>
auto SharedCountersOf(const R& r, int)
  -> decltype(r.SharedStepBatches + r.SharedStepEntries + r.SharedStepCollapses, SharedCounters())
{
  return { r.SharedStepBatches, r.SharedStepEntries, r.SharedStepCollapses };
}
template <class R>
SharedCounters SharedCountersOf(const R&, long)
{
  return {};
}

// Session 45: on two threads only the steps of the larger batches are shared; the collapses that
// stay on the calling thread are sequential work (Amdahl). A batch's steps split when it holds
// more than 16 entries, and its collapses run in a split step when there are more than four of
// them, so the calling thread performs at most one collapse per lone pop, one per entry of a
// batch too small to split, and four per split batch (before, a split batch that ran up to 16
// collapses performed them all there: on this mesh half of its collapses). Counted from sizes:
// the same for 1, 2 and 8 threads, as the output is; none in the strict order.
TEST(QuadricTriangleCollapse, BatchCollapsesLeaveFewCollapsesToTheCallingThread)
{
  vtkSmartPointer<vtkPolyData> input;
  TriangleCollapseOptions options;
  const std::vector<TriangleCollapseResult> results = MarchingCubesInBatches(input, options);
  const TriangleCollapseResult& first = results[0];
  const SharedCounters shared = SharedCountersOf(first, 0);
  const long long lone = first.BatchesPoppedAlone;
  const long long unsplit = first.SelectedEntries - lone - shared.Entries; // entries of batches of at most 16
  const long long onCaller = static_cast<long long>(first.Collapses) - shared.Collapses;
  std::printf("[shared steps] %lld batches, %lld of %lld entries, %lld of %d collapses; %lld lone pops\n", shared.Batches,
    shared.Entries, first.SelectedEntries, shared.Collapses, int(first.Collapses), lone);
  ASSERT_GT(first.SelectedEntries - lone, 16 * 16) << "the test needs larger batches";
  EXPECT_GT(shared.Batches, 0);
  EXPECT_GT(shared.Entries, 16 * shared.Batches);
  EXPECT_GE(unsplit, 0);
  EXPECT_GT(shared.Collapses, 0);
  EXPECT_LE(onCaller, lone + unsplit + 4 * shared.Batches) << "collapses of split batches left to the calling thread";
  ExpectTheSameBatchesAndOutputs(results);
  for (size_t i = 1; i < results.size(); ++i)
  {
    const SharedCounters other = SharedCountersOf(results[i], 0);
    EXPECT_EQ(other.Batches, shared.Batches);
    EXPECT_EQ(other.Entries, shared.Entries);
    EXPECT_EQ(other.Collapses, shared.Collapses);
  }
  options.BatchCollapses = false;
  TriangleMesh mesh = slodtest::ToTriangleMesh(input);
  TriangleCollapseResult strict;
  SimplifyByTriangleCollapse(mesh, options, strict);
  EXPECT_EQ(SharedCountersOf(strict, 0).Collapses, 0);
  EXPECT_EQ(SharedCountersOf(strict, 0).Entries, 0);
}

TEST(QuadricTriangleCollapse, PointDataErrorArrayAndFieldData)
{
  // A linear field f = x + 2y - z is reproduced (up to the clamped barycentric weights).
  vtkSmartPointer<vtkPolyData> input = WithLinearField(slodtest::LoadTestMesh("bunny00"), { 1, 2, -1 });
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetReduction(0.9);
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  vtkDataArray* g = out->GetPointData()->GetArray("f");
  ASSERT_NE(g, nullptr);
  ASSERT_EQ(g->GetNumberOfTuples(), out->GetNumberOfPoints());
  const double diagonal = std::sqrt(vtkMath::Distance2BetweenPoints(input->GetBounds(), input->GetBounds() + 3));
  double meanDifference = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    meanDifference += std::fabs(g->GetComponent(i, 0) - (p[0] + 2 * p[1] - p[2]));
  }
  meanDifference /= out->GetNumberOfPoints();
  EXPECT_LT(meanDifference, 2e-3 * diagonal);

  vtkDataArray* error = out->GetPointData()->GetArray("SimplificationError");
  ASSERT_NE(error, nullptr);
  ASSERT_EQ(error->GetNumberOfTuples(), out->GetNumberOfPoints());
  vtkDataArray* maxError = out->GetFieldData()->GetArray("MaximumSimplificationError");
  ASSERT_NE(maxError, nullptr);
  const double m = maxError->GetComponent(0, 0);
  EXPECT_GT(m, 0.0);
  EXPECT_DOUBLE_EQ(m, filter->GetMaximumSimplificationError());
  EXPECT_LE(error->GetRange()[1], m * (1 + 1e-9));
  EXPECT_NE(out->GetFieldData()->GetArray("MaximumSimplificationErrorRelative"), nullptr);
  EXPECT_NEAR(filter->GetActualReduction(), 0.9, 0.001);
}

TEST(QuadricTriangleCollapse, MaximumErrorStopsFirst)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetReduction(0.99);
  filter->SetMaximumError(2e-4);
  filter->MaximumErrorIsRelativeOn();
  filter->Update();
  const vtkIdType n = filter->GetOutput()->GetNumberOfPolys();
  // The error bound is reached before the 99 % reduction, and it holds.
  EXPECT_GT(n, vtkIdType(0.01 * input->GetNumberOfPolys()) + 4);
  EXPECT_LT(n, input->GetNumberOfPolys());
  const double relative = filter->GetOutput()->GetFieldData()->GetArray("MaximumSimplificationErrorRelative")->GetComponent(0, 0);
  EXPECT_LE(relative, 2e-4);
  // A looser bound lets the count target stop first.
  filter->SetMaximumError(1.0);
  filter->Update();
  EXPECT_LE(filter->GetOutput()->GetNumberOfPolys(), vtkIdType(0.01 * input->GetNumberOfPolys()));
}

TEST(QuadricTriangleCollapse, PaperModeTriangleCollapsesOnly)
{
  // With edge collapses off every operation merges three vertices: 2 vertices fewer each.
  TriangleMesh mesh = slodtest::ToTriangleMesh(slodtest::LoadTestMesh("fandisk"));
  const Index n0 = mesh.NumberOfPoints();
  TriangleCollapseOptions options;
  options.EdgeCollapses = false;
  options.TargetTriangles = 1000;
  options.RecordHistory = true;
  TriangleCollapseResult result;
  SimplifyByTriangleCollapse(mesh, options, result);
  EXPECT_EQ(result.Mesh.NumberOfPoints(), n0 - 2 * result.Collapses);
  for (Index k = 0; k < result.History.NumberOfCollapses(); ++k)
  {
    ASSERT_NE(result.History.Vertices[3 * size_t(k) + 2], InvalidIndex);
  }
  EXPECT_LE(result.Mesh.NumberOfTriangles(), 1000);
  EXPECT_EQ(ComputeMeshStatistics(result.Mesh).Genus, 0);
}

// The paper's configuration (UsePaperConfiguration: triangle collapses only, exact union, no pass
// after the collapses) against the default and vtkQuadricDecimation at the same count, same run.
// Asserted: the operations each mode performs (paper: only triangle collapses, each removing two
// vertices, nothing moved afterwards; default: edge collapses too, and the fit moves vertices),
// the topology kept, and that the default is at least as close to the input as the paper's mode
// (why it is the default). The ratios to vtkQuadricDecimation are printed for the documentation.
TEST(QuadricTriangleCollapse, PaperConfigurationIsTheTriangleCollapseOnly)
{
  for (const char* name : { "bunny00", "armadillo", "fandisk", "femur" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const TriangleMesh in = slodtest::ToTriangleMesh(input);
    const vtkIdType target = in.NumberOfTriangles() / 10;
    vtkNew<vtkQuadricTriangleCollapse> paper, improved;
    paper->UsePaperConfiguration();
    EXPECT_TRUE(!paper->GetEdgeCollapses() && paper->GetExactUnion() && !paper->GetFitToOriginal() && !paper->GetDeviationRefinement());
    for (vtkQuadricTriangleCollapse* filter : { paper.Get(), improved.Get() })
    {
      filter->SetInputData(input);
      filter->SetTargetNumberOfTriangles(target);
      filter->SetTargetReduction(0);
      filter->Update();
      const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
      slodtest::ExpectSameTopology(in, out);
      EXPECT_LE(out.NumberOfTriangles(), target);
      // A triangle collapse removes two vertices, an edge collapse one.
      const vtkIdType edges = filter->GetNumberOfEdgeCollapses(), triangles = filter->GetNumberOfCollapses() - edges;
      EXPECT_EQ(out.NumberOfPoints(), in.NumberOfPoints() - 2 * triangles - edges);
    }
    EXPECT_EQ(paper->GetNumberOfEdgeCollapses(), 0);
    EXPECT_EQ(paper->GetNumberOfFittedVertices() + paper->GetNumberOfRefinedVertices(), 0);
    EXPECT_GT(improved->GetNumberOfEdgeCollapses(), 0);
    EXPECT_GT(improved->GetNumberOfFittedVertices(), 0);

    vtkNew<vtkQuadricDecimation> reference;
    reference->SetInputData(input);
    reference->SetTargetReduction(1.0 - double(target) / in.NumberOfTriangles());
    reference->Update();
    double hp, mp, hi, mi, hq, mq;
    Deviation(input, paper->GetOutput(), hp, mp);
    Deviation(input, improved->GetOutput(), hi, mi);
    Deviation(input, reference->GetOutput(), hq, mq);
    std::printf("[paper] %s to %lld: paper (%lld triangle collapses) Hausdorff %.3e (%.2fx vtkQD) mean %.3e (%.2fx) | "
                "default (%lld triangle + %lld edge collapses, %lld fitted, %lld refined) Hausdorff %.3e (%.2fx) mean %.3e (%.2fx)\n",
      name, (long long)target, (long long)paper->GetNumberOfCollapses(), hp, hp / hq, mp, mp / mq,
      (long long)(improved->GetNumberOfCollapses() - improved->GetNumberOfEdgeCollapses()),
      (long long)improved->GetNumberOfEdgeCollapses(), (long long)improved->GetNumberOfFittedVertices(),
      (long long)improved->GetNumberOfRefinedVertices(), hi, hi / hq, mi, mi / mq);
    EXPECT_LE(hi, hp);
    EXPECT_LE(mi, mp);
  }
}

// The fit's two ways of knowing whom a move can affect (the exact closest-triangle assignment of
// small inputs, the neighbourhood of large ones) both lower the mean without raising the maximum.
TEST(QuadricTriangleCollapse, FitGuardsExactAndLocal)
{
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("armadillo");
  auto run = [&](bool fit, Index exactLimit, double& hausdorff, double& mean) {
    TriangleMesh mesh = slodtest::ToTriangleMesh(input);
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 50;
    options.RefineDeviation = false;
    options.FitToOriginal = fit;
    options.FitExactAssignmentLimit = exactLimit;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    Deviation(input, slodtest::ToPolyData(result.Mesh), hausdorff, mean);
    return result.Mesh;
  };
  double h0, m0, hExact, mExact, hLocal, mLocal;
  const TriangleMesh off = run(false, 0, h0, m0);
  const TriangleMesh exact = run(true, 1 << 30, hExact, mExact);
  const TriangleMesh local = run(true, 0, hLocal, mLocal);
  std::printf("[fit guards] armadillo 2%%: off H %.4e mean %.4e | exact H %.4e mean %.4e | local H %.4e mean %.4e\n", h0,
    m0, hExact, mExact, hLocal, mLocal);
  // Measured: mean -7 % (exact), -2 % (local: its guard blocks more moves); Hausdorff lower in both.
  EXPECT_LT(mExact, 0.97 * m0);
  EXPECT_LT(mLocal, 0.99 * m0);
  EXPECT_LE(hExact, 1.01 * h0);
  EXPECT_LE(hLocal, 1.01 * h0);
  EXPECT_EQ(exact.Triangles, off.Triangles);
  EXPECT_EQ(local.Triangles, off.Triangles);
}

// Locked vertices (the seams of distributed pieces) stay exactly where they are, with or without
// topology changes, while the count target is still met by collapsing around them.
TEST(QuadricTriangleCollapse, LockedVerticesStayExactly)
{
  const TriangleMesh sphere = slodtest::Sphere(64, 48);
  std::vector<unsigned char> locked(size_t(sphere.NumberOfPoints()), 0);
  std::set<std::tuple<double, double, double>> lockedPositions;
  for (Index v = 0; v < sphere.NumberOfPoints(); ++v)
  {
    const Vec3 p = sphere.Point(v);
    if (p[1] == 0.0 && p[0] >= 0.0) // one meridian, pole to pole: a seam
    {
      locked[v] = 1;
      lockedPositions.emplace(p[0], p[1], p[2]);
    }
  }
  ASSERT_GE(lockedPositions.size(), 40u);
  for (const bool allowTopologyChange : { false, true })
  {
    TriangleMesh mesh = sphere;
    TriangleCollapseOptions options;
    options.TargetTriangles = mesh.NumberOfTriangles() / 10;
    options.AllowTopologyChange = allowTopologyChange;
    options.LockedVertices = &locked;
    TriangleCollapseResult result;
    SimplifyByTriangleCollapse(mesh, options, result);
    std::set<std::tuple<double, double, double>> kept;
    for (Index v = 0; v < result.Mesh.NumberOfPoints(); ++v)
    {
      const Vec3 p = result.Mesh.Point(v);
      if (lockedPositions.count({ p[0], p[1], p[2] }))
      {
        kept.emplace(p[0], p[1], p[2]);
        EXPECT_TRUE(locked[result.OutputToInput[v]]) << "a vertex moved onto a locked position";
      }
    }
    EXPECT_EQ(kept, lockedPositions) << "allowTopologyChange " << allowTopologyChange;
    EXPECT_LE(result.Mesh.NumberOfTriangles(), options.TargetTriangles);
  }
}

TEST(QuadricTriangleCollapse, BadInputGivesDefinedOutput)
{
  vtkNew<slodtest::MessageCounter> messages;
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->AddObserver(vtkCommand::ErrorEvent, messages);
  filter->AddObserver(vtkCommand::WarningEvent, messages);

  // Empty.
  vtkNew<vtkPolyData> empty;
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(messages->Errors.size(), 0u);

  // NaN coordinates: error, empty output.
  vtkSmartPointer<vtkPolyData> nan = slodtest::ToPolyData(slodtest::Sphere(12, 8));
  nan->GetPoints()->SetPoint(3, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  filter->SetInputData(nan);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(messages->Errors.size(), 1u);

  // Lines only: nothing to simplify, empty output with a warning.
  vtkNew<vtkPolyData> lines;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(1, 1, 0);
  vtkNew<vtkCellArray> cells;
  const vtkIdType line[3] = { 0, 1, 2 };
  cells->InsertNextCell(3, line);
  lines->SetPoints(points);
  lines->SetLines(cells);
  filter->SetInputData(lines);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPolys(), 0);
  EXPECT_GE(messages->Warnings.size(), 1u);

  // Non-manifold input: simplified where it is manifold, never made worse.
  const TriangleMesh fan = slodtest::Concatenate(slodtest::NonManifoldFan(4), slodtest::Sphere(24, 16));
  const MeshStatistics fanStats = ComputeMeshStatistics(fan);
  filter->SetInputData(slodtest::ToPolyData(fan));
  filter->SetTargetReduction(0.8);
  filter->Update();
  const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
  const MeshStatistics s = ComputeMeshStatistics(out);
  EXPECT_LT(out.NumberOfTriangles(), fan.NumberOfTriangles());
  EXPECT_LE(s.NonManifoldEdges, fanStats.NonManifoldEdges);
  EXPECT_EQ(s.DegenerateTriangles, 0);
  EXPECT_EQ(messages->Errors.size(), 1u);
}

// Quality: at the same output count as vtkQuadricDecimation, the symmetric Hausdorff and mean
// distances (vtkSurfaceDeviation, same samples) are no worse.
struct QualityCase
{
  const char* Mesh;
  double Fraction;
  // Allowed ratios to vtkQuadricDecimation: no worse, up to the sampling noise of the measure.
  // The mean is stable to 1 %; a sampled maximum is not: on bunny00 at 10 % the ratio reads 1.011
  // at 300,000 samples, 0.927 at 1,000,000 and 1.016 at 3,000,000, hence 2 % for the Hausdorff.
  double HausdorffRatio = 1.02;
  double MeanRatio = 1.01;
};

class TriangleCollapseQuality : public ::testing::TestWithParam<QualityCase>
{
};

TEST_P(TriangleCollapseQuality, NoWorseThanQuadricDecimation)
{
  const QualityCase c = GetParam();
  vtkSmartPointer<vtkPolyData> input = Mesh(c.Mesh);
  vtkNew<vtkQuadricDecimation> reference;
  reference->SetInputData(input);
  reference->SetTargetReduction(1.0 - c.Fraction);
  reference->Update();
  const vtkIdType count = reference->GetOutput()->GetNumberOfPolys();
  vtkSmartPointer<vtkPolyData> ours = Collapse(input, count);
  ASSERT_LE(ours->GetNumberOfPolys(), count);

  double hOurs, mOurs, hVtk, mVtk;
  Deviation(input, reference->GetOutput(), hVtk, mVtk);
  Deviation(input, ours, hOurs, mOurs);
  std::printf("[quality] %s %.0f%% (%lld tris): Hausdorff %.4e vs vtkQuadricDecimation %.4e (ratio %.3f), "
              "mean %.4e vs %.4e (ratio %.3f)\n",
    c.Mesh, 100 * c.Fraction, (long long)count, hOurs, hVtk, hVtk > 0 ? hOurs / hVtk : 0.0, mOurs, mVtk,
    mVtk > 0 ? mOurs / mVtk : 0.0);
  ASSERT_GT(hVtk, 0.0);
  ASSERT_GT(mVtk, 0.0);
  // vtkQuadricDecimation has no link condition. Where its output has another genus than the
  // input (femur at 1 %: genus 2 -> 0, both handles closed, which is what lowers its mean), our
  // run with the same freedom (AllowTopologyChangeOn) is the one compared; the default run keeps
  // the genus as the issue demands and is reported above.
  const MeshStatistics in = ComputeMeshStatistics(slodtest::RawTriangleMesh(input));
  const MeshStatistics theirs = ComputeMeshStatistics(slodtest::RawTriangleMesh(reference->GetOutput()));
  if (theirs.EulerCharacteristic != in.EulerCharacteristic && theirs.NonManifoldEdges == 0)
  {
    vtkNew<vtkQuadricTriangleCollapse> free;
    free->SetInputData(input);
    free->SetTargetNumberOfTriangles(count);
    free->SetTargetReduction(0);
    free->AllowTopologyChangeOn();
    free->Update();
    ASSERT_LE(free->GetOutput()->GetNumberOfPolys(), count);
    Deviation(input, free->GetOutput(), hOurs, mOurs);
    std::printf("[quality] %s %.0f%%: vtkQuadricDecimation changed the Euler characteristic %d -> %d; with "
                "AllowTopologyChange: Hausdorff ratio %.3f, mean ratio %.3f\n",
      c.Mesh, 100 * c.Fraction, int(in.EulerCharacteristic), int(theirs.EulerCharacteristic), hOurs / hVtk, mOurs / mVtk);
  }
  EXPECT_LE(hOurs, c.HausdorffRatio * hVtk);
  EXPECT_LE(mOurs, c.MeanRatio * mVtk);
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, TriangleCollapseQuality,
  ::testing::Values(QualityCase{ "fandisk", 0.1 }, QualityCase{ "fandisk", 0.01 },
    QualityCase{ "femur", 0.1 }, QualityCase{ "femur", 0.01 }, QualityCase{ "bunny00", 0.1 }, QualityCase{ "bunny00", 0.01 },
    QualityCase{ "armadillo", 0.1 }, QualityCase{ "armadillo", 0.01 },
    // The demo's isosurface (resolution 112).
    QualityCase{ "marching-cubes", 0.1 }, QualityCase{ "marching-cubes", 0.01 }),
  [](const ::testing::TestParamInfo<QualityCase>& info) {
    std::string name = std::string(info.param.Mesh) + "_" + std::to_string(int(std::lround(1000 * info.param.Fraction)));
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
  });

// The accumulated quadrics (default) against the paper's exact union of interrelated sets.
TEST(QuadricTriangleCollapse, AccumulatedQuadricsMatchExactUnionQuality)
{
  for (const char* name : { "fandisk", "femur" })
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh(name);
    const vtkIdType target = input->GetNumberOfPolys() / 20;
    vtkNew<vtkQuadricTriangleCollapse> exact;
    exact->SetInputData(input);
    exact->SetTargetNumberOfTriangles(target);
    exact->SetTargetReduction(0);
    exact->ExactUnionOn();
    exact->Update();
    vtkSmartPointer<vtkPolyData> accumulated = Collapse(input, target);
    const MeshStatistics s = ComputeMeshStatistics(slodtest::RawTriangleMesh(exact->GetOutput()));
    EXPECT_EQ(s.NonManifoldEdges, 0);
    EXPECT_LE(exact->GetOutput()->GetNumberOfPolys(), target);
    double h[2], m[2];
    vtkPolyData* outputs[2] = { accumulated, exact->GetOutput() };
    for (int i = 0; i < 2; ++i)
    {
      Deviation(input, outputs[i], h[i], m[i], 100000);
    }
    std::printf("[union] %s to %lld: accumulated Hausdorff %.4e mean %.4e | exact union Hausdorff %.4e mean %.4e\n",
      name, (long long)target, h[0], m[0], h[1], m[1]);
    ASSERT_GT(h[1], 0.0) << "vtkSurfaceDeviation measured no distance: quality not measured";
    // Measured: the accumulated quadrics cost up to ~20 % in mean distance (and ~45 % in
    // Hausdorff on fandisk) against the exact union, at a third of the run time.
    EXPECT_LE(h[0], 1.6 * h[1]);
    EXPECT_LE(m[0], 1.3 * m[1]);
  }
}

namespace
{
// The filter at a count with the post-collapse passes chosen, and its deviation from the input.
TriangleMesh CollapseWithPasses(vtkPolyData* input, vtkIdType target, bool fit, bool refine, vtkIdType samples,
  double& hausdorff, double& mean)
{
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(target);
  filter->SetTargetReduction(0);
  filter->SetFitToOriginal(fit);
  filter->SetDeviationRefinement(refine);
  filter->Update();
  Deviation(input, filter->GetOutput(), hausdorff, mean, samples);
  return slodtest::RawTriangleMesh(filter->GetOutput());
}
} // namespace

// The deviation refinement (default on) moves a few vertices of the worst regions: on armadillo
// at 1 % it lowers the Hausdorff distance, keeps the mean, the count and the topology, and the
// paper's result is still available with DeviationRefinementOff() and FitToOriginalOff(). The
// progressive records of the default (fit and refinement) rebuild the moved positions exactly.
TEST(QuadricTriangleCollapse, DeviationRefinementLowersTheMaximum)
{
  vtkSmartPointer<vtkPolyData> input = Mesh("armadillo");
  const vtkIdType target = input->GetNumberOfPolys() / 100;
  // The refinement's own effect: the fit off in both runs.
  double hOff, mOff, hOn, mOn;
  const TriangleMesh off = CollapseWithPasses(input, target, false, false, 100000, hOff, mOff);
  const TriangleMesh on = CollapseWithPasses(input, target, false, true, 100000, hOn, mOn);
  std::printf("[refinement] armadillo 1%%: Hausdorff %.4e -> %.4e, mean %.4e -> %.4e\n", hOff, hOn, mOff, mOn);
  EXPECT_EQ(on.NumberOfTriangles(), off.NumberOfTriangles());
  EXPECT_LT(hOn, 0.9 * hOff);
  EXPECT_LE(mOn, 1.01 * mOff);
  const MeshStatistics a = ComputeMeshStatistics(off), b = ComputeMeshStatistics(on);
  EXPECT_EQ(b.Genus, a.Genus);
  EXPECT_EQ(b.NonManifoldEdges, 0);
  EXPECT_EQ(b.DegenerateTriangles, 0);
  EXPECT_EQ(b.InconsistentlyOrientedEdges, 0);
  // Same connectivity: only positions move.
  EXPECT_EQ(on.Triangles, off.Triangles);

  // The progressive records place the moved vertices where the output has them: splitting
  // everything and collapsing back gives the output again.
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(target);
  filter->SetTargetReduction(0);
  filter->GenerateProgressiveMeshOn();
  vtkNew<vtkProgressiveMeshReconstruction> levels;
  levels->SetCoarseMeshConnection(filter->GetOutputPort(0));
  levels->SetRecordsConnection(filter->GetOutputPort(1));
  levels->SetNumberOfVertexSplits(-1);
  levels->Update();
  EXPECT_EQ(levels->GetOutput()->GetNumberOfPolys(), input->GetNumberOfPolys());
  levels->SetNumberOfVertexSplits(0);
  levels->Update();
  const TriangleMesh back = slodtest::RawTriangleMesh(levels->GetOutput());
  auto sortedPoints = [](const TriangleMesh& m) {
    std::vector<std::array<double, 3>> points;
    for (Index v = 0; v < m.NumberOfPoints(); ++v)
    {
      points.push_back(m.Point(v));
    }
    std::sort(points.begin(), points.end());
    return points;
  };
  const TriangleMesh moved = slodtest::RawTriangleMesh(filter->GetOutput());
  EXPECT_EQ(back.NumberOfTriangles(), moved.NumberOfTriangles());
  EXPECT_TRUE(sortedPoints(back) == sortedPoints(moved));
}

// The fit to the original surface (default on) lowers the mean distance and never raises the
// maximum beyond the sampling noise, with the same connectivity and topology.
TEST(QuadricTriangleCollapse, FitToOriginalLowersTheMeanNotTheMaximum)
{
  // Mesh, kept fraction, and the mean ratio to reach (measured 0.901, 0.968, 0.963).
  const std::tuple<const char*, double, double> cases[] = { { "armadillo", 0.01, 0.93 }, { "femur", 0.1, 0.985 },
    { "fandisk", 0.1, 0.98 } };
  for (const auto& tuple : cases)
  {
    const std::pair<const char*, double> c(std::get<0>(tuple), std::get<1>(tuple));
    vtkSmartPointer<vtkPolyData> input = Mesh(c.first);
    const vtkIdType target = static_cast<vtkIdType>(c.second * input->GetNumberOfPolys());
    // The fit's own effect: the refinement off in both runs.
    double hOff, mOff, hOn, mOn;
    const TriangleMesh off = CollapseWithPasses(input, target, false, false, 300000, hOff, mOff);
    const TriangleMesh on = CollapseWithPasses(input, target, true, false, 300000, hOn, mOn);
    std::printf("[fit] %s %.0f%%: Hausdorff %.4e -> %.4e, mean %.4e -> %.4e (%.3f)\n", c.first, 100 * c.second, hOff,
      hOn, mOff, mOn, mOn / mOff);
    EXPECT_LT(mOn, std::get<2>(tuple) * mOff) << c.first;
    EXPECT_LE(hOn, 1.01 * hOff) << c.first;
    EXPECT_EQ(on.Triangles, off.Triangles) << c.first;
    const MeshStatistics a = ComputeMeshStatistics(off), b = ComputeMeshStatistics(on);
    EXPECT_EQ(b.Genus, a.Genus);
    EXPECT_EQ(b.NonManifoldEdges, 0);
    EXPECT_EQ(b.DegenerateTriangles, 0);
    EXPECT_EQ(b.InconsistentlyOrientedEdges, 0);
  }
}

namespace
{
// Connected sets of border edges (joined at shared vertices): unlike a count of loops walked
// through pinched border vertices, it does not depend on how a walk leaves a pinch.
Index BorderComponents(const TriangleMesh& mesh)
{
  std::map<std::pair<Index, Index>, int> edges;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      ++edges[{ std::min(tri[k], tri[(k + 1) % 3]), std::max(tri[k], tri[(k + 1) % 3]) }];
    }
  }
  UnionFind sets(mesh.NumberOfPoints());
  std::set<Index> onBorder;
  for (const auto& e : edges)
  {
    if (e.second == 1)
    {
      sets.Union(e.first.first, e.first.second);
      onBorder.insert(e.first.first);
      onBorder.insert(e.first.second);
    }
  }
  std::set<Index> roots;
  for (Index v : onBorder)
  {
    roots.insert(sets.Find(v));
  }
  return static_cast<Index>(roots.size());
}
} // namespace

// A scan-like isosurface (noisy integer-valued volume): its non-manifold edges and pinched vertices
// stay as they are (never cut open, never collapsed away with a small component), so the output
// has the input's Euler characteristic, border loops, components and non-manifold edges.
TEST(QuadricTriangleCollapse, NoisyScanIsosurfaceKeepsItsTopology)
{
  for (unsigned seed : { 1u, 2u, 3u })
  {
    SCOPED_TRACE(seed);
    vtkSmartPointer<vtkPolyData> input = slodtest::NoisyScanIsosurface(55, seed);
    const TriangleMesh in = slodtest::ToTriangleMesh(input);
    const MeshStatistics before = ComputeMeshStatistics(in);
    const Index borderBefore = BorderComponents(in);
    // The case must be what it claims: otherwise the test proves nothing.
    ASSERT_GT(before.NonManifoldEdges + before.NonManifoldVertices, 0);
    ASSERT_GT(before.BoundaryLoops, 0);
    ASSERT_LT(before.EulerCharacteristic, 0); // handles
    for (double reduction : { 0.9, 0.97 })
    {
      vtkNew<vtkQuadricTriangleCollapse> filter;
      filter->SetInputData(input);
      filter->SetGlobalWarningDisplay(0);
      filter->SetTargetReduction(reduction);
      filter->Update();
      const TriangleMesh out = slodtest::RawTriangleMesh(filter->GetOutput());
      const MeshStatistics after = ComputeMeshStatistics(out);
      std::printf("[noisy scan %u, %.2f] %d -> %d triangles; euler %lld -> %lld, loops %d -> %d, non-manifold "
                  "edges %d -> %d, components %d -> %d\n", seed, reduction, int(before.Triangles), int(after.Triangles),
        before.EulerCharacteristic, after.EulerCharacteristic, int(before.BoundaryLoops), int(after.BoundaryLoops),
        int(before.NonManifoldEdges), int(after.NonManifoldEdges), int(before.Components), int(after.Components));
      EXPECT_LT(after.Triangles, before.Triangles / 2);
      EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
      EXPECT_EQ(BorderComponents(out), borderBefore);
      if (BorderComponents(out) != borderBefore || after.EulerCharacteristic != before.EulerCharacteristic)
      {
        vtkNew<vtkXMLPolyDataWriter> writer; // for a look at the failure
        writer->SetInputData(input);
        writer->SetFileName(slodtest::OutputPath("noisy-scan-input.vtp").c_str());
        writer->Write();
        writer->SetInputData(filter->GetOutput());
        writer->SetFileName(slodtest::OutputPath("noisy-scan-output.vtp").c_str());
        writer->Write();
      }
      EXPECT_EQ(after.NonManifoldEdges, before.NonManifoldEdges);
      EXPECT_EQ(after.Components, before.Components);
      EXPECT_EQ(after.DegenerateTriangles, 0);
    }
  }
}

TEST(QuadricTriangleCollapse, TopologyChangeOnlyWhenAllowed)
{
  // elephant-with-holes: 106 small holes keep at least 3 border vertices each, so without
  // topology changes the filter stops above a 2 % target; allowing them, it reaches it.
  vtkSmartPointer<vtkPolyData> input = slodtest::LoadTestMesh("elephant-with-holes");
  const TriangleMesh in = slodtest::ToTriangleMesh(input);
  const MeshStatistics before = ComputeMeshStatistics(in);
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetGlobalWarningDisplay(0);
  filter->SetTargetNumberOfTriangles(in.NumberOfTriangles() / 50);
  filter->SetTargetReduction(0);
  filter->Update();
  const MeshStatistics kept = ComputeMeshStatistics(slodtest::RawTriangleMesh(filter->GetOutput()));
  std::printf("[topology] input: loops %d, euler %lld, non-manifold vertices %d | output: loops %d, euler %lld, "
              "non-manifold vertices %d\n", int(before.BoundaryLoops), before.EulerCharacteristic,
    int(before.NonManifoldVertices), int(kept.BoundaryLoops), kept.EulerCharacteristic, int(kept.NonManifoldVertices));
  EXPECT_GT(filter->GetOutput()->GetNumberOfPolys(), in.NumberOfTriangles() / 50);
  // The input's 65 pinched vertices (two border fans meeting) make its loop count ambiguous
  // (each pinch can join two loops, 134 counted here, 106 by anchorbench's meshdist); the
  // simplified mesh has none left and keeps every hole.
  EXPECT_EQ(kept.NonManifoldVertices, 0);
  EXPECT_EQ(kept.NonManifoldEdges, 0);
  EXPECT_GE(kept.BoundaryLoops, before.BoundaryLoops - before.NonManifoldVertices);
  EXPECT_GE(kept.BoundaryLoops, 106);
  filter->AllowTopologyChangeOn();
  filter->Update();
  EXPECT_LE(filter->GetOutput()->GetNumberOfPolys(), in.NumberOfTriangles() / 50);
  EXPECT_GE(filter->GetOutput()->GetNumberOfPolys(), in.NumberOfTriangles() / 50 - 3);
}
