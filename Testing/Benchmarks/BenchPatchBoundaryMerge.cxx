// SPDX-License-Identifier: BSD-3-Clause
// Benchmark of vtkPatchBoundaryMerge (SPBM) against vtkQuadricDecimation and vtkDecimatePro,
// measured in the same run (not part of ctest): Table 1 of Ho 1999 (three levels per model,
// patchification and level-generation times separately), whole-filter speed ratios, peak memory
// per vertex and quality at equal triangle count (vtkSurfaceDeviation).
//
// usage: BenchPatchBoundaryMerge [fandisk] [bunny00] [mc1m] [--samples N] [--repeat N] [--write DIR] [--ear-clipping]
// (no model argument: all three). Models are read from the CGAL demo meshes of the build
// (SURFACELOD_MESH_DIR); mc1m is the demo's ~1M-triangle isosurface (vtkSyntheticIsosurfaceSource)
// (a bumpy sphere).
#include "CliSupport.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkOFFMeshReader.h"
#include "vtkSurfaceDeviation.h"

#include "vtkDecimatePro.h"
#include "vtkSyntheticIsosurfaceSource.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The demo's marching-cubes surface (vtkSyntheticIsosurfaceSource; 500: about 1,000,000 triangles).
vtkSmartPointer<vtkPolyData> MarchingCubesMesh(int resolution)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

vtkSmartPointer<vtkPolyData> LoadModel(const std::string& name)
{
  if (name == "mc1m")
  {
    return MarchingCubesMesh(500);
  }
  vtkNew<vtkOFFMeshReader> reader;
  const std::string path = std::string(SURFACELOD_MESH_DIR) + "/" + name + ".off";
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetOutput()->GetNumberOfCells() == 0)
  {
    std::cerr << "cannot read " << path << "\n";
    std::exit(1);
  }
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  return out;
}

struct Quality
{
  double Hausdorff = 0, Mean = 0;
};
Quality Measure(vtkPolyData* reference, vtkPolyData* simplified, vtkIdType samples)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(simplified);
  deviation->SetNumberOfSamples(samples);
  deviation->Update();
  return { deviation->GetHausdorffRelative(), deviation->GetMeanRelative() };
}
} // namespace

int main(int argc, char* argv[])
{
  std::vector<std::string> models;
  vtkIdType samples = 100000;
  int repeat = 3;
  std::string writeDirectory;
  bool earClipping = false; // --ear-clipping: MinimumDeviationTriangulation off (the paper's)
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--ear-clipping"))
    {
      earClipping = true;
      continue;
    }
    if (!std::strcmp(argv[i], "--write") && i + 1 < argc)
    {
      writeDirectory = argv[++i];
      continue;
    }
    if (!std::strcmp(argv[i], "--samples") && i + 1 < argc)
    {
      samples = std::atol(argv[++i]);
    }
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
    {
      repeat = std::max(1, std::atoi(argv[++i]));
    }
    else
    {
      models.emplace_back(argv[i]);
    }
  }
  if (models.empty())
  {
    models = { "fandisk", "bunny00", "mc1m" };
  }
  std::printf("| model | target | SPBM tris | patchify s | level s | SPBM total s | quadric tris | quadric s | "
              "speed-up | decimatepro tris | decimatepro s | H spbm | H quadric | H pro | H ratio spbm/quadric | "
              "mean spbm | mean quadric | mean pro |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& name : models)
  {
    vtkSmartPointer<vtkPolyData> input = LoadModel(name);
    const vtkIdType inputTriangles = input->GetNumberOfCells();
    std::vector<vtkIdType> targets;
    if (name == "fandisk")
    {
      targets = { 460, 266, 150 };
    }
    else if (name == "bunny00")
    {
      targets = { 1500, 1000, 525 };
    }
    else
    {
      targets = { 12700, 7400, 3500 };
    }
    std::fprintf(stderr, "%s: %lld triangles, %lld points\n", name.c_str(), (long long)inputTriangles,
      (long long)input->GetNumberOfPoints());

    // Memory: peak resident growth of the first level (patchification + level) beyond the input.
    double bytesPerVertex = 0;
    {
      slodcli::ResetPeakResident();
      const double before = slodcli::ResidentMegabytes();
      vtkNew<vtkPatchBoundaryMerge> probe;
      probe->SetMinimumDeviationTriangulation(!earClipping);
      probe->SetInputData(input);
      probe->SetTargetNumberOfTriangles(targets[0]);
      probe->Update();
      const double peak = slodcli::PeakResidentMegabytes();
      bytesPerVertex = 1048576.0 * (peak - before) / double(input->GetNumberOfPoints());
      std::fprintf(stderr, "  peak RSS growth %.1f MB = %.0f bytes/vertex; cache held %.1f bytes/vertex\n",
        peak - before, bytesPerVertex, double(probe->GetCacheMemory()) / input->GetNumberOfPoints());
    }

    // One filter for all levels: the first pays the patchification, the others reuse it.
    std::vector<double> spbmTotal(targets.size(), 1e30), patchTime(targets.size(), 0), levelTime(targets.size(), 1e30);
    std::vector<vtkSmartPointer<vtkPolyData>> spbmOut(targets.size());
    for (int r = 0; r < repeat; ++r)
    {
      input->Modified(); // a new input for the cache: the first level recomputes the patches
      vtkNew<vtkPatchBoundaryMerge> filter;
      filter->SetMinimumDeviationTriangulation(!earClipping);
      filter->SetInputData(input);
      for (size_t t = 0; t < targets.size(); ++t)
      {
        filter->SetTargetNumberOfTriangles(targets[t]);
        const auto start = Clock::now();
        filter->Update();
        const double total = Seconds(start);
        if (total < spbmTotal[t])
        {
          spbmTotal[t] = total;
          patchTime[t] = filter->GetPatchificationTime();
          levelTime[t] = filter->GetLevelTime();
        }
        if (r == 0)
        {
          spbmOut[t] = vtkSmartPointer<vtkPolyData>::New();
          spbmOut[t]->DeepCopy(filter->GetOutput());
          std::fprintf(stderr, "  level %lld: %lld triangles, %lld patches (of %lld), epsilon %.3g, alpha1 %.1f, "
                               "fallback patches %lld refined / %lld original\n",
            (long long)targets[t], (long long)filter->GetOutput()->GetNumberOfCells(),
            (long long)filter->GetNumberOfMergedPatches(), (long long)filter->GetNumberOfPatches(),
            filter->GetUsedEpsilon(), filter->GetUsedMergeAngle(), (long long)filter->GetRefinedPatches(),
            (long long)filter->GetOriginalPatches());
        }
      }
    }
    for (size_t t = 0; t < targets.size(); ++t)
    {
      const vtkIdType count = spbmOut[t]->GetNumberOfCells();
      const double reduction = 1.0 - double(count) / double(inputTriangles);
      double quadricTime = 1e30, proTime = 1e30;
      vtkSmartPointer<vtkPolyData> quadricOut, proOut;
      // vtkDecimatePro at equal count: PreserveTopology when it reaches the count (within two
      // triangles), else PreserveTopologyOff + SplittingOn (marked * in the table).
      bool proSplitting = false;
      for (int r = 0; r < repeat; ++r)
      {
        vtkNew<vtkQuadricDecimation> quadric;
        quadric->SetInputData(input);
        quadric->SetTargetReduction(reduction);
        auto start = Clock::now();
        quadric->Update();
        quadricTime = std::min(quadricTime, Seconds(start));
        quadricOut = quadric->GetOutput();
        vtkNew<vtkDecimatePro> pro;
        pro->SetInputData(input);
        pro->SetTargetReduction(reduction);
        pro->PreserveTopologyOn();
        start = Clock::now();
        pro->Update();
        if (pro->GetOutput()->GetNumberOfCells() > count + 2)
        {
          pro->PreserveTopologyOff();
          pro->SplittingOn();
          start = Clock::now();
          pro->Update();
          proSplitting = true;
        }
        proTime = std::min(proTime, Seconds(start));
        proOut = pro->GetOutput();
      }
      // A fresh filter for this level: the first level's patchification + this level.
      const double fresh = spbmTotal[0] - levelTime[0] + levelTime[t];
      if (!writeDirectory.empty())
      {
        auto write = [&](vtkPolyData* pd, const std::string& method) {
          vtkNew<vtkXMLPolyDataWriter> writer;
          writer->SetInputData(pd);
          writer->SetFileName((writeDirectory + "/" + name + "_" + std::to_string(targets[t]) + "_" + method + ".vtp").c_str());
          writer->Write();
        };
        write(input, "input");
        write(spbmOut[t], "spbm");
        write(quadricOut, "quadric");
        write(proOut, "decimatepro");
      }
      const Quality qs = Measure(input, spbmOut[t], samples);
      const Quality qq = Measure(input, quadricOut, samples);
      const Quality qp = Measure(input, proOut, samples);
      std::printf("| %s | %lld | %lld | %.4f | %.4f | %.4f | %lld | %.4f | %.1fx | %lld%s | %.4f | %.3e | %.3e | %.3e | %.2f | "
                  "%.3e | %.3e | %.3e |\n",
        name.c_str(), (long long)targets[t], (long long)count, patchTime[0], levelTime[t], fresh,
        (long long)quadricOut->GetNumberOfCells(), quadricTime, quadricTime / fresh,
        (long long)proOut->GetNumberOfCells(), proSplitting ? "*" : "", proTime,
        qs.Hausdorff, qq.Hausdorff, qp.Hausdorff, qq.Hausdorff > 0 ? qs.Hausdorff / qq.Hausdorff : 0.0, qs.Mean,
        qq.Mean, qp.Mean);
      std::fflush(stdout);
    }
    std::printf("| %s | memory | peak %.0f bytes/vertex beyond the input | | | | | | | | | | | | | | | |\n", name.c_str(),
      bytesPerVertex);
  }
  std::printf("\nSPBM total = whole filter for a fresh input (input preparation + patchification + this level); "
              "speed-up = vtkQuadricDecimation time / SPBM total. A further level from the cached patchification "
              "costs only 'level s'. Times: best of --repeat runs. decimatepro tris with *: PreserveTopologyOff + SplittingOn "
              "(PreserveTopologyOn stops above the count).\n");
  return 0;
}
