// SPDX-License-Identifier: BSD-3-Clause
// Small helpers of the `surfacelod` tool: errors with exit codes, number formatting, timing, peak
// memory and a terminal progress bar. (Options are parsed by CLI11, JSON written by nlohmann-json.)
#ifndef surfacelodCliSupport_h
#define surfacelodCliSupport_h

#include <chrono>
#include <stdexcept>
#include <string>

class vtkAlgorithm;

namespace slodcli
{
// Exit codes: 0 success, 1 wrong usage, 2 a file or its contents could not be used, 3 other failure.
enum ExitCode
{
  ExitSuccess = 0,
  ExitUsage = 1,
  ExitData = 2,
  ExitFailure = 3
};

// A failure reported to the user as one line on stderr, then exit with Code.
struct CliError : std::runtime_error
{
  CliError(int code, const std::string& message)
    : std::runtime_error(message)
    , Code(code)
  {
  }
  int Code;
};

std::string FormatReal(double value, int significant = 6);

// CPU seconds used so far by every thread of this process (NaN when the clock is missing).
double ProcessCpuSeconds();

// Wall time, and the process' CPU time: on a loaded machine the CPU time of a run still tells
// how much work it did, where its wall time also counts the time it waited for a core.
class Stopwatch
{
public:
  Stopwatch()
    : Start(std::chrono::steady_clock::now())
    , CpuStart(ProcessCpuSeconds())
  {
  }
  double Seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - this->Start).count();
  }
  double CpuSeconds() const { return ProcessCpuSeconds() - this->CpuStart; }

private:
  std::chrono::steady_clock::time_point Start;
  double CpuStart;
};

// Peak resident set size of this process in MiB (VmHWM, else getrusage).
double PeakResidentMegabytes();
// Resident set size now, in MiB (VmRSS; NaN when unknown).
double ResidentMegabytes();
// Makes the peak restart from the current resident size (Linux clear_refs); false when the system
// does not allow it (then PeakResidentMegabytes stays the peak since the start).
bool ResetPeakResident();

// Draws "label [#####     ]  45%" on stderr while the algorithm reports progress, only when
// stderr is a terminal. Detaches and clears the line when destroyed.
class ProgressBar
{
public:
  ProgressBar(vtkAlgorithm* algorithm, const std::string& label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void Draw(double fraction);

private:
  vtkAlgorithm* Algorithm = nullptr;
  unsigned long Tag = 0;
  std::string Label;
  int LastPercent = -1;
  bool Enabled = false;
};
} // namespace slodcli

#endif
