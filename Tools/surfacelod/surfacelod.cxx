// surfacelod: command-line front end of the SurfaceLOD filters.
//
//   surfacelod simplify INPUT OUTPUT --method NAME (--target-triangles N | --target-reduction R)
//   surfacelod compare A B           surfacelod info FILE
//   surfacelod demo                  surfacelod bench            surfacelod methods
//
// Exit codes: 0 success, 1 wrong usage, 2 unusable file (missing, unsupported, malformed,
// unwritable), 3 a filter failed. Every failure is one line on stderr.
#include "BenchInputs.h"
#include "ChildProcess.h"
#include "CliSupport.h"
#include "MeshIO.h"
#include "Methods.h"
#include "Render.h"

#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "vtkSurfaceDeviation.h"

#include "vtkErrorCode.h"
#include "vtkNew.h"
#include "vtkVersion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <thread>

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

// Topology of a surface as stored, with exactly coincident points merged (so that STL and OFF
// triangle soups count correctly); nothing else is changed. name: for the error message.
slod::MeshStatistics SurfaceStatistics(vtkPolyData* surface, const std::string& name, long long* mergedPoints = nullptr)
{
  slod::PreparationOptions options;
  options.MergeDuplicatePoints = true;
  options.RemoveDegenerateTriangles = false;
  options.RemoveDuplicateTriangles = false;
  options.MakeOrientationConsistent = false;
  slod::TriangleMesh mesh;
  std::vector<slod::Index> origin;
  const slod::PreparationReport report = slod::PrepareTriangleMesh(surface, options, mesh, origin);
  if (!report.Valid)
  {
    throw CliError(ExitData, name + ": " + report.Error);
  }
  if (mergedPoints)
  {
    *mergedPoints = report.MergedPoints;
  }
  return slod::ComputeMeshStatistics(mesh);
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
  const bool targetReached = TargetReached(result.Output, settings);
  if (args.Has("json"))
  {
    JsonLine()
      .Add("method", method->Name)
      .Add("input_triangles", static_cast<long long>(settings.InputTriangles))
      .Add("output_triangles", static_cast<long long>(outputTriangles))
      .Add("target_reached", targetReached)
      .Add("seconds", result.Seconds)
      .Add("peak_rss_mb", PeakResidentMegabytes())
      .Print();
  }
  else
  {
    std::cout << method->Name << ": " << settings.InputTriangles << " -> " << outputTriangles << " triangles in "
              << Fixed(result.Seconds, 3) << " s (peak RSS " << Fixed(PeakResidentMegabytes(), 1)
              << " MB), wrote " << outputPath << (targetReached ? "" : " (target not reached)") << "\n";
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
  long long mergedPoints = 0;
  const slod::MeshStatistics s = SurfaceStatistics(ReadMesh(path), path, &mergedPoints);
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
      .Add("merged_points", mergedPoints)
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
              << "  merged points         " << mergedPoints << "\n";
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
  return { "bench",
    "[--inputs a,b,... | --set real | --scaling] [--input FILE]... [--methods a,b,...] [--timeout S] [--json]",
    "Time methods on inputs. Each method runs in a child process (`surfacelod simplify`) that is killed\n"
    "after --timeout seconds (reported as \"timeout\"), so a slow method cannot hold up the run.\n"
    "An input is " + GeneratedInputHelp() + ",\n"
    "a mesh file path, or the name of a CGAL demo mesh (e.g. fandisk) looked up as <name>.off in --mesh-dir.\n"
    "--set real: noisy, mask and openscan at about 1M triangles each, then every --input FILE (e.g. the MRI\n"
    "isosurface of scripts/make-mri-isosurface.py). --scaling: noisy at about 0.25M, 1M and 4M triangles,\n"
    "then time(4M) / time(1M) per method.\n"
    "The baseline " + std::string(BaselineMethod) + " always runs first. seconds: the filter alone\n"
    "(fastest of --repeat runs); Mtri/s: input triangles per second; t/quad and H/quad: the method's time\n"
    "and Hausdorff divided by the baseline's in the same run; hausdorff: relative to the input's\n"
    "bounding-box diagonal; target: at most 1% (+1) more triangles than asked; chi, loops, nm-e: Euler\n"
    "characteristic, border loops and non-manifold edges of the output (the input's on its header line).\n"
    "The header gives the load average.",
    {},
    { { "inputs", "a,b,...", "inputs (default synthetic:500 unless --set, --scaling or --input is given)" },
      { "set", "real", "the scan-like input set (noisy, mask, openscan at ~1M triangles)" },
      { "input", "FILE", "a mesh file to add to the inputs (repeatable)" },
      { "scaling", "", "noisy isosurface at ~0.25M, 1M, 4M triangles; prints time(4M)/time(1M)" },
      { "scaling-resolutions", "A,B,C", "--scaling at these noisy:N resolutions (default " + DefaultScalingResolutions() +
          ")" },
      { "target-reduction", "R", "fraction of the triangles to remove (default 0.9)" },
      { "target-triangles", "N", "number of triangles to keep (instead of --target-reduction)" },
      { "methods", "a,b,...", "methods to run (default: all)" },
      { "repeat", "N", "runs per method, the fastest counts (default 1)" },
      { "timeout", "S", "seconds a method may take (per run, default 600)" },
      { "mesh-dir", "DIR", "where named meshes are (default $SURFACELOD_MESH_DIR or the build's TestData)" },
      { "samples", "N", "deviation samples per surface (default 300000)" },
      { "no-deviation", "", "skip the Hausdorff/RMS measurement" },
      { "json", "", "one JSON line per input and method (and per method with --scaling)" } } };
}

struct BenchOptions
{
  std::vector<const Method*> Methods; // the baseline first
  std::vector<std::string> TargetArguments; // forwarded to `surfacelod simplify`
  int Repeat = 1;
  double TimeoutSeconds = 600.0;
  vtkIdType Samples = -1;
  bool Deviation = true;
  bool Json = false;
  std::string WorkDirectory; // the child processes' input and output files
};

// Topology of a surface as the bench reports it.
struct TopologySummary
{
  long long Triangles = 0, Euler = 0, BorderLoops = 0, NonManifoldEdges = 0;
};

TopologySummary SummarizeTopology(vtkPolyData* surface, const std::string& name)
{
  const slod::MeshStatistics s = SurfaceStatistics(surface, name);
  return { s.Triangles, s.EulerCharacteristic, s.BoundaryLoops, s.NonManifoldEdges };
}

// One method on one input: what the child process reported, and what the bench measured.
struct BenchRow
{
  std::string Input;
  const Method* Run = nullptr;
  std::string Status = "ok"; // ok, timeout, failed
  std::string Message;       // why it failed
  double Seconds = 0.0;
  double PeakMegabytes = 0.0; // of the child process
  vtkIdType InputTriangles = 0, TargetTriangles = 0, OutputTriangles = 0;
  bool TargetReached = false;
  bool HasDeviation = false;
  Deviation Distance;
  TopologySummary Topology;
};

// A number after "key": in a JSON line (the child's `simplify --json` output); NaN when absent.
double JsonNumber(const std::string& line, const std::string& key)
{
  const std::string quoted = "\"" + key + "\":";
  const size_t at = line.find(quoted);
  return at == std::string::npos ? std::numeric_limits<double>::quiet_NaN()
                                 : std::strtod(line.c_str() + at + quoted.size(), nullptr);
}

// The last non-empty line of a child's stderr: the tool's one-line error comes after any warnings.
std::string LastLine(const std::string& text)
{
  const size_t end = text.find_last_not_of("\n");
  if (end == std::string::npos)
  {
    return "no message";
  }
  const size_t begin = text.find_last_of('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end + 1 - (begin == std::string::npos ? 0 : begin + 1));
}

// Runs `surfacelod simplify` on the input file --repeat times; keeps the fastest run. The output
// mesh of the last run is in outputPath when the status is "ok".
void RunMethodInChild(const BenchOptions& options, const std::string& inputPath, const std::string& outputPath,
  BenchRow& row)
{
  std::vector<std::string> arguments = { CurrentExecutable(), "simplify", inputPath, outputPath, "--method",
    row.Run->Name, "--json" };
  arguments.insert(arguments.end(), options.TargetArguments.begin(), options.TargetArguments.end());
  for (int r = 0; r < options.Repeat; ++r)
  {
    const ChildResult child = RunChildProcess(arguments, options.TimeoutSeconds);
    if (child.TimedOut || !child.Started || child.ExitCode != 0)
    {
      row.Status = child.TimedOut ? "timeout" : "failed";
      row.Message = child.TimedOut ? "over " + FormatReal(options.TimeoutSeconds) + " s"
                                   : LastLine(child.Started ? child.Errors : child.Output);
      return;
    }
    const double seconds = JsonNumber(child.Output, "seconds");
    if (!std::isfinite(seconds))
    {
      row.Status = "failed";
      row.Message = "no timing in the output of simplify";
      return;
    }
    if (r == 0 || seconds < row.Seconds)
    {
      row.Seconds = seconds;
    }
    row.PeakMegabytes = std::max(row.PeakMegabytes, JsonNumber(child.Output, "peak_rss_mb"));
  }
}

// Runs one method and measures its output against the input.
BenchRow BenchMethod(const BenchOptions& options, const std::string& inputName, vtkPolyData* input,
  const std::string& inputPath, const MethodSettings& settings, const Method& method)
{
  BenchRow row;
  row.Input = inputName;
  row.Run = &method;
  row.InputTriangles = settings.InputTriangles;
  row.TargetTriangles = settings.TargetTriangles > 0
    ? settings.TargetTriangles
    : vtkIdType(std::llround(double(settings.InputTriangles) * (1.0 - settings.ReductionFraction())));
  const std::string outputPath = options.WorkDirectory + "/" + method.Name + ".vtp";
  RunMethodInChild(options, inputPath, outputPath, row);
  if (row.Status != "ok")
  {
    return row;
  }
  vtkSmartPointer<vtkPolyData> output = TriangulatedSurface(ReadMesh(outputPath));
  row.OutputTriangles = CountTriangles(output);
  row.TargetReached = row.OutputTriangles <= row.TargetTriangles + row.TargetTriangles / 100 + 1;
  row.Topology = SummarizeTopology(output, outputPath);
  if (options.Deviation && row.OutputTriangles > 0)
  {
    row.Distance = MeasureDeviation(input, output, options.Samples, true);
    row.HasDeviation = true;
  }
  return row;
}

// value / baseline, or NaN when either is missing.
double RatioTo(double value, double baseline)
{
  return baseline > 0 && std::isfinite(baseline) && std::isfinite(value) ? value / baseline
                                                                          : std::numeric_limits<double>::quiet_NaN();
}

double OneMinuteLoad()
{
  double load[3] = { 0, 0, 0 };
  return getloadavg(load, 3) > 0 ? load[0] : std::numeric_limits<double>::quiet_NaN();
}

std::string RatioText(double ratio)
{
  return std::isfinite(ratio) ? Fixed(ratio, 2) : std::string("-");
}

void PrintBenchHeader(const BenchOptions& options)
{
  double load[3] = { 0, 0, 0 };
  const int loads = getloadavg(load, 3);
  std::cout << "surfacelod bench, load average " << (loads == 3 ? Fixed(load[0], 2) + " " + Fixed(load[1], 2) + " " +
        Fixed(load[2], 2) : std::string("unknown")) << " (" << std::thread::hardware_concurrency()
            << " CPUs), time-out " << FormatReal(options.TimeoutSeconds) << " s per method run\n\n"
            << Padded("input", 16) << Padded("method", 28) << Padded("out", 9, true) << Padded("target", 7, true)
            << Padded("seconds", 9, true) << Padded("Mtri/s", 8, true) << Padded("t/quad", 8, true)
            << Padded("hausdorff", 11, true) << Padded("H/quad", 8, true) << Padded("chi", 9, true)
            << Padded("loops", 7, true) << Padded("nm-e", 7, true) << "\n";
}

void PrintInputLine(const std::string& name, const TopologySummary& topology, const BenchOptions& options)
{
  if (options.Json)
  {
    return;
  }
  std::cout << name << ": " << topology.Triangles << " triangles, chi " << topology.Euler << ", "
            << topology.BorderLoops << " border loops, " << topology.NonManifoldEdges << " non-manifold edges\n";
}

// The input column: a file by its name without directories, cut to the column's width.
std::string InputColumn(const std::string& input)
{
  const std::string name = std::filesystem::path(input).filename().string();
  return Padded(name.substr(0, 15), 16);
}

void PrintRowText(const BenchRow& row, const BenchRow& baseline)
{
  std::cout << InputColumn(row.Input) << Padded(row.Run->Name, 28);
  if (row.Status != "ok")
  {
    std::cout << Padded(row.Status, 9, true) << "  (" << row.Message << ")" << std::endl;
    return;
  }
  const bool deviation = row.HasDeviation;
  std::cout << Padded(std::to_string(row.OutputTriangles), 9, true) << Padded(row.TargetReached ? "yes" : "no", 7, true)
            << Padded(Fixed(row.Seconds, 3), 9, true)
            << Padded(row.Seconds > 0 ? Fixed(1e-6 * double(row.InputTriangles) / row.Seconds, 2) : "-", 8, true)
            << Padded(RatioText(RatioTo(row.Seconds, baseline.Status == "ok" ? baseline.Seconds : 0)), 8, true)
            << Padded(deviation ? Scientific(row.Distance.Hausdorff) : "-", 11, true)
            << Padded(deviation && baseline.HasDeviation
                   ? RatioText(RatioTo(row.Distance.Hausdorff, baseline.Distance.Hausdorff)) : "-", 8, true)
            << Padded(std::to_string(row.Topology.Euler), 9, true)
            << Padded(std::to_string(row.Topology.BorderLoops), 7, true)
            << Padded(std::to_string(row.Topology.NonManifoldEdges), 7, true) << std::endl;
}

// Adds value, or null when it is not finite / not measured.
void AddOrNull(JsonLine& line, const std::string& key, double value, bool measured = true)
{
  if (measured && std::isfinite(value))
  {
    line.Add(key, value);
  }
  else
  {
    line.AddNull(key);
  }
}

void PrintRowJson(const BenchRow& row, const BenchRow& baseline, const TopologySummary& input)
{
  const bool ok = row.Status == "ok";
  const double baselineSeconds = baseline.Status == "ok" ? baseline.Seconds : 0.0;
  JsonLine line;
  line.Add("input", row.Input).Add("method", row.Run->Name).Add("status", row.Status);
  line.Add("input_triangles", static_cast<long long>(row.InputTriangles))
    .Add("target_triangles", static_cast<long long>(row.TargetTriangles));
  AddOrNull(line, "output_triangles", double(row.OutputTriangles), ok);
  line.Add("target_reached", static_cast<long long>(ok && row.TargetReached));
  AddOrNull(line, "seconds", row.Seconds, ok);
  AddOrNull(line, "input_triangles_per_second", double(row.InputTriangles) / row.Seconds, ok && row.Seconds > 0);
  AddOrNull(line, "baseline_seconds", baselineSeconds, baselineSeconds > 0);
  AddOrNull(line, "speedup_vs_vtk_quadric", RatioTo(baselineSeconds, row.Seconds), ok);
  AddOrNull(line, "time_ratio_vs_vtk_quadric", RatioTo(row.Seconds, baselineSeconds), ok);
  AddOrNull(line, "hausdorff", row.Distance.Hausdorff, row.HasDeviation);
  AddOrNull(line, "rms", row.Distance.RMS, row.HasDeviation);
  AddOrNull(line, "hausdorff_ratio_vs_vtk_quadric", RatioTo(row.Distance.Hausdorff, baseline.Distance.Hausdorff),
    row.HasDeviation && baseline.HasDeviation);
  line.Add("input_euler", input.Euler).Add("input_border_loops", input.BorderLoops)
    .Add("input_nonmanifold_edges", input.NonManifoldEdges);
  AddOrNull(line, "output_euler", double(row.Topology.Euler), ok);
  AddOrNull(line, "output_border_loops", double(row.Topology.BorderLoops), ok);
  AddOrNull(line, "output_nonmanifold_edges", double(row.Topology.NonManifoldEdges), ok);
  AddOrNull(line, "peak_rss_mb", row.PeakMegabytes, ok);
  AddOrNull(line, "load_average", OneMinuteLoad());
  if (!ok)
  {
    line.Add("message", row.Message);
  }
  line.Print();
}

// Every method on one input; returns the rows (the baseline's first).
std::vector<BenchRow> BenchInput(const BenchOptions& options, const ParsedArguments& args, const std::string& name,
  const std::string& meshDir)
{
  vtkSmartPointer<vtkPolyData> input = ResolveBenchInput(name, meshDir);
  const MethodSettings settings = TargetSettings(args, CountTriangles(input), false, 0.9);
  const TopologySummary topology = SummarizeTopology(input, name);
  PrintInputLine(name, topology, options);
  const std::string inputPath = options.WorkDirectory + "/input.vtp";
  WriteMesh(input, inputPath);
  std::vector<BenchRow> rows;
  for (const Method* method : options.Methods)
  {
    rows.push_back(BenchMethod(options, name, input, inputPath, settings, *method));
    if (options.Json)
    {
      PrintRowJson(rows.back(), rows.front(), topology);
    }
    else
    {
      PrintRowText(rows.back(), rows.front());
    }
  }
  return rows;
}

// time(third input) / time(second input) per method after a --scaling run (4M / 1M triangles).
void PrintScaling(const std::vector<std::vector<BenchRow>>& perInput, const BenchOptions& options)
{
  if (perInput.size() != 3)
  {
    return;
  }
  const std::string& middleName = perInput[1].front().Input;
  const std::string& largeName = perInput[2].front().Input;
  if (!options.Json)
  {
    std::cout << "\nscaling: ratio = time on " << largeName << " (" << perInput[2].front().InputTriangles
              << " triangles) / time on " << middleName << " (" << perInput[1].front().InputTriangles << ")\n"
              << Padded("method", 28);
    for (const std::vector<BenchRow>& rows : perInput)
    {
      std::cout << Padded(rows.front().Input, 14, true);
    }
    std::cout << Padded("ratio", 8, true) << "\n";
  }
  for (size_t m = 0; m < options.Methods.size(); ++m)
  {
    const BenchRow& middle = perInput[1][m];
    const BenchRow& large = perInput[2][m];
    const double ratio = large.Status == "ok" && middle.Status == "ok" ? RatioTo(large.Seconds, middle.Seconds)
                                                                        : std::numeric_limits<double>::quiet_NaN();
    if (options.Json)
    {
      JsonLine line;
      line.Add("scaling", options.Methods[m]->Name).Add("ratio_of", largeName + " / " + middleName);
      AddOrNull(line, "time_ratio", ratio);
      line.Print();
      continue;
    }
    std::cout << Padded(options.Methods[m]->Name, 28);
    for (const std::vector<BenchRow>& rows : perInput)
    {
      std::cout << Padded(rows[m].Status == "ok" ? Fixed(rows[m].Seconds, 3) : rows[m].Status, 14, true);
    }
    std::cout << Padded(RatioText(ratio), 8, true) << "\n";
  }
}

// The inputs asked for: --scaling, --set, --inputs (or the default), then every --input.
std::vector<std::string> BenchInputNames(const ParsedArguments& args)
{
  std::vector<std::string> names;
  if (args.Has("scaling"))
  {
    names = ScalingInputSet(SplitList(args.Get("scaling-resolutions")));
  }
  else if (args.Has("set"))
  {
    if (args.Get("set") != "real")
    {
      throw CliError(ExitUsage, "surfacelod bench: unknown set '" + args.Get("set") + "' (known: real)");
    }
    names = RealInputSet();
  }
  else if (args.Has("inputs") || !args.Has("input"))
  {
    names = SplitList(args.Get("inputs", "synthetic:500"));
  }
  for (const std::string& file : args.GetAll("input"))
  {
    names.push_back(file);
  }
  return names;
}

// A private directory for the child processes' files, removed at the end.
struct TemporaryDirectory
{
  std::string Path;
  TemporaryDirectory()
  {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/surfacelod-bench-XXXXXX";
    if (!mkdtemp(pattern.data()))
    {
      throw CliError(ExitData, pattern + ": cannot create a temporary directory");
    }
    this->Path = pattern;
  }
  ~TemporaryDirectory()
  {
    std::error_code ec;
    std::filesystem::remove_all(this->Path, ec);
  }
};

BenchOptions ParseBenchOptions(const ParsedArguments& args)
{
  if (int(args.Has("scaling")) + int(args.Has("set")) + int(args.Has("inputs")) > 1)
  {
    throw CliError(ExitUsage, "surfacelod bench: give one of --inputs, --set, --scaling");
  }
  if (args.Has("scaling-resolutions") && !args.Has("scaling"))
  {
    throw CliError(ExitUsage, "surfacelod bench: --scaling-resolutions goes with --scaling");
  }
  BenchOptions options;
  options.Repeat = static_cast<int>(args.GetInteger("repeat", 1, 1, 1000));
  options.TimeoutSeconds = args.GetReal("timeout", 600.0, 0.001, 1e7);
  options.Samples = args.GetInteger("samples", -1, 0, MaxCount);
  options.Deviation = !args.Has("no-deviation");
  options.Json = args.Has("json");
  TargetSettings(args, 0, false, 0.9); // validates the target options before the work starts
  options.TargetArguments = args.Has("target-triangles")
    ? std::vector<std::string>{ "--target-triangles", args.Get("target-triangles") }
    : std::vector<std::string>{ "--target-reduction", args.Get("target-reduction", "0.9") };
  options.Methods = SelectMethods(args);
  // The baseline runs first so every ratio is measured in the same run.
  const Method* baseline = FindMethod(BaselineMethod);
  options.Methods.erase(std::remove(options.Methods.begin(), options.Methods.end(), baseline), options.Methods.end());
  options.Methods.insert(options.Methods.begin(), baseline);
  return options;
}

int Bench(const ParsedArguments& args)
{
  BenchOptions options = ParseBenchOptions(args);
  const std::vector<std::string> inputs = BenchInputNames(args);
  std::string meshDir = args.Get("mesh-dir");
  if (meshDir.empty() && std::getenv("SURFACELOD_MESH_DIR"))
  {
    meshDir = std::getenv("SURFACELOD_MESH_DIR");
  }
  if (meshDir.empty())
  {
    meshDir = SURFACELOD_DEFAULT_MESH_DIR;
  }
  const TemporaryDirectory work;
  options.WorkDirectory = work.Path;
  if (!options.Json)
  {
    PrintBenchHeader(options);
  }
  std::vector<std::vector<BenchRow>> perInput;
  for (const std::string& name : inputs)
  {
    perInput.push_back(BenchInput(options, args, name, meshDir));
  }
  if (args.Has("scaling"))
  {
    PrintScaling(perInput, options);
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
