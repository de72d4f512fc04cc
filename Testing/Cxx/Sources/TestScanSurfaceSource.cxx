// SPDX-License-Identifier: BSD-3-Clause
// The scan-like benchmark inputs (vtkScanVolumeSource, vtkScanSurfaceSource): the defects of real
// scans where they are promised (and not on the smooth surface the noise is added to), counts
// bounded by what marching cubes and the construction allow at a resolution, identical output
// for a seed.
#include "TestSupport.h"

#include "slodMeshTopology.h"
#include "vtkScanSurfaceSource.h"
#include "vtkScanVolumeSource.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace
{
constexpr int Resolution = 120;

vtkSmartPointer<vtkPolyData> Generate(int kind, int resolution, unsigned int seed = 1, double noise = 1.75)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(kind);
  source->SetResolution(resolution);
  source->SetSeed(seed);
  source->SetNoiseAmplitude(noise);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

slod::MeshStatistics StatisticsOf(vtkPolyData* surface)
{
  return slod::ComputeMeshStatistics(slodtest::RawTriangleMesh(surface));
}

// The defects the noisy isosurface promises: handles far more than a smooth surface's none (at
// least one per 2,000 triangles: chi = 2C - 2g - b, so chi <= -T/1000 means over T/2000
// handles), a border on the volume's edge, non-manifold edges.
bool HasScanDefects(const slod::MeshStatistics& s)
{
  return s.EulerCharacteristic <= -s.Triangles / 1000 && s.BoundaryLoops > 0 && s.NonManifoldEdges > 0;
}

// Cells of the noisy intensity volume whose samples lie on both sides of the contour value:
// marching cubes puts 1 to 5 triangles in each of them and none elsewhere.
vtkIdType CrossingCells(int resolution)
{
  vtkNew<vtkScanVolumeSource> volume;
  volume->SetResolution(resolution);
  volume->Update();
  const short* v = static_cast<const short*>(volume->GetOutput()->GetScalarPointer());
  const double iso = vtkScanVolumeSource::GetNoisyIsoValue();
  const vtkIdType n = resolution;
  vtkIdType crossing = 0;
  for (vtkIdType k = 0; k + 1 < n; ++k)
  {
    for (vtkIdType j = 0; j + 1 < n; ++j)
    {
      for (vtkIdType i = 0; i + 1 < n; ++i)
      {
        int above = 0;
        for (int c = 0; c < 8; ++c)
        {
          above += v[((k + (c >> 2)) * n + j + ((c >> 1) & 1)) * n + i + (c & 1)] >= iso;
        }
        crossing += above > 0 && above < 8;
      }
    }
  }
  return crossing;
}

// FNV-1a over the point coordinates and the connectivity.
std::uint64_t SurfaceHash(vtkPolyData* surface)
{
  std::uint64_t hash = 1469598103934665603ull;
  auto add = [&hash](const void* data, size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t b = 0; b < bytes; ++b)
    {
      hash = (hash ^ p[b]) * 1099511628211ull;
    }
  };
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    double p[3];
    surface->GetPoint(i, p);
    add(p, sizeof(p));
  }
  vtkDataArray* connectivity = surface->GetPolys()->GetConnectivityArray();
  for (vtkIdType i = 0; i < connectivity->GetNumberOfTuples(); ++i)
  {
    const long long id = static_cast<long long>(connectivity->GetTuple1(i));
    add(&id, sizeof(id));
  }
  return hash;
}

// Triangles whose normal is exactly along a coordinate axis (a flat face of voxels).
double AxisAlignedFraction(vtkPolyData* surface)
{
  const slod::TriangleMesh mesh = slodtest::RawTriangleMesh(surface);
  slod::Index aligned = 0;
  for (slod::Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const slod::Vec3 n = slod::Normalized(mesh.TriangleAreaVector(t));
    aligned += std::abs(n[0]) > 1 - 1e-6 || std::abs(n[1]) > 1 - 1e-6 || std::abs(n[2]) > 1 - 1e-6;
  }
  return double(aligned) / double(mesh.NumberOfTriangles());
}
} // namespace

TEST(ScanSurfaceSource, NoisyIsosurfaceHasTheDefectsOfAScan)
{
  vtkSmartPointer<vtkPolyData> noisy = Generate(vtkScanSurfaceSource::NoisyIsosurface, Resolution);
  const slod::MeshStatistics s = StatisticsOf(noisy);
  std::printf("noisy %d: %lld triangles, chi %lld, %lld border loops, %lld non-manifold edges\n", Resolution,
    (long long)s.Triangles, s.EulerCharacteristic, (long long)s.BoundaryLoops, (long long)s.NonManifoldEdges);
  EXPECT_TRUE(HasScanDefects(s));
  EXPECT_EQ(s.DegenerateTriangles, 0); // removed by the clean-up, as in a real pipeline
  EXPECT_EQ(s.Vertices, noisy->GetNumberOfPoints());

  // The smooth surface under the noise (same resolution, no noise) has none of them: a ball cut
  // by the volume's face, one border loop, chi = 1.
  vtkSmartPointer<vtkPolyData> smooth = Generate(vtkScanSurfaceSource::NoisyIsosurface, Resolution, 1, 0.0);
  const slod::MeshStatistics smoothStatistics = StatisticsOf(smooth);
  EXPECT_FALSE(HasScanDefects(smoothStatistics));
  EXPECT_EQ(smoothStatistics.EulerCharacteristic, 1);
  EXPECT_EQ(smoothStatistics.BoundaryLoops, 1);

  // Counts: noise only adds area to the smooth surface; marching cubes puts at most 5 triangles
  // in each cell whose samples straddle the contour value.
  EXPECT_GT(s.Triangles, smoothStatistics.Triangles);
  EXPECT_LE(s.Triangles, 5 * CrossingCells(Resolution));
}

TEST(ScanSurfaceSource, NoisyIsosurfaceScalesWithTheResolution)
{
  // The noise is the same in voxels at every resolution: twice the resolution is four times the
  // area in voxels, so about four times the triangles and the handles.
  const slod::MeshStatistics coarse = StatisticsOf(Generate(vtkScanSurfaceSource::NoisyIsosurface, Resolution));
  const slod::MeshStatistics fine = StatisticsOf(Generate(vtkScanSurfaceSource::NoisyIsosurface, 2 * Resolution));
  const double triangleRatio = double(fine.Triangles) / double(coarse.Triangles);
  const double eulerRatio = double(fine.EulerCharacteristic) / double(coarse.EulerCharacteristic);
  EXPECT_GT(triangleRatio, 3.5);
  EXPECT_LT(triangleRatio, 4.5);
  EXPECT_GT(eulerRatio, 3.0);
  EXPECT_LT(eulerRatio, 5.0);
  EXPECT_TRUE(HasScanDefects(fine));
}

TEST(ScanSurfaceSource, DeterministicForASeed)
{
  for (int kind : { vtkScanSurfaceSource::NoisyIsosurface, vtkScanSurfaceSource::OpenScan })
  {
    const std::uint64_t first = SurfaceHash(Generate(kind, 64));
    EXPECT_EQ(first, SurfaceHash(Generate(kind, 64))) << "kind " << kind;
    EXPECT_NE(first, SurfaceHash(Generate(kind, 64, 2))) << "kind " << kind << ": the seed changes nothing";
  }
}

TEST(ScanSurfaceSource, SegmentationMaskIsAStaircaseWithOneHandleAndOneBorder)
{
  vtkSmartPointer<vtkPolyData> mask = Generate(vtkScanSurfaceSource::SegmentationMask, Resolution);
  const slod::MeshStatistics s = StatisticsOf(mask);
  // One component: the organ with the ring (genus 1) and the stalk cut by the volume's face
  // (one border loop): chi = 2 - 2 - 1.
  EXPECT_EQ(s.Components, 1);
  EXPECT_EQ(s.BoundaryLoops, 1);
  EXPECT_EQ(s.EulerCharacteristic, -1);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.DegenerateTriangles, 0);
  // A binary mask contoured at 0.5: flat voxel faces, exactly axis-aligned triangles, make a
  // large part of the surface (a smooth isosurface has almost none).
  const double aligned = AxisAlignedFraction(mask);
  std::printf("mask %d: %lld triangles, %.3f axis-aligned\n", Resolution, (long long)s.Triangles, aligned);
  EXPECT_GT(aligned, 0.25);
  EXPECT_LT(AxisAlignedFraction(Generate(vtkScanSurfaceSource::NoisyIsosurface, Resolution, 1, 0.0)), 0.05);
  const double ratio = double(StatisticsOf(Generate(vtkScanSurfaceSource::SegmentationMask, 2 * Resolution)).Triangles) /
    double(s.Triangles);
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
}

TEST(ScanSurfaceSource, OpenScanHasHolesAndDropOuts)
{
  const int resolution = 2 * Resolution;
  vtkSmartPointer<vtkPolyData> scan = Generate(vtkScanSurfaceSource::OpenScan, resolution);
  const slod::MeshStatistics s = StatisticsOf(scan);
  std::printf("open scan %d: %lld triangles, chi %lld, %lld border loops, %lld components\n", resolution,
    (long long)s.Triangles, s.EulerCharacteristic, (long long)s.BoundaryLoops, (long long)s.Components);
  // Two triangles per grid cell inside the outline: an ellipse of semi-axes 0.95 x 0.85 whose
  // radius varies by 5% (+ half a cell of jitter), less up to 12 discs of radius <= 0.08.
  const double cells = double(resolution - 1) * (resolution - 1) / 4.0; // per unit area
  const double ellipse = M_PI * 0.95 * 0.85;
  EXPECT_GE(s.Triangles, 2 * cells * (ellipse * 0.94 * 0.94 - 12 * M_PI * 0.08 * 0.08));
  EXPECT_LE(s.Triangles, 2 * cells * ellipse * 1.06 * 1.06);
  // Border loops: the outline, the holes inside it and most single-triangle drop-outs (one per
  // 1,000 triangles; a few touch each other or the outline).
  EXPECT_GE(s.BoundaryLoops, 1 + s.Triangles / 2000);
  EXPECT_LT(s.EulerCharacteristic, 0);
  EXPECT_EQ(s.NonManifoldEdges, 0); // a height field: at most two triangles on an edge
  EXPECT_EQ(s.DegenerateTriangles, 0);
  // Every point is on the documented relief within the noise (0.15 grid spacing).
  const double h = 2.0 / (resolution - 1);
  double worst = 0;
  for (vtkIdType i = 0; i < scan->GetNumberOfPoints(); ++i)
  {
    double p[3];
    scan->GetPoint(i, p);
    worst = std::max(worst, std::abs(p[2] - vtkScanSurfaceSource::OpenScanHeight(p[0], p[1])));
  }
  EXPECT_LE(worst, 0.15 * h + 1e-6);
}
