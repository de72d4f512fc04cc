// SPDX-License-Identifier: BSD-3-Clause
// Every category of the bad-input corpus (BadInputCorpus.h) through every filter, each run in a
// child process under a CPU-time limit: no crash, no hang, and either a clear error (vtkErrorMacro) with
// an empty output or a valid output (see slodtest::CheckFilterOutput). One test per filter; each
// prints its runs, crashes, hangs and invalid outputs, and fails naming every failing category.
//
// The same program serves the command-line test (Testing/Python/cli_test.py):
//   TestBadInputCorpus --run FILTER CATEGORY      one run (what the test's children do)
//   TestBadInputCorpus --write-corpus DIRECTORY   writes the corpus files, prints "KIND PATH" lines
//   TestBadInputCorpus --check-outputs [--may-open|--baseline] CATEGORY FILE...  checks a tool's output files
//     (--baseline: a VTK filter the tool compares with; no topology promise, the rest is checked)
#include "BadInputCorpus.h"
#include "TestSupport.h"

#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkLODInterpolation.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkRetileLevelInterpolation.h"
#include "vtkSurfaceDeviation.h"
#include "vtkTriangleCollapseHierarchy.h"

#include "vtkNew.h"
#include "vtkXMLPolyDataReader.h"

#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using slodtest::BadInput;
using slodtest::OutputExpectations;

namespace
{
struct FilterRun
{
  vtkSmartPointer<vtkPolyData> Output;
  int Errors = 0;
  std::vector<std::string> Problems; // the filter's own properties (e.g. a distance of a surface to itself)
};

// Runs `filter` on its inputs with its messages collected (and so not printed).
template <typename Filter>
FilterRun Execute(Filter* filter)
{
  vtkNew<slodtest::MessageCounter> messages;
  filter->AddObserver(vtkCommand::ErrorEvent, messages);
  filter->AddObserver(vtkCommand::WarningEvent, messages);
  filter->Update();
  FilterRun run;
  run.Output = filter->GetOutput();
  run.Errors = static_cast<int>(messages->Errors.size());
  return run;
}

template <typename Filter>
FilterRun Simplify(vtkPolyData* input)
{
  vtkNew<Filter> filter;
  filter->SetInputData(input);
  filter->SetTargetReduction(0.5);
  return Execute(filter.Get());
}

FilterRun SelfDeviation(vtkPolyData* input)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(input);
  deviation->SetComparedData(input);
  deviation->SetNumberOfSamples(2000);
  FilterRun run = Execute(deviation.Get());
  if (run.Errors > 0 || slodtest::CountSurface(input).TrianglesWithArea == 0)
  {
    return run;
  }
  // Closest points are computed in double: far from the origin a few units in the last place of
  // the coordinates are the best achievable distance of a point to its own surface.
  double bounds[6];
  input->GetBounds(bounds);
  double largest = 0;
  for (double b : bounds)
  {
    largest = std::max(largest, std::abs(b));
  }
  const double diagonal = deviation->GetBoundingBoxDiagonal();
  const double tolerance = 1e-9 + 64 * std::numeric_limits<double>::epsilon() * largest / diagonal;
  if (!(deviation->GetHausdorffRelative() <= tolerance))
  {
    char text[160];
    std::snprintf(text, sizeof(text), "relative distance of a surface to itself %g (tolerance %g)",
      deviation->GetHausdorffRelative(), tolerance);
    run.Problems.push_back(text);
  }
  return run;
}

FilterRun InterpolateWithItself(vtkPolyData* input)
{
  vtkNew<vtkLODInterpolation> interpolation;
  interpolation->SetDetailedData(input);
  interpolation->SetCoarseData(input);
  interpolation->SetT(0.5);
  return Execute(interpolation.Get());
}

FilterRun RetileLevelsOfItself(vtkPolyData* input)
{
  vtkNew<vtkRetileLevelInterpolation> interpolation;
  interpolation->SetHighDetailData(input);
  interpolation->SetLowDetailData(input);
  interpolation->SetT(0.5);
  return Execute(interpolation.Get());
}

// Collapse to half with records, then every vertex split back: the input rebuilt.
FilterRun ProgressiveRoundTrip(vtkPolyData* input)
{
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(input);
  collapse->SetTargetReduction(0.5);
  collapse->GenerateProgressiveMeshOn();
  vtkNew<slodtest::MessageCounter> collapseMessages;
  collapse->AddObserver(vtkCommand::ErrorEvent, collapseMessages);
  collapse->AddObserver(vtkCommand::WarningEvent, collapseMessages);
  vtkNew<vtkProgressiveMeshReconstruction> reconstruction;
  reconstruction->SetCoarseMeshConnection(collapse->GetOutputPort(0));
  reconstruction->SetRecordsConnection(collapse->GetOutputPort(1));
  reconstruction->SetNumberOfVertexSplits(-1);
  FilterRun run = Execute(reconstruction.Get());
  run.Errors += static_cast<int>(collapseMessages->Errors.size());
  return run;
}

struct FilterUnderTest
{
  const char* Name;
  FilterRun (*Run)(vtkPolyData*);
  OutputExpectations Expect;
  bool OutputIsASurface = true; // vtkSurfaceDeviation passes its compared input through
};

const std::vector<FilterUnderTest>& Filters()
{
  OutputExpectations simplifier;
  OutputExpectations topology = simplifier;
  topology.MayOpen = true; // hole and bump removal changes the topology on purpose
  OutputExpectations noPointData = simplifier;
  noPointData.CarriesPointData = false;
  static const std::vector<FilterUnderTest> filters = {
    { "vtkQuadricTriangleCollapse", Simplify<vtkQuadricTriangleCollapse>, simplifier },
    { "vtkTriangleCollapseHierarchy", Simplify<vtkTriangleCollapseHierarchy>, simplifier },
    { "vtkPatchBoundaryMerge", Simplify<vtkPatchBoundaryMerge>, simplifier },
    { "vtkGreedyCutsSimplification", Simplify<vtkGreedyCutsSimplification>, simplifier },
    { "vtkHoleBumpRemoval", Simplify<vtkHoleBumpRemoval>, topology },
    { "vtkRetile", Simplify<vtkRetile>, simplifier },
    { "vtkSurfaceDeviation", SelfDeviation, simplifier, false },
    { "vtkLODInterpolation", InterpolateWithItself, simplifier },
    { "vtkProgressiveMeshReconstruction", ProgressiveRoundTrip, noPointData },
    { "vtkRetileLevelInterpolation", RetileLevelsOfItself, noPointData },
  };
  return filters;
}

const FilterUnderTest* FindFilter(const std::string& name)
{
  for (const FilterUnderTest& f : Filters())
  {
    if (name == f.Name)
      return &f;
  }
  return nullptr;
}

// The child's side: one filter on one category; prints RAN after the filter, PROBLEM lines, DONE.
int RunOne(const std::string& filterName, const std::string& category)
{
  const FilterUnderTest* filter = FindFilter(filterName);
  if (!filter)
  {
    std::cout << "PROBLEM unknown filter " << filterName << std::endl;
    return 1;
  }
  const BadInput input = slodtest::MakeBadInput(category);
  FilterRun run = filter->Run(input.Surface);
  std::cout << "RAN" << std::endl;
  std::vector<std::string> problems = run.Problems;
  if (filter->OutputIsASurface)
  {
    const std::vector<std::string> more = slodtest::CheckFilterOutput(input, run.Output, run.Errors, filter->Expect);
    problems.insert(problems.end(), more.begin(), more.end());
  }
  else if (run.Errors == 0 && input.Unusable)
  {
    problems.push_back("no error on an input with non-finite coordinates");
  }
  for (const std::string& p : problems)
  {
    std::cout << "PROBLEM " << p << std::endl;
  }
  std::cout << "DONE" << std::endl;
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The parent's side: a child process per run, killed at the time-out.

enum class Verdict
{
  Ok,
  Crash,
  Hang,
  Invalid
};

struct Outcome
{
  Verdict Result = Verdict::Ok;
  std::string Detail;
  double Seconds = 0;
};

// A run is a hang when it uses more than this much CPU time (not wall time, which depends far more
// on the load); a run blocked without using the CPU is stopped after six times as long in wall time.
// The slowest legitimate run (retile on the valence-5,000 cone) takes 7.0 s of CPU alone and 7.9 s
// beside another corpus run (shared caches): 30 s keeps a wide margin and still catches a hang.
double CPULimitSeconds()
{
  const char* value = std::getenv("SURFACELOD_CORPUS_CPU_LIMIT");
  return value ? std::atof(value) : 30.0;
}

std::string SelfPath()
{
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof(path) - 1);
  return n > 0 ? std::string(path, size_t(n)) : std::string();
}

// Reads the child's output until it closes it or the deadline passes; false on time-out.
bool ReadUntil(int fd, std::chrono::steady_clock::time_point deadline, std::string& text)
{
  char buffer[4096];
  for (;;)
  {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      return false;
    pollfd p = { fd, POLLIN, 0 };
    if (poll(&p, 1, static_cast<int>(left.count())) <= 0)
      continue; // time-out is checked above; EINTR retried
    const ssize_t n = read(fd, buffer, sizeof(buffer));
    if (n <= 0)
      return true;
    text.append(buffer, size_t(n));
  }
}

Outcome Judge(const std::string& text, int status)
{
  Outcome outcome;
  const bool ran = text.find("RAN\n") != std::string::npos, done = text.find("DONE\n") != std::string::npos;
  if (!done || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
  {
    outcome.Result = Verdict::Crash;
    outcome.Detail = WIFSIGNALED(status) ? std::string("signal ") + strsignal(WTERMSIG(status))
                                         : "exit " + std::to_string(WEXITSTATUS(status));
    outcome.Detail += ran ? " in the test's checks after the filter" : " in the filter";
    const size_t tail = text.size() > 600 ? text.size() - 600 : 0;
    outcome.Detail += "; last output: " + text.substr(tail);
    return outcome;
  }
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line))
  {
    if (line.compare(0, 8, "PROBLEM ") == 0)
    {
      outcome.Result = Verdict::Invalid;
      outcome.Detail += (outcome.Detail.empty() ? "" : "; ") + line.substr(8);
    }
  }
  return outcome;
}

Outcome RunInChild(const std::string& filter, const std::string& category)
{
  int pipeFds[2];
  if (pipe(pipeFds) != 0)
    return { Verdict::Crash, "pipe failed", 0 };
  const std::string self = SelfPath();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0)
  {
    // SIGXCPU at the limit, SIGKILL a second later if it is ignored.
    const rlim_t limit = static_cast<rlim_t>(std::ceil(CPULimitSeconds()));
    const rlimit cpu = { limit, limit + 1 };
    setrlimit(RLIMIT_CPU, &cpu);
    dup2(pipeFds[1], STDOUT_FILENO);
    dup2(pipeFds[1], STDERR_FILENO);
    close(pipeFds[0]);
    close(pipeFds[1]);
    execl(self.c_str(), self.c_str(), "--run", filter.c_str(), category.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipeFds[1]);
  std::string text;
  const auto deadline = start + std::chrono::duration<double>(6 * CPULimitSeconds());
  const bool finished = ReadUntil(pipeFds[0], std::chrono::time_point_cast<std::chrono::steady_clock::duration>(deadline), text);
  if (!finished)
  {
    kill(pid, SIGKILL);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(pipeFds[0]);
  Outcome outcome = finished ? Judge(text, status)
                             : Outcome{ Verdict::Hang, "no result after " + std::to_string(6 * CPULimitSeconds()) + " s", 0 };
  if (finished && WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL))
  {
    outcome = { Verdict::Hang, "more than " + std::to_string(CPULimitSeconds()) + " s of CPU time", 0 };
  }
  outcome.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}
} // namespace

class BadInputCorpus : public ::testing::TestWithParam<std::string>
{
};

TEST_P(BadInputCorpus, EveryCategoryGivesAnErrorOrAValidOutput)
{
  const std::string filter = GetParam();
  int runs = 0, crashes = 0, hangs = 0, invalid = 0;
  double slowest = 0;
  std::string slowestCategory;
  for (const std::string& category : slodtest::BadInputNames())
  {
    const Outcome outcome = RunInChild(filter, category);
    ++runs;
    crashes += outcome.Result == Verdict::Crash;
    hangs += outcome.Result == Verdict::Hang;
    invalid += outcome.Result == Verdict::Invalid;
    static const char* const verdictNames[] = { "ok", "CRASH", "HANG", "INVALID" };
    if (outcome.Result != Verdict::Ok)
    {
      ADD_FAILURE() << filter << " x " << category << ": " << verdictNames[int(outcome.Result)] << ": " << outcome.Detail;
    }
    if (outcome.Seconds > slowest)
    {
      slowest = outcome.Seconds;
      slowestCategory = category;
    }
  }
  std::printf("[corpus] %s: %d runs, %d crashes, %d hangs, %d invalid outputs (slowest: %s, %.2f s)\n",
    filter.c_str(), runs, crashes, hangs, invalid, slowestCategory.c_str(), slowest);
}

namespace
{
std::vector<std::string> FilterNames()
{
  std::vector<std::string> names;
  for (const FilterUnderTest& f : Filters())
  {
    names.push_back(f.Name);
  }
  return names;
}

int WriteCorpus(const std::string& directory)
{
  for (const std::string& path : slodtest::WriteBadInputFiles(directory))
  {
    const std::string file = path.substr(path.rfind('/') + 1);
    std::string kind = "broken";
    if (file.compare(0, 7, "broken-") != 0)
    {
      const BadInput input = slodtest::MakeBadInput(file.substr(0, file.rfind('.')));
      kind = input.Unusable ? "unusable" : "category";
    }
    std::cout << kind << " " << path << "\n";
  }
  return 0;
}

// Output files of a command-line tool, one per category: valid surfaces (no point data required).
// Prints "CATEGORY: problem" lines.
int CheckOutputFiles(const std::vector<std::string>& categoryFilePairs, const std::string& mode)
{
  OutputExpectations expect;
  expect.CarriesPointData = false;
  expect.MayOpen = mode == "--may-open" || mode == "--baseline";
  expect.MayAddNonManifoldEdges = mode == "--baseline";
  bool ok = true;
  for (size_t i = 0; i + 1 < categoryFilePairs.size(); i += 2)
  {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(categoryFilePairs[i + 1].c_str());
    reader->Update();
    for (const std::string& p : slodtest::CheckFilterOutput(slodtest::MakeBadInput(categoryFilePairs[i]), reader->GetOutput(), 0, expect))
    {
      std::cout << categoryFilePairs[i] << ": " << p << "\n";
      ok = false;
    }
  }
  return ok ? 0 : 1;
}
} // namespace

INSTANTIATE_TEST_SUITE_P(Filters, BadInputCorpus, ::testing::ValuesIn(FilterNames()),
  [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

int main(int argc, char** argv)
{
  if (argc == 4 && std::strcmp(argv[1], "--run") == 0)
  {
    return RunOne(argv[2], argv[3]);
  }
  if (argc == 3 && std::strcmp(argv[1], "--write-corpus") == 0)
  {
    return WriteCorpus(argv[2]);
  }
  if (argc >= 2 && std::strcmp(argv[1], "--check-outputs") == 0)
  {
    const std::string mode = argc >= 3 && std::strncmp(argv[2], "--", 2) == 0 ? argv[2] : "";
    return CheckOutputFiles(std::vector<std::string>(argv + (mode.empty() ? 2 : 3), argv + argc), mode);
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
