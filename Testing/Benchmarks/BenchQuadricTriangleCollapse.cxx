// SPDX-License-Identifier: BSD-3-Clause
// Benchmark (not a test): vtkQuadricTriangleCollapse vs vtkQuadricDecimation, same inputs, same
// run. Reports wall time of the filter update, input triangles per second, the time ratio and the
// peak memory growth per input vertex (VmHWM reset through /proc/self/clear_refs).
//
//   BenchQuadricTriangleCollapse [--mc N] [--runs R] [--threads T] [--write DIR] [--skip-vtk] [--paper]
//     [--batch TOLERANCE] [--passes] [mesh[:target]]...
// Default cases: a ~1M-triangle marching-cubes mesh to 10 %, bunny00 to 2306 triangles (the
// paper's table). With --write DIR the outputs are saved as .vtp for external measurement. With
// --paper the paper's configuration (UsePaperConfiguration) runs too, in the same run; with --batch
// the BatchCollapses mode at that BatchCostTolerance; with --passes the main run uses the pass
// schedule (CollapseSchedule PASSES). A mesh is a CGAL demo name or a .vtp path.
#include "CliSupport.h"
#include "TestSupport.h"
#include "vtkQuadricTriangleCollapse.h"

#include "vtkFlyingEdges3D.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace
{
double CpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Measure
{
  double Seconds = 0; // CPU time of the update (the machine may be shared: wall time is noisier)
  double Wall = 0;
  double BytesPerVertex = 0;
  vtkIdType Triangles = 0;
};

template <typename Filter>
Measure Run(vtkPolyData* input, Filter* filter, int runs, vtkSmartPointer<vtkPolyData>& output)
{
  std::vector<double> times, walls;
  Measure m;
  for (int r = 0; r < runs; ++r)
  {
    filter->SetInputData(input);
    filter->Modified();
    output = nullptr;
    slodcli::ResetPeakResident();
    const double before = slodcli::ResidentMegabytes();
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = CpuSeconds();
    filter->Update();
    const double c1 = CpuSeconds();
    const auto t1 = std::chrono::steady_clock::now();
    const double peak = slodcli::PeakResidentMegabytes();
    walls.push_back(std::chrono::duration<double>(t1 - t0).count());
    times.push_back(c1 - c0);
    m.BytesPerVertex = std::max(m.BytesPerVertex, 1048576.0 * (peak - before) / double(input->GetNumberOfPoints()));
    output = vtkSmartPointer<vtkPolyData>::New();
    output->ShallowCopy(filter->GetOutput());
    filter->SetInputData(nullptr);
    filter->GetOutput()->Initialize();
  }
  std::sort(times.begin(), times.end());
  std::sort(walls.begin(), walls.end());
  // Minimum over the runs: on a shared machine the fastest run is the one least disturbed.
  m.Seconds = times.front();
  m.Wall = walls.front();
  m.Triangles = output->GetNumberOfPolys();
  return m;
}

void Write(vtkPolyData* mesh, const std::string& path)
{
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(mesh);
  writer->SetFileName(path.c_str());
  writer->SetDataModeToBinary();
  writer->Write();
}
} // namespace

int main(int argc, char* argv[])
{
  int mcResolution = 500; // vtkSyntheticIsosurfaceSource: 1,004,688 triangles (the demo mesh)
  int runs = 1;
  bool skipVtk = false, paper = false;
  double batchTolerance = -1.0; // < 0: no batch-mode run
  int schedule = vtkQuadricTriangleCollapse::QUEUE;
  std::string writeDir;
  std::vector<std::string> cases;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--mc" && i + 1 < argc)
    {
      mcResolution = std::atoi(argv[++i]);
    }
    else if (a == "--runs" && i + 1 < argc)
    {
      runs = std::max(1, std::atoi(argv[++i]));
    }
    else if (a == "--write" && i + 1 < argc)
    {
      writeDir = argv[++i];
    }
    else if (a == "--threads" && i + 1 < argc)
    {
      // 1: single-threaded (the speed goal); default: vtkSMPTools' default.
      vtkSMPTools::Initialize(std::atoi(argv[++i]));
    }
    else if (a == "--skip-vtk")
    {
      skipVtk = true;
    }
    else if (a == "--paper")
    {
      paper = true;
    }
    else if (a == "--batch" && i + 1 < argc)
    {
      batchTolerance = std::atof(argv[++i]);
    }
    else if (a == "--passes")
    {
      schedule = vtkQuadricTriangleCollapse::PASSES;
    }
    else
    {
      cases.push_back(a);
    }
  }
  if (cases.empty())
  {
    cases = { "mc:0.1", "bunny00:2306" };
  }

  std::printf("vtkSMPTools threads: %d (CPU s = process CPU time, all threads; wall s = elapsed; minimum of %d run(s))\n\n",
    vtkSMPTools::GetEstimatedNumberOfThreads(), runs);
  std::printf("| case | input tris | target | method | out tris | CPU s | wall s | input Mtris/s (CPU) | peak MB | bytes/vertex |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& c : cases)
  {
    const size_t colon = c.find(':');
    std::string name = c.substr(0, colon);
    vtkSmartPointer<vtkPolyData> input;
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".vtp") == 0)
    {
      vtkNew<vtkXMLPolyDataReader> reader;
      reader->SetFileName(name.c_str());
      reader->Update();
      input = reader->GetOutput();
      name = name.substr(name.find_last_of('/') + 1);
      name = name.substr(0, name.size() - 4);
    }
    const std::string spec = colon == std::string::npos ? "0.1" : c.substr(colon + 1);
    if (!input)
    {
      input = name == "mc" ? slodtest::SyntheticIsosurface(mcResolution) : slodtest::LoadTestMesh(name);
    }
    const vtkIdType n = input->GetNumberOfPolys();
    const double value = std::atof(spec.c_str());
    const vtkIdType target = value < 1.0 ? static_cast<vtkIdType>(std::llround(value * n)) : static_cast<vtkIdType>(value);
    if (!writeDir.empty())
    {
      Write(input, writeDir + "/" + name + ".vtp");
    }

    vtkSmartPointer<vtkPolyData> ours, theirs;
    vtkNew<vtkQuadricTriangleCollapse> collapse;
    collapse->SetTargetNumberOfTriangles(target);
    collapse->SetTargetReduction(0.0);
    collapse->SetCollapseSchedule(schedule);
    const Measure a = Run(input.Get(), collapse.Get(), runs, ours);
    Measure p;
    vtkSmartPointer<vtkPolyData> paperOutput;
    if (paper)
    {
      vtkNew<vtkQuadricTriangleCollapse> published;
      published->UsePaperConfiguration();
      published->SetTargetNumberOfTriangles(target);
      published->SetTargetReduction(0.0);
      p = Run(input.Get(), published.Get(), runs, paperOutput);
    }
    Measure bm;
    vtkSmartPointer<vtkPolyData> batchOutput;
    if (batchTolerance >= 0)
    {
      vtkNew<vtkQuadricTriangleCollapse> batched;
      batched->BatchCollapsesOn();
      batched->SetBatchCostTolerance(batchTolerance);
      batched->SetTargetNumberOfTriangles(target);
      batched->SetTargetReduction(0.0);
      bm = Run(input.Get(), batched.Get(), runs, batchOutput);
    }
    Measure b;
    if (!skipVtk)
    {
      vtkNew<vtkQuadricDecimation> decimation;
      decimation->SetTargetReduction(1.0 - double(target) / double(n));
      b = Run(input.Get(), decimation.Get(), runs, theirs);
    }
    auto row = [&](const char* method, const Measure& m) {
      std::printf("| %s | %lld | %lld | %s | %lld | %.3f | %.3f | %.2f | %.1f | %.0f |\n", name.c_str(), (long long)n,
        (long long)target, method, (long long)m.Triangles, m.Seconds, m.Wall, n / m.Seconds / 1e6,
        m.BytesPerVertex * input->GetNumberOfPoints() / 1048576.0, m.BytesPerVertex);
    };
    row("vtkQuadricTriangleCollapse", a);
    if (paper)
    {
      row("vtkQuadricTriangleCollapse, paper's configuration", p);
    }
    if (batchTolerance >= 0)
    {
      row("vtkQuadricTriangleCollapse, batch collapses", bm);
    }
    if (!skipVtk)
    {
      row("vtkQuadricDecimation", b);
      std::printf("| %s | | | speed-up | | %.2fx | %.2fx | | | |\n", name.c_str(), b.Seconds / a.Seconds, b.Wall / a.Wall);
      if (paper)
      {
        std::printf("| %s | | | speed-up, paper's configuration | | %.2fx | %.2fx | | | |\n", name.c_str(),
          b.Seconds / p.Seconds, b.Wall / p.Wall);
      }
      if (batchTolerance >= 0)
      {
        std::printf("| %s | | | speed-up, batch collapses | | %.2fx | %.2fx | | | |\n", name.c_str(),
          b.Seconds / bm.Seconds, b.Wall / bm.Wall);
      }
    }
    std::fflush(stdout);
    if (!writeDir.empty())
    {
      const std::string stem = writeDir + "/" + name + "_" + std::to_string(target);
      Write(ours, stem + "_qtc.vtp");
      if (batchOutput)
      {
        Write(batchOutput, stem + "_batch.vtp");
      }
      if (theirs)
      {
        Write(theirs, stem + "_vtkquadric.vtp");
      }
    }
  }
  return 0;
}
