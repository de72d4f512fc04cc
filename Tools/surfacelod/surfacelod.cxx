// SPDX-License-Identifier: BSD-3-Clause
// surfacelod: command-line front end of the SurfaceLOD filters.
//
//   surfacelod simplify INPUT OUTPUT -m NAME (-t TRIANGLES | -r REDUCTION | -e MAX_ERROR) [-s Name=Value]...
//   mpiexec -n N surfacelod simplify ...   (the surface in N pieces, one per process: Distributed.h)
//   surfacelod compare A B           surfacelod info FILE
//   surfacelod demo                  surfacelod bench            surfacelod methods
//
// Exit codes: 0 success, 1 wrong usage, 2 unusable file (missing, unsupported, malformed,
// unwritable), 3 a filter failed. Every failure is one line on stderr.
#include "BenchInputs.h"
#include "ChildProcess.h"
#include "CliSupport.h"
#include "Distributed.h"
#include "MeshIO.h"
#include "PartitionedFiles.h"
#include "Methods.h"
#include "Render.h"

#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkLogger.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkVersion.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <thread>

#ifndef SURFACELOD_VERSION
#define SURFACELOD_VERSION "unknown"
#endif
#ifndef SURFACELOD_DEFAULT_MESH_DIR
#define SURFACELOD_DEFAULT_MESH_DIR ""
#endif

using namespace slodcli;
using Json = nlohmann::ordered_json; // keys in the order written

namespace
{
constexpr long long MaxCount = std::numeric_limits<int>::max();

void PrintJson(const Json& line)
{
  std::cout << line.dump() << std::endl; // NaN and infinities are written as null
}

// value, or null when it is not finite / not measured.
Json NumberOrNull(double value, bool measured = true)
{
  return measured && std::isfinite(value) ? Json(value) : Json(nullptr);
}

// ---------------------------------------------------------------------------------------------
// Shared stages

struct RunResult
{
  vtkSmartPointer<vtkPolyData> Output;
  double Seconds = 0.0;
  double CpuSeconds = 0.0; // of every thread, during Update()
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
RunResult RunMethod(const Method& method, vtkPolyData* triangles, const MethodSettings& settings,
  const std::vector<ParameterAssignment>& assignments = {})
{
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = CreateFilter(method, settings, assignments);
  RunResult result;
  std::string error;
  {
    MessageCapture capture(/*swallowWarnings=*/false);
    filter->SetInputData(method.PreparesItsInput ? vtkSmartPointer<vtkPolyData>(triangles) : PreparedInput(filter, triangles));
    ProgressBar progress(filter, method.Name);
    Stopwatch watch;
    filter->Update();
    result.Seconds = watch.Seconds();
    result.CpuSeconds = watch.CpuSeconds();
    error = capture.FirstError();
  }
  result.Output = vtkSmartPointer<vtkPolyData>::New();
  result.Output->ShallowCopy(filter->GetOutput());
  if (!error.empty() || (result.Output->GetNumberOfPolys() == 0 && triangles->GetNumberOfPolys() > 0))
  {
    throw CliError(ExitFailure,
      std::string(method.Name) + " failed: " + (error.empty() ? std::string("empty output") : error));
  }
  // The input's points are finite (checked when read): a method whose arithmetic cannot hold them
  // (VTK's decimators write float points, so coordinates beyond 3.4e38 become infinite) fails
  // instead of writing them.
  if (vtkPoints* points = result.Output->GetPoints())
  {
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      double p[3];
      points->GetPoint(i, p);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      {
        throw CliError(ExitFailure,
          std::string(method.Name) + " failed: its output has a non-finite point (the input's coordinates are beyond its precision)");
      }
    }
  }
  return result;
}

struct DeviationValues
{
  double Hausdorff = 0, HausdorffAB = 0, HausdorffBA = 0, Mean = 0, RMS = 0;
};

struct Deviation : DeviationValues // relative to A's bounding-box diagonal
{
  DeviationValues Absolute; // in the meshes' units
  double Diagonal = 0;
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
  d.Absolute = { deviation->GetHausdorff(), deviation->GetHausdorffAB(), deviation->GetHausdorffBA(),
    deviation->GetMean(), deviation->GetRMS() };
  d.Diagonal = deviation->GetBoundingBoxDiagonal();
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

// -t / -r / -e / -l as given; a value below its option's range means "not given".
struct TargetArguments
{
  long long Triangles = 0;
  double Reduction = -1.0;
  double MaximumError = -1.0;
  double Level = -1.0;
};

// -t and -r (one of them); with withErrorAndLevel also -e and -l (not with -t, -r).
void AddTargetOptions(CLI::App& app, TargetArguments& target, bool withErrorAndLevel, const std::string& reductionHelp)
{
  CLI::Option* triangles = app.add_option("-t,--target-triangles", target.Triangles, "number of triangles to keep")
                             ->type_name("N")->check(CLI::Range(1LL, std::numeric_limits<long long>::max()));
  CLI::Option* reduction = app.add_option("-r,--target-reduction", target.Reduction, reductionHelp)
                             ->type_name("R")->check(CLI::Range(0.0, 1.0))->excludes(triangles);
  if (withErrorAndLevel)
  {
    app.add_option("-e,--max-error", target.MaximumError,
      "stop before the surface moves more than E (absolute, mesh units)")
      ->type_name("E")->check(CLI::NonNegativeNumber);
    app.add_option("-l,--level", target.Level,
      "level i+t of a hierarchy method (triangle-collapse-hierarchy): M_i blended by t")
      ->type_name("L")->check(CLI::NonNegativeNumber)->excludes(triangles)->excludes(reduction);
  }
}

// Settings from the target options; command: for the messages.
MethodSettings TargetSettings(const TargetArguments& target, vtkIdType inputTriangles, bool required,
  double defaultReduction, const std::string& command)
{
  MethodSettings settings;
  settings.InputTriangles = inputTriangles;
  const bool byError = target.MaximumError >= 0;
  if (target.Level >= 0)
  {
    settings.Level = target.Level;
  }
  else if (target.Triangles > 0)
  {
    settings.TargetTriangles = target.Triangles;
  }
  else if (target.Reduction >= 0 || !byError)
  {
    if (target.Reduction < 0 && !byError && required)
    {
      throw CliError(ExitUsage, "surfacelod " + command + ": give -t/--target-triangles N, -r/--target-reduction R "
        "or -e/--max-error E");
    }
    settings.TargetReduction = target.Reduction >= 0 ? target.Reduction : defaultReduction;
  }
  else
  {
    settings.TargetReduction = 1.0; // --max-error alone: simplify until the error bound stops it
  }
  settings.HasMaximumError = byError;
  settings.MaximumError = byError ? target.MaximumError : 0.0;
  return settings;
}

// The methods named (all those of the default runs when none is).
std::vector<const Method*> SelectMethods(const std::vector<std::string>& names)
{
  std::vector<const Method*> selected;
  for (const Method& m : Methods())
  {
    if (names.empty() ? m.InDefaultRuns : std::find(names.begin(), names.end(), m.Name) != names.end())
    {
      selected.push_back(&m);
    }
  }
  return selected;
}

// The registry's method names, for CLI11's check of -m.
CLI::IsMember KnownMethod()
{
  std::vector<std::string> known;
  for (const Method& m : Methods())
  {
    known.push_back(m.Name);
  }
  return CLI::IsMember(known);
}

// -m/--methods a,b,...: one comma-separated word.
void AddMethodsOption(CLI::App& app, std::vector<std::string>& names, const std::string& help)
{
  app.add_option("-m,--methods", names, help)
    ->type_name("A,B,...")->delimiter(',')->allow_extra_args(false)->check(KnownMethod());
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

struct SimplifyArguments
{
  std::string Input, Output, MethodName;
  TargetArguments Target;
  std::vector<std::string> Assignments; // --set Name=Value
  double FeatureSize = -1.0;             // --feature-size
  bool Json = false;
  int LogVerbosity = vtkLogger::VERBOSITY_OFF; // --log-verbosity
};

std::string SimplifyDescription()
{
  return "Simplify the surface in INPUT and write it to OUTPUT.\n"
         "Readable: " + ReadableExtensions() + "; writable: " + WritableExtensions() + " (chosen by extension).\n"
         "Polygons and strips are triangulated first. Methods: " + MethodNames() + "\n"
         "(`surfacelod methods --verbose` describes them and lists the parameters --set changes).";
}

int Simplify(const SimplifyArguments& args);

std::function<int()> DefineSimplify(CLI::App& app)
{
  auto args = std::make_shared<SimplifyArguments>();
  app.add_option("INPUT", args->Input, "input mesh file")->required();
  app.add_option("OUTPUT", args->Output, "output mesh file")->required();
  app.add_option("-m,--method", args->MethodName, "simplification method (required)")
    ->type_name("NAME")->required()->check(KnownMethod());
  AddTargetOptions(app, args->Target, true, "fraction of the triangles to remove, 0..1 (0.9 keeps 10%)");
  app.add_option("-s,--set", args->Assignments, "set a parameter of the method's filter (repeatable)")
    ->type_name("Name=Value")->allow_extra_args(false); // one word per --set, never the positionals
  app.add_option("--feature-size", args->FeatureSize,
    "size below which features go (absolute, mesh units), for feature-removal methods (topological-noise-removal)")
    ->type_name("F")->check(CLI::NonNegativeNumber);
  app.add_flag("-j,--json", args->Json,
    "print one JSON line: method, input_triangles, output_triangles, target_reached, seconds, peak_rss_mb");
  app.add_option("--log-verbosity", args->LogVerbosity,
    "print the filters' vtkLogger messages up to this verbosity on stderr (0 INFO ... 9 TRACE: stage times, counts)")
    ->type_name("N")->check(CLI::Range(0, 9));
  return [args] { return Simplify(*args); };
}

// The method asked for, checked against the other options before a large file is read.
const Method& CheckedMethod(const SimplifyArguments& args)
{
  const Method* method = FindMethod(args.MethodName);
  if (args.Target.MaximumError >= 0 && !method->SupportsMaximumError)
  {
    throw CliError(ExitUsage, std::string("surfacelod simplify: method ") + method->Name + " does not support --max-error");
  }
  if (args.Target.Level >= 0 && !method->SupportsLevel)
  {
    throw CliError(ExitUsage, std::string("surfacelod simplify: method ") + method->Name + " has no levels (--level)");
  }
  TargetSettings(args.Target, 0, method->NeedsTarget, 0.0, "simplify");
  return *method;
}

// What `simplify` reports of its output: the triangles and the filter's own "TargetReached" (-1: none).
struct OutputSummary
{
  vtkIdType Triangles = 0;
  int ReportedReached = -1;
};

OutputSummary Summarize(vtkPolyData* output)
{
  return { output->GetNumberOfPolys(), ReportedTargetReached(output) };
}

// Memory the method needed beyond its input: the peak resident size during the run minus the
// resident size before it (the read input included). NaN when it could not be measured.
struct RunMemory
{
  vtkIdType InputPoints = 0;
  double PeakBeforeRun = 0.0; // the reader's peak, which a reset of the peak forgets
  double WorkingMegabytes = std::numeric_limits<double>::quiet_NaN();
  double BytesPerInputPoint() const
  {
    return this->InputPoints > 0 ? this->WorkingMegabytes * 1048576.0 / double(this->InputPoints)
                                 : std::numeric_limits<double>::quiet_NaN();
  }
};

// The line `simplify` prints; `distributed` adds the figures of a run on several processes.
void PrintSimplified(const SimplifyArguments& args, const Method& method, const MethodSettings& settings,
  const OutputSummary& output, double seconds, double cpuSeconds, const RunMemory& memory,
  const Json& distributed = Json())
{
  const bool measured = std::isfinite(memory.BytesPerInputPoint());
  const double peak = std::max(memory.PeakBeforeRun, PeakResidentMegabytes());
  const vtkIdType outputTriangles = output.Triangles;
  // A method that removes features of a size needs no target: with none given there is none to
  // reach (null in the JSON).
  const TargetArguments& target = args.Target;
  const bool hasTarget = method.NeedsTarget || target.Triangles > 0 || target.Reduction >= 0 ||
    target.MaximumError >= 0 || target.Level >= 0;
  const bool targetReached = !hasTarget || TargetReached(outputTriangles, output.ReportedReached, settings);
  if (args.Json)
  {
    Json line = { { "method", method.Name }, { "input_triangles", settings.InputTriangles },
      { "output_triangles", outputTriangles }, { "target_reached", hasTarget ? Json(targetReached) : Json() },
      { "seconds", seconds }, { "cpu_seconds", NumberOrNull(cpuSeconds) },
      { "peak_rss_mb", peak } };
    if (measured)
    {
      line["input_points"] = memory.InputPoints;
      line["working_rss_mb"] = memory.WorkingMegabytes;
    }
    if (!distributed.is_null())
    {
      line.update(distributed);
    }
    PrintJson(line);
  }
  else
  {
    std::cout << method.Name << ": " << settings.InputTriangles << " -> " << outputTriangles << " triangles in "
              << Fixed(seconds, 3) << " s (peak RSS " << Fixed(peak, 1) << " MB"
              << (measured ? ", " + Fixed(memory.BytesPerInputPoint(), 0) + " bytes per input point beyond the input"
                           : std::string())
              << (distributed.is_null() ? std::string() : "; " + distributed.dump()) << "), wrote " << args.Output
              << (targetReached ? "" : " (target not reached)") << "\n";
  }
}

int SimplifyDistributed(const SimplifyArguments& args, const Method& method,
  const std::vector<ParameterAssignment>& assignments, vtkMultiProcessController* controller);

int Simplify(const SimplifyArguments& args)
{
  const Method& method = CheckedMethod(args);
  const std::vector<ParameterAssignment> assignments = ParseAssignments(method, args.Assignments);
  if (args.LogVerbosity != vtkLogger::VERBOSITY_OFF)
  {
    vtkLogger::SetStderrVerbosity(static_cast<vtkLogger::Verbosity>(args.LogVerbosity));
  }
  if (vtkMultiProcessController* controller = DistributedController())
  {
    return SimplifyDistributed(args, method, assignments, controller);
  }
  CheckWritablePath(args.Output);

  vtkSmartPointer<vtkPolyData> input = TriangulatedSurface(ReadMesh(args.Input));
  MethodSettings settings = TargetSettings(args.Target, CountTriangles(input), method.NeedsTarget, 0.0, "simplify");
  settings.FeatureSize = args.FeatureSize;
  RunMemory memory;
  memory.InputPoints = input->GetNumberOfPoints();
  memory.PeakBeforeRun = PeakResidentMegabytes();
  const bool peakReset = ResetPeakResident();
  const double residentBefore = ResidentMegabytes();
  const RunResult result = RunMethod(method, input, settings, assignments);
  if (peakReset)
  {
    memory.WorkingMegabytes = std::max(0.0, PeakResidentMegabytes() - residentBefore);
  }
  WriteMesh(result.Output, args.Output);
  PrintSimplified(args, method, settings, Summarize(result.Output), result.Seconds, result.CpuSeconds, memory);
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// simplify on several processes (mpiexec): every stage between collectives catches its own
// failures and shares them, so that all processes leave together instead of waiting for each other.

// The worst exit code of all processes; throws it on every process, with the message of the
// lowest-ranked process that failed (rank 0 prints it: the failure may be another process's own,
// such as its piece of a .pvtp).
void FailTogether(vtkMultiProcessController* controller, int code, const std::string& message)
{
  int worst = ExitSuccess;
  controller->AllReduce(&code, &worst, 1, vtkCommunicator::MAX_OP);
  if (worst == ExitSuccess)
  {
    return;
  }
  const int rank = controller->GetLocalProcessId();
  int mine = code != ExitSuccess ? rank : controller->GetNumberOfProcesses(), first = 0;
  controller->AllReduce(&mine, &first, 1, vtkCommunicator::MIN_OP);
  std::string text = rank == first ? message : std::string();
  vtkIdType length = static_cast<vtkIdType>(text.size());
  controller->Broadcast(&length, 1, first);
  text.resize(static_cast<size_t>(length));
  if (length > 0)
  {
    controller->Broadcast(text.data(), length, first);
  }
  throw CliError(worst, text.empty() ? "surfacelod simplify: another process failed" : text);
}

// Rank 0 reads the input (nullptr on the other ranks); every rank learns its triangle count.
vtkSmartPointer<vtkPolyData> ReadOnRankZero(
  vtkMultiProcessController* controller, const SimplifyArguments& args, vtkIdType& inputTriangles)
{
  vtkSmartPointer<vtkPolyData> input;
  int code = ExitSuccess;
  std::string message;
  long long triangles = 0;
  if (controller->GetLocalProcessId() == 0)
  {
    try
    {
      CheckWritablePath(args.Output);
      input = TriangulatedSurface(ReadMesh(args.Input));
      triangles = CountTriangles(input);
    }
    catch (const CliError& e)
    {
      code = e.Code;
      message = e.what();
    }
  }
  FailTogether(controller, code, message);
  controller->Broadcast(&triangles, 1, 0);
  inputTriangles = static_cast<vtkIdType>(triangles);
  return input;
}

RunResult SimplifyPiece(vtkMultiProcessController* controller, const Method& method, vtkPolyData* piece,
  const MethodSettings& settings, const std::vector<ParameterAssignment>& assignments)
{
  RunResult result;
  int code = ExitSuccess;
  std::string message;
  try
  {
    // Every rank starts with its piece in hand, so that `seconds` times the filter, not the
    // scatter (rank 0 would otherwise wait in the filter's first collective for the last piece).
    controller->Barrier();
    result = RunMethod(method, piece, settings, assignments); // collective inside the filter's Update
  }
  catch (const CliError& e)
  {
    code = e.Code;
    message = e.what();
  }
  FailTogether(controller, code, message);
  return result;
}

// This process's own piece of a .pvtp input that has one piece per process; every process learns
// the union's triangle count.
vtkSmartPointer<vtkPolyData> ReadOwnPiece(
  vtkMultiProcessController* controller, const SimplifyArguments& args, vtkIdType& inputTriangles)
{
  vtkSmartPointer<vtkPolyData> piece;
  int code = ExitSuccess;
  std::string message;
  long long triangles = 0, total = 0;
  try
  {
    piece = TriangulatedSurface(
      ReadPartitionedPiece(args.Input, controller->GetLocalProcessId(), controller->GetNumberOfProcesses()));
    const std::string problem = piece->GetNumberOfPoints() > 0 ? SurfaceProblem(piece) : std::string();
    if (!problem.empty())
    {
      throw CliError(ExitData, args.Input + ": piece " + std::to_string(controller->GetLocalProcessId()) + ": " + problem);
    }
    triangles = CountTriangles(piece);
  }
  catch (const CliError& e)
  {
    code = e.Code;
    message = e.what();
  }
  FailTogether(controller, code, message);
  controller->AllReduce(&triangles, &total, 1, vtkCommunicator::SUM_OP);
  inputTriangles = static_cast<vtkIdType>(total);
  return piece;
}

// This process's piece of the input: read by itself from a .pvtp with one piece per process, else
// split from the whole surface that rank 0 reads.
vtkSmartPointer<vtkPolyData> DistributedInput(
  vtkMultiProcessController* controller, const SimplifyArguments& args, vtkIdType& inputTriangles, bool& readOwnPiece)
{
  readOwnPiece = false;
  if (IsPartitionedPath(args.Input))
  {
    int pieces = 0, code = ExitSuccess;
    std::string message;
    try
    {
      CheckWritablePath(args.Output);
      pieces = PartitionedPieceCount(args.Input);
    }
    catch (const CliError& e)
    {
      code = e.Code;
      message = e.what();
    }
    FailTogether(controller, code, message);
    if (pieces == controller->GetNumberOfProcesses())
    {
      readOwnPiece = true;
      return ReadOwnPiece(controller, args, inputTriangles);
    }
  }
  return ScatterPieces(controller, ReadOnRankZero(controller, args, inputTriangles));
}

// Every process writes its own piece of a .pvtp output; the union's figures are reduced to rank 0.
OutputSummary WriteOwnPiece(vtkMultiProcessController* controller, const SimplifyArguments& args, vtkPolyData* piece)
{
  const std::string problem = WritePartitioned(piece, args.Output, controller);
  FailTogether(controller, problem.empty() ? ExitSuccess : ExitData,
    problem.empty() ? std::string() : args.Output + ": cannot write: " + problem);
  long long triangles = piece->GetNumberOfPolys(), total = 0;
  int reported = ReportedTargetReached(piece), leastReported = -1;
  controller->Reduce(&triangles, &total, 1, vtkCommunicator::SUM_OP, 0);
  controller->Reduce(&reported, &leastReported, 1, vtkCommunicator::MIN_OP, 0);
  return { static_cast<vtkIdType>(total), leastReported };
}

int SimplifyDistributed(const SimplifyArguments& args, const Method& method,
  const std::vector<ParameterAssignment>& assignments, vtkMultiProcessController* controller)
{
  if (!method.SimplifiesPieces)
  {
    throw CliError(ExitUsage, std::string("surfacelod simplify: method ") + method.Name +
        " does not simplify distributed pieces; run it without mpiexec");
  }
  const Stopwatch wall;
  vtkIdType inputTriangles = 0;
  bool readOwnPiece = false;
  vtkSmartPointer<vtkPolyData> piece = DistributedInput(controller, args, inputTriangles, readOwnPiece);
  const MethodSettings settings = TargetSettings(args.Target, inputTriangles, true, 0.0, "simplify");
  const RunResult result = SimplifyPiece(controller, method, piece, settings, assignments);
  piece = nullptr;
  const bool eachWritesItsPiece = IsPartitionedPath(args.Output);
  const OutputSummary summary = eachWritesItsPiece ? WriteOwnPiece(controller, args, result.Output) : OutputSummary();
  const vtkSmartPointer<vtkPolyData> merged = eachWritesItsPiece ? nullptr : GatherPieces(controller, result.Output);

  const int processes = controller->GetNumberOfProcesses();
  double slowest = 0.0, cpu = 0.0, peak = PeakResidentMegabytes();
  std::vector<double> peaks(static_cast<size_t>(processes));
  controller->Reduce(&result.Seconds, &slowest, 1, vtkCommunicator::MAX_OP, 0);
  controller->Reduce(&result.CpuSeconds, &cpu, 1, vtkCommunicator::SUM_OP, 0); // all processes' work
  controller->Gather(&peak, peaks.data(), 1, 0);
  if (controller->GetLocalProcessId() != 0)
  {
    return ExitSuccess;
  }
  if (!eachWritesItsPiece)
  {
    WriteMesh(merged, args.Output);
  }
  PrintSimplified(args, method, settings, eachWritesItsPiece ? summary : Summarize(merged), slowest, cpu, RunMemory(),
    { { "processes", processes }, { "wall_seconds", wall.Seconds() }, { "peak_rss_mb_per_process", peaks },
      { "pieces_read", readOwnPiece ? processes : 0 }, { "pieces_written", eachWritesItsPiece ? processes : 0 } });
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// compare

struct CompareArguments
{
  std::string A, B;
  long long Samples = -1; // the deviation filter's default
  bool Json = false;
};

std::string CompareDescription()
{
  return "Two-sided distance between surface A (reference) and surface B, with vtkSurfaceDeviation:\n"
         "all vertices plus N random area-weighted samples on each surface: hausdorff (symmetric),\n"
         "hausdorff_ab (A's samples to B), hausdorff_ba, mean and rms (averages of both sides), each\n"
         "relative to the bounding-box diagonal of A and absolute (in the meshes' units, *_absolute).";
}

int Compare(const CompareArguments& args);

std::function<int()> DefineCompare(CLI::App& app)
{
  auto args = std::make_shared<CompareArguments>();
  app.add_option("A", args->A, "reference mesh file")->required();
  app.add_option("B", args->B, "compared mesh file")->required();
  app.add_option("-n,--samples", args->Samples, "random samples per surface (default 300000)")
    ->type_name("N")->check(CLI::Range(0LL, MaxCount));
  app.add_flag("-j,--json", args->Json, "print one JSON line (relative and absolute values, the diagonal)");
  return [args] { return Compare(*args); };
}

int Compare(const CompareArguments& args)
{
  vtkSmartPointer<vtkPolyData> a = TriangulatedSurface(ReadMesh(args.A));
  vtkSmartPointer<vtkPolyData> b = TriangulatedSurface(ReadMesh(args.B));
  const Deviation d = MeasureDeviation(a, b, args.Samples, false);
  if (args.Json)
  {
    PrintJson({ { "hausdorff", d.Hausdorff }, { "hausdorff_ab", d.HausdorffAB }, { "hausdorff_ba", d.HausdorffBA },
      { "mean", d.Mean }, { "rms", d.RMS }, { "hausdorff_absolute", d.Absolute.Hausdorff },
      { "hausdorff_ab_absolute", d.Absolute.HausdorffAB }, { "hausdorff_ba_absolute", d.Absolute.HausdorffBA },
      { "mean_absolute", d.Absolute.Mean }, { "rms_absolute", d.Absolute.RMS }, { "diagonal", d.Diagonal } });
    return ExitSuccess;
  }
  auto row = [&](const char* name, double relative, double absolute, const char* note) {
    std::cout << "  " << Padded(name, 13) << Padded(Scientific(relative), 11, true)
              << Padded(Scientific(absolute), 12, true) << note << "\n";
  };
  std::cout << "relative to the bounding-box diagonal of " << args.A << " (" << Scientific(d.Diagonal)
            << "), and absolute:\n";
  row("hausdorff", d.Hausdorff, d.Absolute.Hausdorff, "");
  row("hausdorff_ab", d.HausdorffAB, d.Absolute.HausdorffAB, "  (A to B)");
  row("hausdorff_ba", d.HausdorffBA, d.Absolute.HausdorffBA, "  (B to A)");
  row("mean", d.Mean, d.Absolute.Mean, "");
  row("rms", d.RMS, d.Absolute.RMS, "");
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// info

struct InfoArguments
{
  std::string File;
  bool Json = false;
};

std::string InfoDescription()
{
  return "Topology of the surface in FILE, as read, with exactly coincident points merged (so that STL\n"
         "and OFF triangle soups count correctly); polygons are triangulated, nothing else is changed.\n"
         "genus is -1 (\"undefined\") unless the surface is an orientable manifold.";
}

int Info(const InfoArguments& args);

std::function<int()> DefineInfo(CLI::App& app)
{
  auto args = std::make_shared<InfoArguments>();
  app.add_option("FILE", args->File, "mesh file")->required();
  app.add_flag("-j,--json", args->Json, "print one JSON line");
  return [args] { return Info(*args); };
}

int Info(const InfoArguments& args)
{
  const std::string& path = args.File;
  long long mergedPoints = 0;
  const slod::MeshStatistics s = SurfaceStatistics(ReadMesh(path), path, &mergedPoints);
  if (args.Json)
  {
    PrintJson({ { "file", path }, { "vertices", s.Vertices }, { "triangles", s.Triangles }, { "edges", s.Edges },
      { "boundary_edges", s.BoundaryEdges }, { "boundary_loops", s.BoundaryLoops },
      { "nonmanifold_edges", s.NonManifoldEdges }, { "nonmanifold_vertices", s.NonManifoldVertices },
      { "components", s.Components }, { "euler_characteristic", s.EulerCharacteristic }, { "genus", s.Genus },
      { "degenerate_triangles", s.DegenerateTriangles },
      { "inconsistently_oriented_edges", s.InconsistentlyOrientedEdges }, { "merged_points", mergedPoints } });
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

struct DemoArguments
{
  int Resolution = 500;
  std::string OutputDirectory = "surfacelod-demo";
  double Reduction = 0.9;
  std::vector<std::string> MethodNames;
  long long Samples = -1;
  // The cleaning step: a noisy scan-like isosurface (or a file, e.g. an MRI isosurface) cleaned
  // by topological-noise-removal, then simplified before and after cleaning.
  bool Cleaning = true;
  int NoisyResolution = 100;
  std::string NoisyInput;
  double FeatureSize = -1.0;
};

std::string DemoDescription()
{
  return "Generate the synthetic test surface (vtkSyntheticIsosurfaceSource: a rippled ring of Gaussian\n"
         "blobs, genus 1, about 1,000,000 triangles at the default resolution 500), simplify it with every\n"
         "method (those marked in `surfacelod methods` only when named in --methods), print a table (time,\n"
         "symmetric Hausdorff and RMS distance relative to the bounding-box diagonal), write each mesh as\n"
         "DIR/<method>.vtp and a side-by-side picture DIR/demo.png (needs an X display; run under\n"
         "`xvfb-run -a` on a headless machine). Then the cleaning step: a noisy scan-like isosurface\n"
         "(vtkScanSurfaceSource, or --noisy-input FILE such as an MRI isosurface) cleaned by\n"
         "topological-noise-removal, and quadric-triangle-collapse on it before and after cleaning.";
}

int Demo(const DemoArguments& args);

std::function<int()> DefineDemo(CLI::App& app)
{
  auto args = std::make_shared<DemoArguments>();
  app.add_option("--resolution", args->Resolution, "samples per axis of the synthetic field (default 500)")
    ->type_name("N")->check(CLI::Range(16, 4000));
  app.add_option("-o,--output-dir", args->OutputDirectory,
    "where meshes and the picture go (default ./surfacelod-demo)")
    ->type_name("DIR");
  app.add_option("-r,--target-reduction", args->Reduction,
    "fraction of the triangles to remove (default 0.9: keep 10%)")
    ->type_name("R")->check(CLI::Range(0.0, 1.0));
  AddMethodsOption(app, args->MethodNames, "methods to run (default: all)");
  app.add_option("-n,--samples", args->Samples, "deviation samples per surface (default 300000)")
    ->type_name("N")->check(CLI::Range(0LL, MaxCount));
  app.add_flag("!--no-cleaning", args->Cleaning, "skip the cleaning step");
  app.add_option("--noisy-resolution", args->NoisyResolution,
    "resolution of the cleaning step's noisy isosurface (default 100: about 134,000 triangles)")
    ->type_name("N")->check(CLI::Range(16, 2000));
  app.add_option("--noisy-input", args->NoisyInput, "a mesh file for the cleaning step instead (e.g. an MRI isosurface)")
    ->type_name("FILE");
  app.add_option("--feature-size", args->FeatureSize,
    "the cleaning step's feature size, absolute (default: 1% of the diagonal)")
    ->type_name("F")->check(CLI::PositiveNumber);
  return [args] { return Demo(*args); };
}

// One row of the cleaning step: a surface's triangles, time, distance to the noisy input and topology.
void PrintCleaningRow(const std::string& name, vtkPolyData* noisy, vtkPolyData* surface, double seconds,
  vtkIdType samples)
{
  const Deviation d = MeasureDeviation(noisy, surface, samples, true);
  const slod::MeshStatistics s = SurfaceStatistics(surface, name);
  std::cout << Padded(name, 40) << Padded(std::to_string(s.Triangles), 11, true) << Padded(Fixed(seconds, 3), 10, true)
            << Padded(Scientific(d.Hausdorff), 12, true) << Padded(Scientific(d.RMS), 12, true)
            << Padded(std::to_string(s.EulerCharacteristic), 8, true) << Padded(std::to_string(s.NonManifoldEdges), 7, true)
            << std::endl;
}

// The handles the survey did not size and the output's genus; both are -1 when the genus is not
// defined (non-manifold edges left where the sheets could not be split), said in words then.
std::string KeptHandlesText(vtkFieldData* fd)
{
  const long long notSized = std::llround(fd->GetArray("HandlesNotSized")->GetTuple1(0));
  const long long genus = std::llround(fd->GetArray("HandlesKept")->GetTuple1(0));
  if (genus < 0)
  {
    return ", output genus not defined (non-manifold or inconsistently oriented edges remain)";
  }
  return " (" + std::to_string(notSized) + " larger, not sized), output genus " + std::to_string(genus);
}

// The cleaning step: topological-noise-removal on a noisy surface, then quadric-triangle-collapse
// to the demo's reduction on the noisy and on the cleaned surface, both measured against the noisy one.
void DemoCleaning(const DemoArguments& args)
{
  const std::string name = args.NoisyInput.empty() ? "noisy:" + std::to_string(args.NoisyResolution) : args.NoisyInput;
  vtkSmartPointer<vtkPolyData> noisy = ResolveBenchInput(name, "");
  WriteMesh(noisy, args.OutputDirectory + "/noisy.vtp");
  const slod::MeshStatistics before = SurfaceStatistics(noisy, name);
  std::cout << "\ncleaning step: " << name << ": " << before.Triangles << " triangles, chi " << before.EulerCharacteristic
            << ", " << before.NonManifoldEdges << " non-manifold edges, " << before.BoundaryLoops << " border loops\n";
  MethodSettings settings;
  settings.InputTriangles = before.Triangles;
  settings.FeatureSize = args.FeatureSize;
  const RunResult cleaned = RunMethod(*FindMethod("topological-noise-removal"), noisy, settings);
  vtkFieldData* fd = cleaned.Output->GetFieldData();
  vtkDataArray* sizes = fd->GetArray("KeptHandleSizes");
  std::cout << "  topological-noise-removal, feature size " << FormatReal(fd->GetArray("FeatureSize")->GetTuple1(0))
            << ": " << fd->GetArray("HandlesRemoved")->GetTuple1(0) << " handles cut, "
            << fd->GetArray("NonManifoldEdgesSplit")->GetTuple1(0) << " non-manifold edges split, "
            << (sizes ? sizes->GetNumberOfTuples() : 0) << " kept handles sized up to "
            << FormatReal(fd->GetArray("KeptHandleSurveySize")->GetTuple1(0)) << KeptHandlesText(fd) << "\n\n"
            << Padded("surface", 40) << Padded("triangles", 11, true) << Padded("seconds", 10, true)
            << Padded("hausdorff", 12, true) << Padded("rms", 12, true) << Padded("chi", 8, true) << Padded("nm-e", 7, true)
            << "\n";
  PrintCleaningRow("topological-noise-removal", noisy, cleaned.Output, cleaned.Seconds, args.Samples);
  WriteMesh(cleaned.Output, args.OutputDirectory + "/cleaned.vtp");
  settings.TargetTriangles = std::max<vtkIdType>(1, std::llround((1.0 - args.Reduction) * before.Triangles));
  const Method& collapse = *FindMethod("quadric-triangle-collapse");
  for (const bool clean : { false, true })
  {
    const RunResult simplified = RunMethod(collapse, clean ? cleaned.Output.Get() : noisy.Get(), settings);
    const std::string label = std::string("quadric-triangle-collapse on the ") + (clean ? "cleaned" : "noisy");
    PrintCleaningRow(label, noisy, simplified.Output, simplified.Seconds, args.Samples);
    WriteMesh(simplified.Output, args.OutputDirectory + (clean ? "/cleaned-simplified.vtp" : "/noisy-simplified.vtp"));
  }
  std::cout << "(distances to the noisy surface, relative to its diagonal; chi: Euler characteristic; nm-e:\n"
            << "non-manifold edges)\n";
}

int Demo(const DemoArguments& args)
{
  const int resolution = args.Resolution;
  const double reduction = args.Reduction;
  const vtkIdType samples = args.Samples;
  const std::string& outputDir = args.OutputDirectory;
  const std::vector<const Method*> methods = SelectMethods(args.MethodNames);
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
  std::cout << "\n(hausdorff, rms: relative to the bounding-box diagonal; seconds: filter only)\n";
  if (args.Cleaning)
  {
    DemoCleaning(args);
  }
  std::cout << "meshes written to " << outputDir << "/\n";

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

std::string BenchDescription()
{
  return "Time methods on inputs. Each method runs in a child process (`surfacelod simplify`) that is killed\n"
    "after --timeout seconds (reported as \"timeout\"), so a slow method cannot hold up the run.\n"
    "An input is " + GeneratedInputHelp() + ",\n"
    "a mesh file path, or the name of a CGAL demo mesh (e.g. fandisk) looked up as <name>.off in --mesh-dir.\n"
    "--set real: noisy, mask and openscan at about 1M triangles each, then every --input FILE (e.g. the MRI\n"
    "isosurface of scripts/make-mri-isosurface.py). --scaling: noisy at about 0.25M, 1M and 4M triangles,\n"
    "then time(4M) / time(1M) per method, by wall time and by CPU time.\n"
    "The baseline " + std::string(BaselineMethod) + " always runs first. seconds: the filter alone\n"
    "(fastest of --repeat runs); cpu s: the CPU time of all its threads in that run (on a loaded machine the\n"
    "figure to compare); Mtri/s: input triangles per second; t/quad and H/quad: the method's time\n"
    "and Hausdorff divided by the baseline's in the same run; hausdorff: relative to the input's\n"
    "bounding-box diagonal; target: at most 1% (+1) more triangles than asked; chi, loops, nm-e: Euler\n"
    "characteristic, border loops and non-manifold edges of the output (the input's on its header line); B/vert:\n"
    "the method's peak memory beyond the read input, in bytes per input point (largest of the runs).\n"
    "--interleave: the --repeat runs of an input alternate between the methods (a round runs each\n"
    "once, the baseline first), and t/quad is the median of the rounds' ratios: a machine whose speed\n"
    "drifts during the bench moves both times of a round alike.\n"
    "The header gives the load average.";
}

// What the bench command line says, as given.
struct BenchArguments
{
  std::vector<std::string> Inputs, Files, ScalingResolutions, MethodNames;
  std::string InputSet, MeshDirectory;
  bool Scaling = false, NoDeviation = false, Json = false, Interleave = false;
  TargetArguments Target;
  int Repeat = 1;
  double TimeoutSeconds = 600.0;
  long long Samples = -1;
};

int Bench(const BenchArguments& args);

// The options choosing the inputs: one of --inputs, --set, --scaling; any number of --input.
void AddBenchInputOptions(CLI::App& app, BenchArguments& args)
{
  CLI::Option* inputs = app.add_option("--inputs", args.Inputs,
    "inputs (default synthetic:500 unless --set, --scaling or --input is given)")
    ->type_name("a,b,...")->delimiter(',')->allow_extra_args(false);
  CLI::Option* set = app.add_option("--set", args.InputSet, "the scan-like input set (noisy, mask, openscan at ~1M "
    "triangles)")->type_name("real")->check(CLI::IsMember({ "real" }))->excludes(inputs);
  app.add_option("-i,--input", args.Files, "a mesh file to add to the inputs (repeatable)")
    ->type_name("FILE")->allow_extra_args(false);
  CLI::Option* scaling = app.add_flag("--scaling", args.Scaling,
    "noisy isosurface at ~0.25M, 1M, 4M triangles; prints time(4M)/time(1M)")->excludes(inputs)->excludes(set);
  app.add_option("--scaling-resolutions", args.ScalingResolutions, "--scaling at these noisy:N resolutions (default "
    + DefaultScalingResolutions() + ")")->type_name("A,B,C")->delimiter(',')->allow_extra_args(false)->needs(scaling);
}

std::function<int()> DefineBench(CLI::App& app)
{
  auto args = std::make_shared<BenchArguments>();
  AddBenchInputOptions(app, *args);
  AddTargetOptions(app, args->Target, false, "fraction of the triangles to remove (default 0.9)");
  AddMethodsOption(app, args->MethodNames, "methods to run (default: all)");
  app.add_option("--repeat", args->Repeat, "runs per method, the fastest counts (default 1)")
    ->type_name("N")->check(CLI::Range(1, 1000));
  app.add_flag("--interleave", args->Interleave, "the --repeat runs alternate between the methods; t/quad is the "
    "median of the rounds' ratios");
  app.add_option("--timeout", args->TimeoutSeconds, "seconds a method may take (per run, default 600)")
    ->type_name("S")->check(CLI::Range(0.001, 1e7));
  app.add_option("--mesh-dir", args->MeshDirectory,
    "where named meshes are (default $SURFACELOD_MESH_DIR or the build's TestData)")->type_name("DIR");
  app.add_option("-n,--samples", args->Samples, "deviation samples per surface (default 300000)")
    ->type_name("N")->check(CLI::Range(0LL, MaxCount));
  app.add_flag("--no-deviation", args->NoDeviation, "skip the Hausdorff/RMS measurement");
  app.add_flag("-j,--json", args->Json, "one JSON line per input and method (and per method with --scaling)");
  return [args] { return Bench(*args); };
}

struct BenchOptions
{
  std::vector<const Method*> Methods; // the baseline first
  std::vector<std::string> TargetArguments; // forwarded to `surfacelod simplify`
  int Repeat = 1;
  bool Interleave = false; // rounds of one run per method instead of each method's runs in a row
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
  double CpuSeconds = 0.0;    // of the fastest run: the work, whatever the machine's load
  double PeakMegabytes = 0.0; // of the child process
  double WorkingBytesPerInputPoint = std::numeric_limits<double>::quiet_NaN(); // beyond the input, largest run
  std::vector<double> RoundSeconds; // with --interleave: the filter's seconds in each round
  vtkIdType InputTriangles = 0, TargetTriangles = 0, OutputTriangles = 0;
  bool HasTarget = true; // false for a method that removes features of a size (no count to reach)
  bool TargetReached = false;
  bool HasDeviation = false;
  Deviation Distance;
  TopologySummary Topology;
};

// A number of the child's `simplify --json` line; NaN when the output is not that line or lacks it.
double JsonNumber(const std::string& output, const std::string& key)
{
  const Json line = Json::parse(output, nullptr, /*allow_exceptions=*/false);
  return line.is_object() && line.contains(key) && line[key].is_number() ? line[key].get<double>()
                                                                         : std::numeric_limits<double>::quiet_NaN();
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

// The `surfacelod simplify` command line of a row's method.
std::vector<std::string> ChildArguments(const BenchOptions& options, const std::string& inputPath,
  const std::string& outputPath, const BenchRow& row)
{
  std::vector<std::string> arguments = { CurrentExecutable(), "simplify", inputPath, outputPath, "--method",
    row.Run->Name, "--json" };
  arguments.insert(arguments.end(), options.TargetArguments.begin(), options.TargetArguments.end());
  return arguments;
}

// One run of a row's method in a child process; keeps the fastest run's times and the largest
// memory. Returns false (status and message set) when the run failed or timed out.
bool RunOnceInChild(const BenchOptions& options, const std::vector<std::string>& arguments, bool first, BenchRow& row)
{
  const ChildResult child = RunChildProcess(arguments, options.TimeoutSeconds);
  if (child.TimedOut || !child.Started || child.ExitCode != 0)
  {
    row.Status = child.TimedOut ? "timeout" : "failed";
    row.Message = child.TimedOut ? "over " + FormatReal(options.TimeoutSeconds) + " s"
                                 : LastLine(child.Started ? child.Errors : child.Output);
    return false;
  }
  const double seconds = JsonNumber(child.Output, "seconds");
  if (!std::isfinite(seconds))
  {
    row.Status = "failed";
    row.Message = "no timing in the output of simplify";
    return false;
  }
  if (first || seconds < row.Seconds)
  {
    row.Seconds = seconds;
    row.CpuSeconds = JsonNumber(child.Output, "cpu_seconds");
  }
  if (options.Interleave)
  {
    row.RoundSeconds.push_back(seconds);
  }
  row.PeakMegabytes = std::max(row.PeakMegabytes, JsonNumber(child.Output, "peak_rss_mb"));
  const double working = JsonNumber(child.Output, "working_rss_mb") * 1048576.0 / JsonNumber(child.Output, "input_points");
  if (std::isfinite(working) && !(working <= row.WorkingBytesPerInputPoint))
  {
    row.WorkingBytesPerInputPoint = working;
  }
  return true;
}

// A row for one method on one input, not yet run.
BenchRow MakeBenchRow(const std::string& inputName, const MethodSettings& settings, const Method& method)
{
  BenchRow row;
  row.Input = inputName;
  row.Run = &method;
  row.InputTriangles = settings.InputTriangles;
  row.HasTarget = method.NeedsTarget;
  row.TargetTriangles = settings.TargetTriangles > 0
    ? settings.TargetTriangles
    : vtkIdType(std::llround(double(settings.InputTriangles) * (1.0 - settings.ReductionFraction())));
  return row;
}

std::string BenchOutputPath(const BenchOptions& options, const BenchRow& row)
{
  return options.WorkDirectory + "/" + row.Run->Name + ".vtp";
}

// The last run's output of a row that ran: its count, topology and deviation from the input.
void MeasureBenchOutput(const BenchOptions& options, vtkPolyData* input, BenchRow& row)
{
  if (row.Status != "ok")
  {
    return;
  }
  const std::string outputPath = BenchOutputPath(options, row);
  vtkSmartPointer<vtkPolyData> output = TriangulatedSurface(ReadMesh(outputPath));
  row.OutputTriangles = CountTriangles(output);
  row.TargetReached = row.OutputTriangles <= row.TargetTriangles + row.TargetTriangles / 100 + 1;
  row.Topology = SummarizeTopology(output, outputPath);
  if (options.Deviation && row.OutputTriangles > 0)
  {
    row.Distance = MeasureDeviation(input, output, options.Samples, true);
    row.HasDeviation = true;
  }
}

// value / baseline, or NaN when either is missing.
double RatioTo(double value, double baseline)
{
  return baseline > 0 && std::isfinite(baseline) && std::isfinite(value) ? value / baseline
                                                                          : std::numeric_limits<double>::quiet_NaN();
}

// The method's time over the baseline's: with --interleave the median of the rounds' ratios,
// else the ratio of the fastest runs.
double TimeRatio(const BenchRow& row, const BenchRow& baseline)
{
  if (row.Status != "ok" || baseline.Status != "ok")
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const size_t rounds = row.RoundSeconds.size();
  if (rounds < 2 || baseline.RoundSeconds.size() != rounds)
  {
    return RatioTo(row.Seconds, baseline.Seconds);
  }
  std::vector<double> ratios(rounds);
  for (size_t r = 0; r < rounds; ++r)
  {
    ratios[r] = RatioTo(row.RoundSeconds[r], baseline.RoundSeconds[r]);
  }
  std::sort(ratios.begin(), ratios.end());
  return rounds % 2 ? ratios[rounds / 2] : 0.5 * (ratios[rounds / 2 - 1] + ratios[rounds / 2]);
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
            << Padded("seconds", 9, true) << Padded("cpu s", 9, true) << Padded("Mtri/s", 8, true) << Padded("t/quad", 8, true)
            << Padded("hausdorff", 11, true) << Padded("H/quad", 8, true) << Padded("chi", 9, true)
            << Padded("loops", 7, true) << Padded("nm-e", 7, true) << Padded("B/vert", 8, true) << "\n";
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
  std::cout << Padded(std::to_string(row.OutputTriangles), 9, true) << Padded(!row.HasTarget ? "-" : row.TargetReached ? "yes" : "no", 7, true)
            << Padded(Fixed(row.Seconds, 3), 9, true)
            << Padded(std::isfinite(row.CpuSeconds) ? Fixed(row.CpuSeconds, 3) : "-", 9, true)
            << Padded(row.Seconds > 0 ? Fixed(1e-6 * double(row.InputTriangles) / row.Seconds, 2) : "-", 8, true)
            << Padded(RatioText(TimeRatio(row, baseline)), 8, true)
            << Padded(deviation ? Scientific(row.Distance.Hausdorff) : "-", 11, true)
            << Padded(deviation && baseline.HasDeviation
                   ? RatioText(RatioTo(row.Distance.Hausdorff, baseline.Distance.Hausdorff)) : "-", 8, true)
            << Padded(std::to_string(row.Topology.Euler), 9, true)
            << Padded(std::to_string(row.Topology.BorderLoops), 7, true)
            << Padded(std::to_string(row.Topology.NonManifoldEdges), 7, true)
            << Padded(std::isfinite(row.WorkingBytesPerInputPoint) ? Fixed(row.WorkingBytesPerInputPoint, 0) : "-", 8, true)
            << std::endl;
}

// An integer when measured, else null (as the topology of a failed run).
Json CountOrNull(long long value, bool measured)
{
  return measured ? Json(value) : Json(nullptr);
}

void PrintRowJson(const BenchRow& row, const BenchRow& baseline, const TopologySummary& input)
{
  const bool ok = row.Status == "ok";
  const double baselineSeconds = baseline.Status == "ok" ? baseline.Seconds : 0.0;
  Json line = { { "input", row.Input }, { "method", row.Run->Name }, { "status", row.Status },
    { "input_triangles", row.InputTriangles }, { "target_triangles", row.TargetTriangles },
    { "output_triangles", CountOrNull(row.OutputTriangles, ok) }, { "target_reached", row.HasTarget ? Json(int(ok && row.TargetReached)) : Json() },
    { "seconds", NumberOrNull(row.Seconds, ok) }, { "cpu_seconds", NumberOrNull(row.CpuSeconds, ok) },
    { "input_triangles_per_second", NumberOrNull(double(row.InputTriangles) / row.Seconds, ok && row.Seconds > 0) },
    { "baseline_seconds", NumberOrNull(baselineSeconds, baselineSeconds > 0) },
    { "speedup_vs_vtk_quadric", NumberOrNull(1.0 / TimeRatio(row, baseline), ok) },
    { "time_ratio_vs_vtk_quadric", NumberOrNull(TimeRatio(row, baseline), ok) },
    { "hausdorff", NumberOrNull(row.Distance.Hausdorff, row.HasDeviation) },
    { "rms", NumberOrNull(row.Distance.RMS, row.HasDeviation) },
    { "hausdorff_ratio_vs_vtk_quadric", NumberOrNull(RatioTo(row.Distance.Hausdorff, baseline.Distance.Hausdorff),
      row.HasDeviation && baseline.HasDeviation) },
    { "input_euler", input.Euler }, { "input_border_loops", input.BorderLoops },
    { "input_nonmanifold_edges", input.NonManifoldEdges },
    { "output_euler", CountOrNull(row.Topology.Euler, ok) },
    { "output_border_loops", CountOrNull(row.Topology.BorderLoops, ok) },
    { "output_nonmanifold_edges", CountOrNull(row.Topology.NonManifoldEdges, ok) },
    { "peak_rss_mb", NumberOrNull(row.PeakMegabytes, ok) },
    { "working_bytes_per_input_point", NumberOrNull(row.WorkingBytesPerInputPoint, ok) },
    { "load_average", NumberOrNull(OneMinuteLoad()) } };
  if (!ok)
  {
    line["message"] = row.Message;
  }
  if (!row.RoundSeconds.empty())
  {
    line["round_seconds"] = row.RoundSeconds;
  }
  PrintJson(line);
}

// Runs the rows' methods --repeat times: each method's runs in a row, or with --interleave in
// rounds of one run per method (a method that failed runs no more).
void RunBenchRows(const BenchOptions& options, const std::string& inputPath, std::vector<BenchRow>& rows)
{
  const int rounds = options.Interleave ? options.Repeat : 1;
  const int runsPerRound = options.Interleave ? 1 : options.Repeat;
  for (int round = 0; round < rounds; ++round)
  {
    for (BenchRow& row : rows)
    {
      const std::vector<std::string> arguments = ChildArguments(options, inputPath, BenchOutputPath(options, row), row);
      for (int r = 0; r < runsPerRound && row.Status == "ok"; ++r)
      {
        RunOnceInChild(options, arguments, round + r == 0, row);
      }
    }
  }
}

// Every method on one input; returns the rows (the baseline's first).
std::vector<BenchRow> BenchInput(const BenchOptions& options, const TargetArguments& target, const std::string& name,
  const std::string& meshDir)
{
  vtkSmartPointer<vtkPolyData> input = ResolveBenchInput(name, meshDir);
  const MethodSettings settings = TargetSettings(target, CountTriangles(input), false, 0.9, "bench");
  const TopologySummary topology = SummarizeTopology(input, name);
  PrintInputLine(name, topology, options);
  const std::string inputPath = options.WorkDirectory + "/input.vtp";
  WriteMesh(input, inputPath);
  std::vector<BenchRow> rows;
  for (const Method* method : options.Methods)
  {
    rows.push_back(MakeBenchRow(name, settings, *method));
  }
  // Without --interleave each method runs and is printed before the next one starts.
  const size_t batch = options.Interleave ? rows.size() : 1;
  for (size_t first = 0; first < rows.size(); first += batch)
  {
    std::vector<BenchRow> part(rows.begin() + first, rows.begin() + first + batch);
    RunBenchRows(options, inputPath, part);
    for (size_t k = 0; k < batch; ++k)
    {
      rows[first + k] = std::move(part[k]);
      MeasureBenchOutput(options, input, rows[first + k]);
      options.Json ? PrintRowJson(rows[first + k], rows.front(), topology) : PrintRowText(rows[first + k], rows.front());
    }
  }
  return rows;
}

// time(third input) / time(second input) per method after a --scaling run (4M / 1M triangles),
// by wall time and by CPU time (the CPU ratio is the one that a loaded machine does not distort).
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
    std::cout << Padded("ratio", 8, true) << Padded("cpu ratio", 10, true) << "\n";
  }
  for (size_t m = 0; m < options.Methods.size(); ++m)
  {
    const BenchRow& middle = perInput[1][m];
    const BenchRow& large = perInput[2][m];
    const bool ok = large.Status == "ok" && middle.Status == "ok";
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double ratio = ok ? RatioTo(large.Seconds, middle.Seconds) : nan;
    const double cpuRatio = ok ? RatioTo(large.CpuSeconds, middle.CpuSeconds) : nan;
    if (options.Json)
    {
      PrintJson({ { "scaling", options.Methods[m]->Name }, { "ratio_of", largeName + " / " + middleName },
        { "time_ratio", NumberOrNull(ratio) }, { "cpu_time_ratio", NumberOrNull(cpuRatio) } });
      continue;
    }
    std::cout << Padded(options.Methods[m]->Name, 28);
    for (const std::vector<BenchRow>& rows : perInput)
    {
      std::cout << Padded(rows[m].Status == "ok" ? Fixed(rows[m].Seconds, 3) : rows[m].Status, 14, true);
    }
    std::cout << Padded(RatioText(ratio), 8, true) << Padded(RatioText(cpuRatio), 10, true) << "\n";
  }
}

// The inputs asked for: --scaling, --set, --inputs (or the default), then every --input.
std::vector<std::string> BenchInputNames(const BenchArguments& args)
{
  std::vector<std::string> names;
  if (args.Scaling)
  {
    names = ScalingInputSet(args.ScalingResolutions);
  }
  else if (!args.InputSet.empty())
  {
    names = RealInputSet(); // the only set (checked by the option)
  }
  else if (!args.Inputs.empty() || args.Files.empty())
  {
    names = args.Inputs.empty() ? std::vector<std::string>{ "synthetic:500" } : args.Inputs;
  }
  names.insert(names.end(), args.Files.begin(), args.Files.end());
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

BenchOptions MakeBenchOptions(const BenchArguments& args)
{
  BenchOptions options;
  options.Repeat = args.Repeat;
  options.Interleave = args.Interleave;
  options.TimeoutSeconds = args.TimeoutSeconds;
  options.Samples = args.Samples;
  options.Deviation = !args.NoDeviation;
  options.Json = args.Json;
  options.TargetArguments = args.Target.Triangles > 0
    ? std::vector<std::string>{ "--target-triangles", std::to_string(args.Target.Triangles) }
    : std::vector<std::string>{ "--target-reduction",
        FormatReal(args.Target.Reduction >= 0 ? args.Target.Reduction : 0.9, 17) };
  options.Methods = SelectMethods(args.MethodNames);
  // The baseline runs first so every ratio is measured in the same run.
  const Method* baseline = FindMethod(BaselineMethod);
  options.Methods.erase(std::remove(options.Methods.begin(), options.Methods.end(), baseline), options.Methods.end());
  options.Methods.insert(options.Methods.begin(), baseline);
  return options;
}

int Bench(const BenchArguments& args)
{
  BenchOptions options = MakeBenchOptions(args);
  const std::vector<std::string> inputs = BenchInputNames(args);
  std::string meshDir = args.MeshDirectory;
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
    perInput.push_back(BenchInput(options, args.Target, name, meshDir));
  }
  if (args.Scaling)
  {
    PrintScaling(perInput, options);
  }
  return ExitSuccess;
}

// ---------------------------------------------------------------------------------------------
// methods, help, dispatch

std::string MethodsDescription()
{
  return "List the simplification methods; with --verbose, each one's parameters (type and the tool's\n"
         "default) that `surfacelod simplify ... --set Name=Value` changes.";
}

int ListMethods(bool verbose)
{
  for (const Method& m : Methods())
  {
    std::cout << Padded(m.Name, 30) << m.Description << (m.SupportsMaximumError ? "" : " [no --max-error]")
              << (m.InDefaultRuns ? "" : " [demo/bench only with --methods]") << "\n";
    for (const Parameter& p : verbose ? m.Parameters : std::vector<Parameter>())
    {
      std::cout << "    " << Padded(p.Name, 34) << Padded(ParameterTypeName(p.Type), 8) << ParameterDefault(m, p)
                << "\n";
    }
  }
  return ExitSuccess;
}

std::function<int()> DefineMethods(CLI::App& app)
{
  auto verbose = std::make_shared<bool>(false);
  app.add_flag("-v,--verbose", *verbose, "also list each method's parameters: name, type (bool, int, double), default");
  return [verbose] { return ListMethods(*verbose); };
}

struct Command
{
  const char* Name;
  const char* Usage; // after "surfacelod NAME"
  const char* Summary;
  std::string (*Description)();
  std::function<int()> (*Define)(CLI::App&); // adds the options; returns the run
};

const std::vector<Command>& Commands()
{
  static const std::vector<Command> commands = {
    { "simplify", "INPUT OUTPUT -m NAME (-t N | -r R | -e E | -l L) [-s Name=Value]... [options]",
      "simplify a mesh file with a chosen method and target", &SimplifyDescription, &DefineSimplify },
    { "compare", "A B [-n N] [-j]", "Hausdorff / mean / RMS distance between two surfaces", &CompareDescription,
      &DefineCompare },
    { "info", "FILE [-j]", "vertices, triangles, boundary, manifoldness, components, genus of a mesh",
      &InfoDescription, &DefineInfo },
    { "demo", "[--resolution N] [-o DIR] [-r R] [-m A,B,...] [-n N] [--no-cleaning] [--noisy-input FILE] [...]",
      "simplify a synthetic 1M-triangle surface with every method, table + picture; clean a noisy one", &DemoDescription, &DefineDemo },
    { "bench", "[--inputs a,b,... | --set real | --scaling] [-i FILE]... [-m a,b,...] [--timeout S] [-j]",
      "time methods against vtkQuadricDecimation on named inputs", &BenchDescription, &DefineBench },
    { "methods", "[-v]", "list the simplification methods (-v: their parameters)", &MethodsDescription,
      &DefineMethods },
  };
  return commands;
}

// `surfacelod COMMAND --help`: "usage: surfacelod COMMAND ...", the description, then the options.
class CommandHelp : public CLI::Formatter
{
public:
  explicit CommandHelp(const Command& command)
    : TheCommand(command)
  {
    this->column_width(34);
  }
  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode mode) const override
  {
    return std::string("usage: surfacelod ") + this->TheCommand.Name + " " + this->TheCommand.Usage + "\n\n" +
      app->get_description() + "\n" + this->make_groups(app, mode);
  }
  // "-t,--target-triangles N": the value's name only (the ranges, choices and exclusions are in the
  // option's own help text and in the one-line error).
  std::string make_option_opts(const CLI::Option* option) const override
  {
    const std::string name = option->get_type_name();
    return option->get_type_size() == 0 || name.empty() ? std::string() : " " + name.substr(0, name.find(':'));
  }

private:
  const Command& TheCommand;
};

// Parses the command's arguments and runs it; --help prints the help. A parse error is a
// CliError(ExitUsage) of one line.
int RunCommand(const Command& command, int argc, char* argv[])
{
  CLI::App app(command.Description(), command.Name);
  app.formatter(std::make_shared<CommandHelp>(command));
  const std::function<int()> run = command.Define(app);
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::CallForHelp&)
  {
    std::cout << app.help();
    return ExitSuccess;
  }
  catch (const CLI::ParseError& e)
  {
    std::string message = e.what();
    std::replace(message.begin(), message.end(), '\n', ' ');
    throw CliError(ExitUsage, "surfacelod " + std::string(command.Name) + ": " + message + " (see --help)");
  }
  return run();
}

void PrintUsage(std::ostream& out)
{
  out << "usage: surfacelod COMMAND [ARGS] (surfacelod COMMAND --help for details)\n\ncommands:\n";
  for (const Command& c : Commands())
  {
    out << "  " << Padded(c.Name, 10) << c.Summary << "\n";
  }
  out << "\nexit codes: 0 success, 1 wrong usage, 2 unusable file, 3 a filter failed\n";
}
} // namespace
int main(int argc, char* argv[])
{
  const MpiSession mpi(&argc, &argv); // several processes only when started by mpiexec
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
    if (DistributedController() && name != "simplify")
    {
      throw CliError(ExitUsage, "surfacelod " + name + ": only `simplify` runs on several processes (mpiexec)");
    }
    for (const Command& command : Commands())
    {
      if (name == command.Name)
      {
        return RunCommand(command, argc - 1, argv + 1); // argv[1], the command, as the program name
      }
    }
    std::cerr << "surfacelod: unknown command '" << name << "'\n";
    PrintUsage(std::cerr);
    return ExitUsage;
  }
  catch (const CliError& e)
  {
    std::cout.flush();
    if (ProcessRank() != 0) // every process fails together; rank 0 says why
    {
      return e.Code;
    }
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
