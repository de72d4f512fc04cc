// SPDX-License-Identifier: BSD-3-Clause
#include "BenchInputs.h"

#include "CliSupport.h"
#include "MeshIO.h"

#include "vtkNew.h"
#include "vtkScanSurfaceSource.h"
#include "vtkSyntheticIsosurfaceSource.h"

#include <cstdlib>
#include <filesystem>

namespace slodcli
{
namespace
{
// Resolutions giving about 0.25M, 1M and 4M triangles (the counts are in
// Documentation/Benchmarks.md; the noisy isosurface has about 13.4 Resolution^2 triangles).
constexpr int NoisyResolutionQuarterMillion = 137;
constexpr int NoisyResolutionMillion = 273;
constexpr int NoisyResolutionFourMillion = 546;
constexpr int MaskResolutionMillion = 472;
constexpr int OpenScanResolutionMillion = 913;

struct Generator
{
  const char* Prefix; // "noisy:" ...
  int Kind;           // vtkScanSurfaceSource kind, or -1 for vtkSyntheticIsosurfaceSource
  int MaximumResolution;
};

const Generator Generators[] = {
  { "synthetic:", -1, 4000 },
  { "noisy:", vtkScanSurfaceSource::NoisyIsosurface, 2000 },
  { "mask:", vtkScanSurfaceSource::SegmentationMask, 2000 },
  { "openscan:", vtkScanSurfaceSource::OpenScan, 2000 },
};

vtkSmartPointer<vtkPolyData> MakeScanSurface(int kind, int resolution)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(kind);
  source->SetResolution(resolution);
  {
    ProgressBar progress(source, "generating input");
    source->Update();
  }
  vtkSmartPointer<vtkPolyData> mesh = source->GetOutput();
  return mesh;
}

// The resolution of "prefix:N", validated.
int GeneratorResolution(const std::string& name, const Generator& generator)
{
  const std::string value = name.substr(std::string(generator.Prefix).size());
  char* end = nullptr;
  const long resolution = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || resolution < 16 || resolution > generator.MaximumResolution)
  {
    throw CliError(ExitUsage, "surfacelod bench: bad input '" + name + "' (" + generator.Prefix + "<resolution 16.." +
        std::to_string(generator.MaximumResolution) + ">)");
  }
  return static_cast<int>(resolution);
}
} // namespace

vtkSmartPointer<vtkPolyData> MakeSyntheticSurface(int resolution, double* seconds)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  {
    ProgressBar progress(source, "synthetic surface");
    Stopwatch watch;
    source->Update();
    if (seconds)
    {
      *seconds = watch.Seconds();
    }
  }
  vtkSmartPointer<vtkPolyData> mesh = source->GetOutput();
  return mesh;
}

vtkSmartPointer<vtkPolyData> ResolveBenchInput(const std::string& name, const std::string& meshDir)
{
  for (const Generator& generator : Generators)
  {
    if (name.compare(0, std::string(generator.Prefix).size(), generator.Prefix) == 0)
    {
      const int resolution = GeneratorResolution(name, generator);
      return generator.Kind < 0 ? MakeSyntheticSurface(resolution) : MakeScanSurface(generator.Kind, resolution);
    }
  }
  std::error_code ec;
  if (std::filesystem::exists(name, ec) || name.find('/') != std::string::npos || name.find('.') != std::string::npos)
  {
    return TriangulatedSurface(ReadMesh(name));
  }
  if (meshDir.empty())
  {
    throw CliError(ExitUsage, "surfacelod bench: '" + name + "' is not a file; give --mesh-dir to look it up");
  }
  return TriangulatedSurface(ReadMesh(meshDir + "/" + name + ".off"));
}

std::string GeneratedInputHelp()
{
  return "synthetic:N (the demo's smooth closed surface, vtkSyntheticIsosurfaceSource), and the scan-like\n"
         "surfaces of vtkScanSurfaceSource: noisy:N (noisy MRI-like isosurface: thousands of handles, border\n"
         "loops, non-manifold edges), mask:N (segmentation-mask staircase), openscan:N (open height-field\n"
         "scan with holes); N is the resolution";
}

std::vector<std::string> RealInputSet()
{
  return { "noisy:" + std::to_string(NoisyResolutionMillion), "mask:" + std::to_string(MaskResolutionMillion),
    "openscan:" + std::to_string(OpenScanResolutionMillion) };
}

std::vector<std::string> ScalingInputSet(const std::vector<std::string>& resolutions)
{
  if (resolutions.empty())
  {
    return { "noisy:" + std::to_string(NoisyResolutionQuarterMillion), "noisy:" + std::to_string(NoisyResolutionMillion),
      "noisy:" + std::to_string(NoisyResolutionFourMillion) };
  }
  if (resolutions.size() != 3)
  {
    throw CliError(ExitUsage, "surfacelod bench: --scaling-resolutions takes three resolutions (small, middle, large)");
  }
  std::vector<std::string> names;
  for (const std::string& r : resolutions)
  {
    names.push_back("noisy:" + r); // validated when the input is generated
  }
  return names;
}

std::string DefaultScalingResolutions()
{
  return std::to_string(NoisyResolutionQuarterMillion) + "," + std::to_string(NoisyResolutionMillion) + "," +
    std::to_string(NoisyResolutionFourMillion);
}
} // namespace slodcli
