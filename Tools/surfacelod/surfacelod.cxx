// surfacelod: command-line front end of the SurfaceLOD filters.
//
//   surfacelod simplify INPUT OUTPUT --method NAME (--target-triangles N | --target-reduction R)
//   surfacelod compare A B           surfacelod info FILE
//   surfacelod demo                  surfacelod bench            surfacelod methods
//
// Exit codes: 0 success, 1 wrong usage, 2 unusable file (missing, unsupported, malformed,
// unwritable), 3 a filter failed. Every failure is one line on stderr.
#include "CliSupport.h"
#include "MeshIO.h"
#include "Methods.h"
#include "Render.h"

#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "vtkSurfaceDeviation.h"
#include "vtkSyntheticIsosurfaceSource.h"

#include "vtkErrorCode.h"
#include "vtkNew.h"
#include "vtkVersion.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>

#ifndef SURFACELOD_VERSION
#define SURFACELOD_VERSION "unknown"
#endif
#ifndef SURFACELOD_DEFAULT_MESH_DIR
#define SURFACELOD_DEFAULT_MESH_DIR ""
#endif

using namespace slodcli;

namespace
{
constexpr long long MaxCount = std::numeric_limits<int>::max();

// ---------------------------------------------------------------------------------------------
// Shared stages

struct RunResult
{
  vtkSmartPointer<vtkPolyData> Output;
  double Seconds = 0.0;
};

// The input every SurfaceLOD filter works on (coincident points merged, triangles with a repeated
// vertex and duplicates removed, orientation made consistent), with its point data, for a filter
// that takes its input as it is; its warnings and errors are reported on `filter`.
vtkSmartPointer<vtkPolyData> PreparedInput(vtkPolyDataAlgorithm* filter, vtkPolyData* triangles)
{
  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput;
  auto prepared = vtkSmartPointer<vtkPolyData>::New();
  if (slod::PrepareFilterInput(filter, triangles, slod::PreparationOptions(), mesh, vertexToInput))
  {
    slod::MeshToPolyData(mesh, prepared);
    std::vector<slod::Index> everyVertex(static_cast<size_t>(mesh.NumberOfPoints()));
    std::iota(everyVertex.begin(), everyVertex.end(), 0);
    slod::StoreUsedPoints(triangles, mesh, everyVertex, vertexToInput, false, prepared);
  }
  return prepared;
}

// Runs one method on a triangle mesh; times the filter's Update() alone.
RunResult RunMethod(const Method& method, vtkPolyData* triangles, const MethodSettings& settings)
{
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = method.Create(settings);
  RunResult result;
  std::string error;
  {
    MessageCapture capture(/*swallowWarnings=*/false);
    filter->SetInputData(method.PreparesItsInput ? vtkSmartPointer<vtkPolyData>(triangles) : PreparedInput(filter, triangles));
    ProgressBar progress(filter, method.Name);
    Stopwatch watch;
    filter->Update();
    result.Seconds = watch.Seconds();
    error = capture.FirstError();
  }
  result.Output = vtkSmartPointer<vtkPolyData>::New();
  result.Output->ShallowCopy(filter->GetOutput());
  if (!error.empty() || (result.Output->GetNumberOfPolys() == 0 && triangles->GetNumberOfPolys() > 0))
  {
    throw CliError(ExitFailure,
      std::string(method.Name) + " failed: " + (error.empty() ? std::string("empty output") : error));
  }
  return result;
}

struct Deviation
{
  double Hausdorff = 0, HausdorffAB = 0, HausdorffBA = 0, Mean = 0, RMS = 0; // relative to A's diagonal
};

// quiet: drop the deviation filter's warnings about its inputs (demo and bench tables; `compare`
// shows them, they describe the user's files).
Deviation MeasureDeviation(vtkPolyData* reference, vtkPolyData* compared, vtkIdType samples, bool quiet)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(compared);
  if (samples >= 0)
  {
    deviation->SetNumberOfSamples(samples);
  }
  std::string error;
  {
    MessageCapture capture(quiet);
    ProgressBar progress(deviation, "deviation");
    deviation->Update();
    error = capture.FirstError();
  }
  if (!error.empty())
  {
    throw CliError(ExitFailure, "surface deviation failed: " + error);
  }
  Deviation d;
  d.Hausdorff = deviation->GetHausdorffRelative();
  d.HausdorffAB = deviation->GetHausdorffABRelative();
  d.HausdorffBA = deviation->GetHausdorffBARelative();
  d.Mean = deviation->GetMeanRelative();
  d.RMS = deviation->GetRMSRelative();
  return d;
}

vtkSmartPointer<vtkPolyData> MakeSyntheticSurface(int resolution, double* seconds = nullptr)
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

// Settings from --target-triangles / --target-reduction / --max-error.
MethodSettings TargetSettings(const ParsedArguments& args, vtkIdType inputTriangles, bool required,
  double defaultReduction)
{
  MethodSettings settings;
  settings.InputTriangles = inputTriangles;
  const bool byCount = args.Has("target-triangles");
  const bool byReduction = args.Has("target-reduction");
  const bool byLevel = args.Has("level");
  if (int(byCount) + int(byReduction) + int(byLevel) > 1)
  {
    throw CliError(ExitUsage, "surfacelod " + args.Command + ": give one of --target-triangles, --target-reduction, --level");
  }
  const bool byError = args.Has("max-error");
  if (!byCount && !byReduction && !byLevel && !byError && required)
  {
    throw CliError(ExitUsage, "surfacelod " + args.Command + ": give --target-triangles N, --target-reduction R or --max-error E");
  }
  if (byLevel)
  {
    settings.Level = args.GetReal("level", 0.0, 0.0, std::numeric_limits<double>::max());
  }
  else if (byCount)
  {
    settings.TargetTriangles = args.GetInteger("target-triangles", 0, 1, std::numeric_limits<long long>::max());
  }
  else if (byReduction || !byError)
  {
    settings.TargetReduction = args.GetReal("target-reduction", defaultReduction, 0.0, 1.0);
  }
  else
  {
    settings.TargetReduction = 1.0; // --max-error alone: simplify until the error bound stops it
  }
  if (args.Has("max-error"))
  {
    settings.HasMaximumError = true;
    settings.MaximumError = args.GetReal("max-error", 0.0, 0.0, std::numeric_limits<double>::max());
  }
  return settings;
}

std::vector<const Method*> SelectMethods(const ParsedArguments& args)
{
  std::vector<const Method*> selected;
  if (!args.Has("methods"))
  {
    for (const Method& m : Methods())
    {
      if (m.InDefaultRuns)
      {
        selected.push_back(&m);
      }
    }
    return selected;
  }
  for (const std::string& name : SplitList(args.Get("methods")))
  {
    const Method* m = FindMethod(name);
    if (!m)
    {
      throw CliError(ExitUsage, "surfacelod " + args.Command + ": unknown method '" + name + "' (known: " + MethodNames() + ")");
    }
    selected.push_back(m);
  }
  return selected;
}

std::string Padded(const std::string& text, size_t width, bool right = false)
{
  if (text.size() >= width)
  {
    return text;
  }
  const std::string pad(width - text.size(), ' ');
  return right ? pad + text : text + pad;
}

std::string Fixed(double value, int decimals)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::string Scientific(double value)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.3e", value);
  return buffer;
}

// ---------------------------------------------------------------------------------------------
// simplify

CommandSpec SimplifySpec()
{
  return { "simplify", "INPUT OUTPUT --method NAME (--target-triangles N | --target-reduction R) [options]",
    "Simplify the surface in INPUT and write it to OUTPUT.\n"
    "Readable: " + ReadableExtensions() + "; writable: " + WritableExtensions() + " (chosen by extension).\n"
    "Polygons and strips are triangulated first. Methods: " + MethodNames() + "\n"
    "(`surfacelod methods` describes them).",
    { "INPUT", "OUTPUT" },
    { { "method", "NAME", "simplification method (required)" },
      { "target-triangles", "N", "number of triangles to keep" },
      { "target-reduction", "R", "fraction of the triangles to remove, 0..1 (0.9 keeps 10%)" },
      { "max-error", "E", "stop before the surface moves more than E (absolute, mesh units)" },
      { "level", "L", "level i+t of a hierarchy method (triangle-collapse-hierarchy): M_i blended by t" },
      { "json", "", "print one JSON line: method, input_triangles, output_triangles, seconds, peak_rss_mb" } } };
}

int Simplify(const ParsedArguments& args)
{
  const std::string& inputPath = args.Positionals[0];
  const std::string& outputPath = args.Positionals[1];
  if (!args.Has("method"))
  {
    throw CliError(ExitUsage, "surfacelod simplify: --method NAME is required (known: " + MethodNames() + ")");
  }
  const Method* method = FindMethod(args.Get("method"));
  if (!method)
  {
    throw CliError(ExitUsage, "surfacelod simplify: unknown method '" + args.Get("method") + "' (known: " + MethodNames() + ")");
  }
  if (args.Has("max-error") && !method->SupportsMaximumError)
  {
    throw CliError(ExitUsage, std::string("surfacelod simplify: method ") + method->Name + " does not support --max-error");
  }
  if (args.Has("level") && !method->SupportsLevel)
  {
    throw CliError(ExitUsage, std::string("surfacelod simplify: method ") + method->Name + " has no levels (--level)");
  }
  TargetSettings(args, 0, true, 0.0); // validate the options before reading a large file
  CheckWritablePath(outputPath);

  vtkSmartPointer<vtkPolyData> input = TriangulatedSurface(ReadMesh(inputPath));
  const MethodSettings settings = TargetSettings(args, CountTriangles(input), true, 0.0);
  const RunResult result = RunMethod(*method, input, settings);
  WriteMesh(result.Output, outputPath);

  const vtkIdType outputTriangles = result.Output->GetNumberOfPolys();
  if (args.Has("json"))
  {
    JsonLine()
      .Add("method", method->Name)
      .Add("input_triangles", static_cast<long long>(settings.InputTriangles))
      .Add("output_triangles", static_cast<long long>(outputTriangles))
      .Add("seconds", result.Seconds)
      .Add("peak_rss_mb", PeakResidentMegabytes())
      .Print();
  }
  else
  {
    std::cout << method->Name << ": " << settings.InputTriangles << " -> " << outputTriangles << " triangles in "
              << Fixed(result.Seconds, 3) << " s (peak RSS " << Fixed(PeakResidentMegabytes(), 1)
              << " MB), wrote " << outputPath << "\n";
  }
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// compare

CommandSpec CompareSpec()
{
  return { "compare", "A B [--samples N] [--json]",
    "Two-sided distance between surface A (reference) and surface B, with vtkSurfaceDeviation:\n"
    "all vertices plus N random area-weighted samples on each surface. Results are relative to the\n"
    "bounding-box diagonal of A: hausdorff (symmetric), hausdorff_ab (A's samples to B),\n"
    "hausdorff_ba, mean and rms (averages of both sides).",
    { "A", "B" },
    { { "samples", "N", "random samples per surface (default 300000)" },
      { "json", "", "print one JSON line" } } };
}

int Compare(const ParsedArguments& args)
{
  const vtkIdType samples = args.GetInteger("samples", -1, 0, MaxCount);
  vtkSmartPointer<vtkPolyData> a = TriangulatedSurface(ReadMesh(args.Positionals[0]));
  vtkSmartPointer<vtkPolyData> b = TriangulatedSurface(ReadMesh(args.Positionals[1]));
  const Deviation d = MeasureDeviation(a, b, samples, false);
  if (args.Has("json"))
  {
    JsonLine()
      .Add("hausdorff", d.Hausdorff)
      .Add("hausdorff_ab", d.HausdorffAB)
      .Add("hausdorff_ba", d.HausdorffBA)
      .Add("mean", d.Mean)
      .Add("rms", d.RMS)
      .Print();
  }
  else
  {
    std::cout << "relative to the bounding-box diagonal of " << args.Positionals[0] << ":\n"
              << "  hausdorff    " << Scientific(d.Hausdorff) << "\n"
              << "  hausdorff_ab " << Scientific(d.HausdorffAB) << "  (A to B)\n"
              << "  hausdorff_ba " << Scientific(d.HausdorffBA) << "  (B to A)\n"
              << "  mean         " << Scientific(d.Mean) << "\n"
              << "  rms          " << Scientific(d.RMS) << "\n";
  }
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// info

CommandSpec InfoSpec()
{
  return { "info", "FILE [--json]",
    "Topology of the surface in FILE, as read, with exactly coincident points merged (so that STL\n"
    "and OFF triangle soups count correctly); polygons are triangulated, nothing else is changed.\n"
    "genus is -1 (\"undefined\") unless the surface is an orientable manifold.",
    { "FILE" }, { { "json", "", "print one JSON line" } } };
}

int Info(const ParsedArguments& args)
{
  const std::string& path = args.Positionals[0];
  vtkSmartPointer<vtkPolyData> input = ReadMesh(path);
  slod::PreparationOptions options;
  options.MergeDuplicatePoints = true;
  options.RemoveDegenerateTriangles = false;
  options.RemoveDuplicateTriangles = false;
  options.MakeOrientationConsistent = false;
  slod::TriangleMesh mesh;
  std::vector<slod::Index> origin;
  const slod::PreparationReport report = slod::PrepareTriangleMesh(input, options, mesh, origin);
  if (!report.Valid)
  {
    throw CliError(ExitData, path + ": " + report.Error);
  }
  const slod::MeshStatistics s = slod::ComputeMeshStatistics(mesh);
  if (args.Has("json"))
  {
    JsonLine()
      .Add("file", path)
      .Add("vertices", static_cast<long long>(s.Vertices))
      .Add("triangles", static_cast<long long>(s.Triangles))
      .Add("edges", static_cast<long long>(s.Edges))
      .Add("boundary_edges", static_cast<long long>(s.BoundaryEdges))
      .Add("boundary_loops", static_cast<long long>(s.BoundaryLoops))
      .Add("nonmanifold_edges", static_cast<long long>(s.NonManifoldEdges))
      .Add("nonmanifold_vertices", static_cast<long long>(s.NonManifoldVertices))
      .Add("components", static_cast<long long>(s.Components))
      .Add("euler_characteristic", s.EulerCharacteristic)
      .Add("genus", s.Genus)
      .Add("degenerate_triangles", static_cast<long long>(s.DegenerateTriangles))
      .Add("inconsistently_oriented_edges", static_cast<long long>(s.InconsistentlyOrientedEdges))
      .Add("merged_points", report.MergedPoints)
      .Print();
  }
  else
  {
    std::cout << path << "\n"
              << "  vertices              " << s.Vertices << "\n"
              << "  triangles             " << s.Triangles << "\n"
              << "  edges                 " << s.Edges << "\n"
              << "  boundary edges        " << s.BoundaryEdges << " (" << s.BoundaryLoops << " loops)\n"
              << "  non-manifold edges    " << s.NonManifoldEdges << "\n"
              << "  non-manifold vertices " << s.NonManifoldVertices << "\n"
              << "  components            " << s.Components << "\n"
              << "  Euler characteristic  " << s.EulerCharacteristic << "\n"
              << "  genus                 " << (s.Genus >= 0 ? std::to_string(s.Genus) : std::string("undefined")) << "\n"
              << "  degenerate triangles  " << s.DegenerateTriangles << "\n"
              << "  misoriented edges     " << s.InconsistentlyOrientedEdges << "\n"
              << "  merged points         " << report.MergedPoints << "\n";
  }
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// demo

CommandSpec DemoSpec()
{
  return { "demo", "[--resolution N] [--output-dir DIR] [--target-reduction R]",
    "Generate the synthetic test surface (vtkSyntheticIsosurfaceSource: a rippled ring of Gaussian\n"
    "blobs, genus 1, about 1,000,000 triangles at the default resolution 500), simplify it with every\n"
    "method (those marked in `surfacelod methods` only when named in --methods), print a table (time, symmetric Hausdorff and RMS distance relative to the bounding-box\n"
    "diagonal), write each mesh as DIR/<method>.vtp and a side-by-side picture DIR/demo.png\n"
    "(needs an X display; run under `xvfb-run -a` on a headless machine).",
    {},
    { { "resolution", "N", "samples per axis of the synthetic field (default 500)" },
      { "output-dir", "DIR", "where meshes and the picture go (default ./surfacelod-demo)" },
      { "target-reduction", "R", "fraction of the triangles to remove (default 0.9: keep 10%)" },
      { "methods", "A,B,...", "methods to run (default: all)" },
      { "samples", "N", "deviation samples per surface (default 300000)" } } };
}

int Demo(const ParsedArguments& args)
{
  const int resolution = static_cast<int>(args.GetInteger("resolution", 500, 16, 4000));
  const double reduction = args.GetReal("target-reduction", 0.9, 0.0, 1.0);
  const vtkIdType samples = args.GetInteger("samples", -1, 0, MaxCount);
  const std::string outputDir = args.Get("output-dir", "surfacelod-demo");
  const std::vector<const Method*> methods = SelectMethods(args);
  std::error_code ec;
  std::filesystem::create_directories(outputDir, ec);
  if (ec || !std::filesystem::is_directory(outputDir))
  {
    throw CliError(ExitData, outputDir + ": cannot create the output directory (" + ec.message() + ")");
  }

  double generationSeconds = 0.0;
  vtkSmartPointer<vtkPolyData> input = MakeSyntheticSurface(resolution, &generationSeconds);
  const vtkIdType inputTriangles = input->GetNumberOfPolys();
  std::cout << "synthetic isosurface, resolution " << resolution << ": " << inputTriangles << " triangles, "
            << input->GetNumberOfPoints() << " vertices (" << Fixed(generationSeconds, 2) << " s)\n";
  const std::string inputPath = outputDir + "/synthetic.vtp";
  WriteMesh(input, inputPath);

  MethodSettings settings;
  settings.InputTriangles = inputTriangles;
  settings.TargetReduction = reduction;

  std::cout << "target: remove " << Fixed(100.0 * reduction, 1) << "% of the triangles\n\n"
            << Padded("method", 28) << Padded("triangles", 11, true) << Padded("seconds", 10, true)
            << Padded("hausdorff", 12, true) << Padded("rms", 12, true) << "\n";
  std::vector<Panel> panels;
  std::vector<vtkSmartPointer<vtkPolyData>> outputs;
  panels.push_back({ input, "input\n" + std::to_string(inputTriangles) + " triangles" });
  for (const Method* method : methods)
  {
    const RunResult result = RunMethod(*method, input, settings);
    const Deviation d = MeasureDeviation(input, result.Output, samples, true);
    const vtkIdType triangles = result.Output->GetNumberOfPolys();
    std::cout << Padded(method->Name, 28) << Padded(std::to_string(triangles), 11, true)
              << Padded(Fixed(result.Seconds, 3), 10, true) << Padded(Scientific(d.Hausdorff), 12, true)
              << Padded(Scientific(d.RMS), 12, true) << std::endl;
    WriteMesh(result.Output, outputDir + "/" + method->Name + ".vtp");
    outputs.push_back(result.Output);
    panels.push_back({ result.Output, std::string(method->Name) + "\n" + std::to_string(triangles) +
        " triangles, " + Fixed(result.Seconds, 2) + " s\nHausdorff " + Scientific(d.Hausdorff) });
  }
  std::cout << "\n(hausdorff, rms: relative to the bounding-box diagonal; seconds: filter only)\n"
            << "meshes written to " << outputDir << "/\n";

  std::string reason;
  if (!CanRender(reason))
  {
    std::cerr << "surfacelod demo: " << reason << "; skipping the picture (run under `xvfb-run -a` to get it)\n";
    return ExitSuccess;
  }
  const std::string pngPath = outputDir + "/demo.png";
  RenderPanels(panels, pngPath);
  std::cout << "picture: " << pngPath << "\n";
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// bench

CommandSpec BenchSpec()
{
  return { "bench", "[--inputs a,b,...] [--target-reduction R] [--methods a,b,...] [--repeat N] [--json]",
    "Time methods on named inputs. An input is synthetic:<resolution> (vtkSyntheticIsosurfaceSource),\n"
    "a mesh file path, or the name of a CGAL demo mesh (e.g. fandisk) looked up as <name>.off in\n"
    "--mesh-dir. The baseline " + std::string(BaselineMethod) + " always runs; speedup = its time /\n"
    "the method's time, measured in the same run. Time is the minimum over --repeat runs of the\n"
    "filter alone; hausdorff and rms are relative to the input's bounding-box diagonal.",
    {},
    { { "inputs", "a,b,...", "inputs (default synthetic:500)" },
      { "target-reduction", "R", "fraction of the triangles to remove (default 0.9)" },
      { "target-triangles", "N", "number of triangles to keep (instead of --target-reduction)" },
      { "methods", "a,b,...", "methods to run (default: all)" },
      { "repeat", "N", "runs per method, the fastest counts (default 1)" },
      { "mesh-dir", "DIR", "where named meshes are (default $SURFACELOD_MESH_DIR or the build's TestData)" },
      { "samples", "N", "deviation samples per surface (default 300000)" },
      { "no-deviation", "", "skip the Hausdorff/RMS measurement" },
      { "json", "", "one JSON line per input and method" } } };
}

vtkSmartPointer<vtkPolyData> ResolveBenchInput(const std::string& name, const std::string& meshDir)
{
  const std::string prefix = "synthetic:";
  if (name.compare(0, prefix.size(), prefix) == 0)
  {
    const std::string value = name.substr(prefix.size());
    char* end = nullptr;
    const long resolution = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || resolution < 16 || resolution > 4000)
    {
      throw CliError(ExitUsage, "surfacelod bench: bad input '" + name + "' (synthetic:<resolution 16..4000>)");
    }
    return MakeSyntheticSurface(static_cast<int>(resolution));
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

int Bench(const ParsedArguments& args)
{
  const std::vector<std::string> inputs = SplitList(args.Get("inputs", "synthetic:500"));
  const int repeat = static_cast<int>(args.GetInteger("repeat", 1, 1, 1000));
  const vtkIdType samples = args.GetInteger("samples", -1, 0, MaxCount);
  const bool deviation = !args.Has("no-deviation");
  const bool json = args.Has("json");
  std::string meshDir = args.Get("mesh-dir");
  if (meshDir.empty() && std::getenv("SURFACELOD_MESH_DIR"))
  {
    meshDir = std::getenv("SURFACELOD_MESH_DIR");
  }
  if (meshDir.empty())
  {
    meshDir = SURFACELOD_DEFAULT_MESH_DIR;
  }
  std::vector<const Method*> methods = SelectMethods(args);
  // The baseline runs first so every ratio is measured in the same run.
  const Method* baseline = FindMethod(BaselineMethod);
  methods.erase(std::remove(methods.begin(), methods.end(), baseline), methods.end());
  methods.insert(methods.begin(), baseline);
  TargetSettings(args, 0, false, 0.9); // validate before the work starts

  if (!json)
  {
    std::cout << Padded("input", 20) << Padded("method", 28) << Padded("in", 10, true) << Padded("out", 10, true)
              << Padded("seconds", 10, true) << Padded("speedup", 9, true) << Padded("hausdorff", 12, true)
              << Padded("rms", 12, true) << "\n";
  }
  for (const std::string& name : inputs)
  {
    vtkSmartPointer<vtkPolyData> input = ResolveBenchInput(name, meshDir);
    const MethodSettings settings = TargetSettings(args, CountTriangles(input), false, 0.9);
    double baselineSeconds = 0.0;
    for (const Method* method : methods)
    {
      RunResult best;
      for (int r = 0; r < repeat; ++r)
      {
        RunResult run = RunMethod(*method, input, settings);
        if (r == 0 || run.Seconds < best.Seconds)
        {
          best = run;
        }
      }
      if (method == baseline)
      {
        baselineSeconds = best.Seconds;
      }
      const double speedup = best.Seconds > 0 ? baselineSeconds / best.Seconds : 0.0;
      Deviation d;
      if (deviation)
      {
        d = MeasureDeviation(input, best.Output, samples, true);
      }
      const vtkIdType outTriangles = best.Output->GetNumberOfPolys();
      if (json)
      {
        JsonLine line;
        line.Add("input", name)
          .Add("method", method->Name)
          .Add("input_triangles", static_cast<long long>(settings.InputTriangles))
          .Add("output_triangles", static_cast<long long>(outTriangles))
          .Add("seconds", best.Seconds)
          .Add("baseline_seconds", baselineSeconds)
          .Add("speedup_vs_vtk_quadric", speedup);
        if (deviation)
        {
          line.Add("hausdorff", d.Hausdorff).Add("rms", d.RMS);
        }
        else
        {
          line.AddNull("hausdorff").AddNull("rms");
        }
        line.Add("peak_rss_mb", PeakResidentMegabytes()).Print();
      }
      else
      {
        std::cout << Padded(name, 20) << Padded(method->Name, 28)
                  << Padded(std::to_string(settings.InputTriangles), 10, true)
                  << Padded(std::to_string(outTriangles), 10, true) << Padded(Fixed(best.Seconds, 3), 10, true)
                  << Padded(Fixed(speedup, 2) + "x", 9, true)
                  << Padded(deviation ? Scientific(d.Hausdorff) : "-", 12, true)
                  << Padded(deviation ? Scientific(d.RMS) : "-", 12, true) << std::endl;
      }
    }
  }
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// methods, help, dispatch

CommandSpec MethodsSpec()
{
  return { "methods", "", "List the simplification methods.", {}, {} };
}

int ListMethods(const ParsedArguments&)
{
  for (const Method& m : Methods())
  {
    std::cout << Padded(m.Name, 30) << m.Description << (m.SupportsMaximumError ? "" : " [no --max-error]")
              << (m.InDefaultRuns ? "" : " [demo/bench only with --methods]") << "\n";
  }
  return ExitSuccess;
}

struct Command
{
  CommandSpec (*Spec)();
  int (*Run)(const ParsedArguments&);
  const char* Summary;
};

const std::vector<Command>& Commands()
{
  static const std::vector<Command> commands = {
    { &SimplifySpec, &Simplify, "simplify a mesh file with a chosen method and target" },
    { &CompareSpec, &Compare, "Hausdorff / mean / RMS distance between two surfaces" },
    { &InfoSpec, &Info, "vertices, triangles, boundary, manifoldness, components, genus of a mesh" },
    { &DemoSpec, &Demo, "simplify a synthetic 1M-triangle surface with every method, table + picture" },
    { &BenchSpec, &Bench, "time methods against vtkQuadricDecimation on named inputs" },
    { &MethodsSpec, &ListMethods, "list the simplification methods" },
  };
  return commands;
}

void PrintUsage(std::ostream& out)
{
  out << "usage: surfacelod COMMAND [ARGS] (surfacelod COMMAND --help for details)\n\ncommands:\n";
  for (const Command& c : Commands())
  {
    out << "  " << Padded(c.Spec().Name, 10) << c.Summary << "\n";
  }
  out << "\nexit codes: 0 success, 1 wrong usage, 2 unusable file, 3 a filter failed\n";
}
} // namespace

int main(int argc, char* argv[])
{
  InstallMessageHandler();
  if (argc < 2)
  {
    PrintUsage(std::cerr);
    return ExitUsage;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help")
  {
    PrintUsage(std::cout);
    return ExitSuccess;
  }
  if (name == "--version")
  {
    std::cout << "surfacelod " << SURFACELOD_VERSION << " (VTK " << vtkVersion::GetVTKVersion() << ")\n";
    return ExitSuccess;
  }
  try
  {
    for (const Command& command : Commands())
    {
      const CommandSpec spec = command.Spec();
      if (spec.Name == name)
      {
        ParsedArguments args;
        if (!ParseArguments(spec, argc, argv, 2, args))
        {
          return ExitSuccess; // --help
        }
        return command.Run(args);
      }
    }
    std::cerr << "surfacelod: unknown command '" << name << "'\n";
    PrintUsage(std::cerr);
    return ExitUsage;
  }
  catch (const CliError& e)
  {
    std::cout.flush();
    std::cerr << (std::string(e.what()).compare(0, 11, "surfacelod ") == 0 ? "" : "surfacelod: ") << e.what()
              << std::endl;
    return e.Code;
  }
  catch (const std::exception& e)
  {
    std::cerr << "surfacelod: " << e.what() << std::endl;
    return ExitFailure;
  }
}
