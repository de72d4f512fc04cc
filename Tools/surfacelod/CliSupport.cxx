// SPDX-License-Identifier: BSD-3-Clause
#include "CliSupport.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkNew.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

namespace slodcli
{
std::string FormatReal(double value, int significant)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

namespace
{
// A "Key: <n> kB" line of /proc/self/status in MiB; NaN when absent (not Linux).
double StatusMegabytes(const char* key)
{
  std::ifstream status("/proc/self/status");
  const size_t length = std::strlen(key);
  std::string line;
  while (std::getline(status, line))
  {
    if (line.compare(0, length, key) == 0)
    {
      return std::strtod(line.c_str() + length, nullptr) / 1024.0;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}
} // namespace

double PeakResidentMegabytes()
{
  const double peak = StatusMegabytes("VmHWM:");
  if (std::isfinite(peak))
  {
    return peak;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0; // kB on Linux
}

double ProcessCpuSeconds()
{
  timespec now{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now) != 0)
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

double ResidentMegabytes()
{
  return StatusMegabytes("VmRSS:");
}

bool ResetPeakResident()
{
  std::ofstream("/proc/self/clear_refs") << "5"; // Linux: VmHWM := VmRSS
  const double peak = StatusMegabytes("VmHWM:"), resident = StatusMegabytes("VmRSS:");
  return std::isfinite(peak) && std::isfinite(resident) && peak <= resident + 1.0;
}

namespace
{
void OnProgress(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* bar = static_cast<ProgressBar*>(clientData);
  bar->Draw(static_cast<vtkAlgorithm*>(caller)->GetProgress());
}
} // namespace

ProgressBar::ProgressBar(vtkAlgorithm* algorithm, const std::string& label)
  : Algorithm(algorithm)
  , Label(label)
  , Enabled(algorithm && isatty(STDERR_FILENO))
{
  if (this->Enabled)
  {
    vtkNew<vtkCallbackCommand> callback;
    callback->SetCallback(OnProgress);
    callback->SetClientData(this);
    this->Tag = algorithm->AddObserver(vtkCommand::ProgressEvent, callback);
  }
}

ProgressBar::~ProgressBar()
{
  if (this->Enabled)
  {
    this->Algorithm->RemoveObserver(this->Tag);
    if (this->LastPercent >= 0)
    {
      std::fprintf(stderr, "\r%*s\r", static_cast<int>(this->Label.size()) + 40, "");
      std::fflush(stderr);
    }
  }
}

void ProgressBar::Draw(double fraction)
{
  const int percent = static_cast<int>(std::lround(100.0 * std::min(1.0, std::max(0.0, fraction))));
  if (percent == this->LastPercent)
  {
    return;
  }
  this->LastPercent = percent;
  constexpr int width = 30;
  const int filled = percent * width / 100;
  std::fprintf(stderr, "\r%s [%s%s] %3d%%", this->Label.c_str(), std::string(size_t(filled), '#').c_str(),
    std::string(size_t(width - filled), ' ').c_str(), percent);
  std::fflush(stderr);
}
} // namespace slodcli
