// SPDX-License-Identifier: BSD-3-Clause
#ifndef slodStageClock_h
#define slodStageClock_h

#include "vtkLogger.h"

#include <chrono>
#include <ctime>
#if defined(__unix__)
#include <time.h>
#endif

namespace slod
{
#if defined(__unix__)
// Seconds of a POSIX clock (CPU time of the process or the calling thread), or `fallback`
// where it cannot be read.
inline double PosixClockSeconds(clockid_t clock, double fallback)
{
  timespec now;
  return clock_gettime(clock, &now) == 0 ? double(now.tv_sec) + 1e-9 * double(now.tv_nsec) : fallback;
}
#endif

// Wall, process CPU and calling-thread CPU time of consecutive stages, logged at TRACE verbosity
// (`surfacelod --log-verbosity 9`). The calling thread's share of the CPU time tells how much of a
// stage ran on other threads even on a loaded machine, where the wall time says little. The
// clocks are read only when TRACE is logged (they are system calls).
class StageClock
{
public:
  explicit StageClock(const char* owner)
    : Owner(owner)
    , Enabled(vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE)
  {
    this->Restart();
  }

  void Restart()
  {
    if (this->Enabled)
    {
      this->Wall = std::chrono::steady_clock::now();
      this->Cpu = std::clock();
      this->Thread = ThreadSeconds();
    }
  }

  // Logs the time since the last lap (or the start) as `stage` and starts the next one.
  void Lap(const char* stage)
  {
    if (!this->Enabled)
    {
      return;
    }
    const auto wall = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    const double wallSeconds = std::chrono::duration<double>(wall - this->Wall).count();
    const double thread = ThreadSeconds();
    const double cpuSeconds = double(cpu - this->Cpu) / double(CLOCKS_PER_SEC);
    vtkLogF(TRACE, "%s: %s took %.3f s (CPU %.3f s, of which this thread %.3f s)", this->Owner, stage, wallSeconds,
      cpuSeconds, thread - this->Thread);
    this->Wall = wall;
    this->Cpu = cpu;
    this->Thread = thread;
  }

  // The calling thread's CPU time (0 where it cannot be read).
  static double ThreadSeconds()
  {
#if defined(__unix__)
    return PosixClockSeconds(CLOCK_THREAD_CPUTIME_ID, 0.0);
#else
    return 0.0;
#endif
  }

private:
  const char* Owner;
  bool Enabled;
  std::chrono::steady_clock::time_point Wall;
  std::clock_t Cpu = 0;
  double Thread = 0.0;
};

// Wall, process CPU and calling-thread CPU seconds summed over every visit of a stage that recurs
// (a level's stages).
struct StageTotal
{
  double Wall = 0.0;
  double Cpu = 0.0;
  double Thread = 0.0;
};

// Adds the wall, process CPU and calling-thread CPU time of its scope to a StageTotal; a null
// total (timing off) reads no clock.
class ScopedStageTime
{
public:
  explicit ScopedStageTime(StageTotal* total)
    : Total(total)
  {
    if (this->Total)
    {
      this->Wall = std::chrono::steady_clock::now();
      this->Cpu = ProcessSeconds();
      this->Thread = StageClock::ThreadSeconds();
    }
  }
  ~ScopedStageTime()
  {
    if (this->Total)
    {
      this->Total->Wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - this->Wall).count();
      this->Total->Cpu += ProcessSeconds() - this->Cpu;
      this->Total->Thread += StageClock::ThreadSeconds() - this->Thread;
    }
  }
  ScopedStageTime(const ScopedStageTime&) = delete;
  ScopedStageTime& operator=(const ScopedStageTime&) = delete;

  // The process's CPU time of all its threads.
  static double ProcessSeconds()
  {
    const double fallback = double(std::clock()) / double(CLOCKS_PER_SEC);
#if defined(__unix__)
    return PosixClockSeconds(CLOCK_PROCESS_CPUTIME_ID, fallback);
#else
    return fallback;
#endif
  }

private:
  StageTotal* Total;
  std::chrono::steady_clock::time_point Wall;
  double Cpu = 0.0;
  double Thread = 0.0;
};
} // namespace slod

#endif
