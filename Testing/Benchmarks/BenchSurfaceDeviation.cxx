// SPDX-License-Identifier: BSD-3-Clause
// Speed of the deviation measurement (a plain timed program, not a test).
//
// A = the demo's marching-cubes surface (vtkSyntheticIsosurfaceSource) with about 1,000,000 triangles,
// B = the same surface extracted on a coarser grid (about 60,000 triangles).
// Reported, wall clock:
//  1. one side as every filter test uses it: TriangleBVH over A (build) + 300,000 area-weighted
//     samples on B measured to A (queries), with the phases;
//  2. vtkSurfaceDeviation(A, B) with its defaults (input preparation, both trees, all vertices +
//     300,000 random samples per side);
//  3. with --vtk: vtkHausdorffDistancePointSetFilter (point-to-cell, vertices only) on the same
//     pair, VTK's own tool for this, for the ratio.
// Usage: BenchSurfaceDeviation [--resolution N] [--samples N] [--threads N] [--vtk] [--write PREFIX]
// (--write saves the pair as PREFIX_A.vtp / PREFIX_B.vtp, e.g. to run meshdist on it.)
#include "slodInputPreparation.h"
#include "slodSurfaceDeviation.h"
#include "slodTriangleBVH.h"
#include "vtkSurfaceDeviation.h"
#include "vtkSyntheticIsosurfaceSource.h"

#include "vtkFloatArray.h"
#include "vtkHausdorffDistancePointSetFilter.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataWriter.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{
double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The demo's marching-cubes surface at a given resolution (500: about 1,000,000 triangles).
vtkSmartPointer<vtkPolyData> Isosurface(int resolution)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}
} // namespace

int main(int argc, char* argv[])
{
  int resolution = 500;
  long long samples = 300000;
  int threads = 0;
  bool runVtk = false;
  std::string writePrefix;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--resolution" && i + 1 < argc)
    {
      resolution = std::atoi(argv[++i]);
    }
    else if (arg == "--samples" && i + 1 < argc)
    {
      samples = std::atoll(argv[++i]);
    }
    else if (arg == "--threads" && i + 1 < argc)
    {
      threads = std::atoi(argv[++i]);
    }
    else if (arg == "--write" && i + 1 < argc)
    {
      writePrefix = argv[++i];
    }
    else if (arg == "--vtk")
    {
      runVtk = true;
    }
    else
    {
      std::fprintf(stderr, "usage: %s [--resolution N] [--samples N] [--threads N] [--vtk] [--write PREFIX]\n", argv[0]);
      return 2;
    }
  }
  if (threads > 0)
  {
    vtkSMPTools::Initialize(threads);
  }
  std::printf("SMP backend %s, %d threads\n", vtkSMPTools::GetBackend(), vtkSMPTools::GetEstimatedNumberOfThreads());

  double t = Now();
  vtkSmartPointer<vtkPolyData> a = Isosurface(resolution);
  vtkSmartPointer<vtkPolyData> b = Isosurface(resolution / 4);
  std::printf("meshes: A %lld triangles, B %lld triangles (generated in %.2f s, untimed)\n",
    static_cast<long long>(a->GetNumberOfPolys()), static_cast<long long>(b->GetNumberOfPolys()), Now() - t);

  if (!writePrefix.empty())
  {
    for (const auto& item : { std::make_pair(std::string("_A.vtp"), a), std::make_pair(std::string("_B.vtp"), b) })
    {
      vtkNew<vtkXMLPolyDataWriter> writer;
      writer->SetFileName((writePrefix + item.first).c_str());
      writer->SetInputData(item.second);
      writer->SetDataModeToBinary();
      writer->Write();
    }
  }

  // 1. One side, core API.
  slod::TriangleMesh meshA, meshB;
  std::vector<slod::Index> map;
  slod::PreparationOptions options;
  options.MakeOrientationConsistent = false;
  t = Now();
  slod::PrepareTriangleMesh(a, options, meshA, map);
  const double tPrepare = Now() - t;
  slod::PrepareTriangleMesh(b, options, meshB, map);

  t = Now();
  const slod::TriangleBVH tree(meshA);
  const double tBuild = Now() - t;
  t = Now();
  std::vector<double> points;
  slod::SampleSurface(meshB, samples, 12345, 0, points);
  const double tSample = Now() - t;
  t = Now();
  std::vector<double> distances;
  slod::ComputeDistances(tree, points, distances);
  const double tQuery = Now() - t;
  double maxDistance = 0;
  for (double d : distances)
  {
    maxDistance = std::max(maxDistance, d);
  }
  std::printf("one side (%lld samples on B to A's tree): build %.3f s (%zu nodes, depth %d) + sampling %.3f s + "
              "queries %.3f s = %.3f s   [max %.6g; A's input preparation %.3f s, not included]\n",
    samples, tBuild, tree.GetNodes().size(), tree.GetDepth(), tSample, tQuery, tBuild + tSample + tQuery,
    maxDistance, tPrepare);

  // 2. The filter, both sides, defaults.
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(a);
  deviation->SetComparedData(b);
  deviation->SetNumberOfSamples(samples);
  t = Now();
  deviation->Update();
  const double tFilter = Now() - t;
  std::printf("vtkSurfaceDeviation (both sides, vertices + %lld samples each): %.3f s   Hausdorff %.6e "
              "(AB %.6e, BA %.6e), RMS %.6e (relative)\n",
    samples, tFilter, deviation->GetHausdorffRelative(), deviation->GetHausdorffABRelative(),
    deviation->GetHausdorffBARelative(), deviation->GetRMSRelative());

  // 3. VTK's point-to-cell Hausdorff filter (vertices only) for the ratio.
  if (runVtk)
  {
    vtkNew<vtkHausdorffDistancePointSetFilter> hausdorff;
    hausdorff->SetInputData(0, a);
    hausdorff->SetInputData(1, b);
    hausdorff->SetTargetDistanceMethodToPointToCell();
    t = Now();
    hausdorff->Update();
    const double tVtk = Now() - t;
    std::printf("vtkHausdorffDistancePointSetFilter (point-to-cell, vertices only): %.3f s   Hausdorff %.6e "
                "(relative)\n",
      tVtk, hausdorff->GetHausdorffDistance() / deviation->GetBoundingBoxDiagonal());
    vtkNew<vtkSurfaceDeviation> verticesOnly;
    verticesOnly->SetReferenceData(a);
    verticesOnly->SetComparedData(b);
    verticesOnly->SetNumberOfSamples(0);
    t = Now();
    verticesOnly->Update();
    const double tOurs = Now() - t;
    std::printf("vtkSurfaceDeviation vertices only: %.3f s   Hausdorff %.6e (relative); speed-up vs VTK x%.1f\n",
      tOurs, verticesOnly->GetHausdorffRelative(), tVtk / tOurs);
  }
  return 0;
}
