// SPDX-License-Identifier: BSD-3-Clause
// Runs a program as a child process with a wall-clock limit (the bench runs every method this
// way, so that a slow or hanging method is stopped and reported instead of stalling the run).
#ifndef surfacelodChildProcess_h
#define surfacelodChildProcess_h

#include <string>
#include <vector>

namespace slodcli
{
struct ChildResult
{
  bool Started = false;  // false: fork/exec failed (Output says why)
  bool TimedOut = false; // killed at the limit
  int ExitCode = -1;     // when it exited normally; -1 when killed by a signal
  std::string Output;    // its stdout
  std::string Errors;    // its stderr
  double Seconds = 0.0;  // wall-clock time until it ended or was killed
};

// Runs arguments[0] (a path) with the arguments; kills it (SIGKILL) after timeoutSeconds.
ChildResult RunChildProcess(const std::vector<std::string>& arguments, double timeoutSeconds);

// The path of the running executable (/proc/self/exe).
std::string CurrentExecutable();
} // namespace slodcli

#endif
