// SPDX-License-Identifier: BSD-3-Clause
// Benchmark of vtkTriangleCollapseHierarchy (not a test): the paper's figures on bunny00 and on a
// ~1M-triangle marching-cubes surface. Prints, per mesh and configuration: the number of levels
// needed to get below 5% of the triangles with 2.5% per batch, the levels in all, the hierarchy
// build time, the time of one blended level M_i(t) through the pipeline (the slider path), and
// vtkQuadricDecimation's time to 5% on the same mesh, measured in the same run.
//
// Usage: BenchmarkTriangleCollapseHierarchy [mesh-directory] [demo isosurface resolution (default 500: about 1M triangles)]
#include "vtkSyntheticIsosurfaceSource.h"
#include "vtkNew.h"
#include "vtkOFFMeshReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleCollapseHierarchy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace
{
double Seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The demo's marching-cubes surface (vtkSyntheticIsosurfaceSource; 500: about 1,000,000 triangles).
vtkSmartPointer<vtkPolyData> MarchingCubesSurface(int resolution)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

void Run(const std::string& label, vtkPolyData* mesh, bool paper)
{
  const vtkIdType n0 = mesh->GetNumberOfPolys();
  vtkNew<vtkTriangleCollapseHierarchy> filter;
  filter->SetInputData(mesh);
  filter->GenerateAllLevelsOff();
  if (paper)
  {
    // Gieng et al.: w = 1/3 each, collapse point on the fitted quadratic, the paper's rules only.
    filter->SetErrorWeight(0.0);
    filter->SetQuadricCollapsePoint(false);
    filter->SetRelaxWhenBlocked(false);
    filter->SetMinimumNormalDot(0.2);
    filter->SetBatchSearchDepth(0.0);
    filter->SetStarShapedInStencilPlane(false);
    filter->SetSwapBlockingEdges(false);
    filter->SetEdgeCollapses(vtkTriangleCollapseHierarchy::EDGE_COLLAPSES_OFF);
  }
  filter->SetLevel(0);
  filter->Update();
  const int levels = filter->GetNumberOfLevels();
  int below = -1;
  for (int i = 0; i < levels && below < 0; ++i)
  {
    if (filter->GetLevelNumberOfTriangles(i) < 0.05 * n0)
    {
      below = i;
    }
  }
  // Blend: one M_i(t) per Update, t sweeping the whole hierarchy like a slider.
  const int steps = 200;
  std::vector<double> times;
  for (int s = 0; s < steps; ++s)
  {
    filter->SetContinuousLevel((levels - 1) * (s + 0.5) / steps);
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    times.push_back(Seconds(start));
  }
  std::sort(times.begin(), times.end());
  // The finest levels are the most expensive to blend.
  double worst = 0;
  for (int s = 0; s < 20; ++s)
  {
    filter->SetContinuousLevel(0.05 * s);
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    worst = std::max(worst, Seconds(start));
  }
  std::printf("%-10s %-6s %9lld tris: %3d levels to <5%% (%lld tris), %3d levels, coarsest %lld tris, "
              "build %.2f s, blend median %.2f ms, blend at M0(t) max %.2f ms, %d builds\n",
    label.c_str(), paper ? "paper" : "default", static_cast<long long>(n0), below,
    below >= 0 ? static_cast<long long>(filter->GetLevelNumberOfTriangles(below)) : -1LL, levels,
    static_cast<long long>(filter->GetLevelNumberOfTriangles(levels - 1)), filter->GetHierarchyBuildTime(),
    1e3 * times[times.size() / 2], 1e3 * worst, filter->GetNumberOfHierarchyBuilds());
}

void RunQuadric(const std::string& label, vtkPolyData* mesh)
{
  vtkNew<vtkQuadricDecimation> quadric;
  quadric->SetInputData(mesh);
  quadric->SetTargetReduction(0.95);
  const auto start = std::chrono::steady_clock::now();
  quadric->Update();
  std::printf("%-10s vtkQuadricDecimation to 5%%: %.2f s (%lld tris)\n", label.c_str(), Seconds(start),
    static_cast<long long>(quadric->GetOutput()->GetNumberOfPolys()));
}
} // namespace

int main(int argc, char* argv[])
{
  const std::string dir = argc > 1 ? argv[1] : SURFACELOD_MESH_DIR;
  const int grid = argc > 2 ? std::atoi(argv[2]) : 500;
  vtkNew<vtkOFFMeshReader> reader;
  reader->SetFileName((dir + "/bunny00.off").c_str());
  reader->Update();
  vtkPolyData* bunny = reader->GetOutput();
  if (bunny->GetNumberOfPolys() == 0)
  {
    std::fprintf(stderr, "cannot read %s/bunny00.off\n", dir.c_str());
    return 1;
  }
  Run("bunny00", bunny, true);
  Run("bunny00", bunny, false);
  RunQuadric("bunny00", bunny);

  const auto start = std::chrono::steady_clock::now();
  vtkSmartPointer<vtkPolyData> mc = MarchingCubesSurface(grid);
  std::printf("demo isosurface, resolution %d: %lld triangles in %.2f s\n", grid,
    static_cast<long long>(mc->GetNumberOfPolys()), Seconds(start));
  Run("mc", mc, true);
  Run("mc", mc, false);
  RunQuadric("mc", mc);
  return 0;
}
