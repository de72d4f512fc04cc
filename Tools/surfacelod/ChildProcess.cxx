// SPDX-License-Identifier: BSD-3-Clause
#include "ChildProcess.h"

#include "CliSupport.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace slodcli
{
namespace
{
// Reads what is available on fd into text; returns false at end of file (or on an error).
bool DrainPipe(int fd, std::string& text)
{
  char buffer[4096];
  const ssize_t n = read(fd, buffer, sizeof(buffer));
  if (n > 0)
  {
    text.append(buffer, size_t(n));
    return true;
  }
  return n < 0 && (errno == EINTR || errno == EAGAIN);
}

// Collects the child's stdout and stderr until both close or the deadline passes.
// Returns false when the deadline passed first.
bool CollectUntilClosed(int outFd, int errFd, const Stopwatch& watch, double timeoutSeconds, ChildResult& result)
{
  struct pollfd fds[2] = { { outFd, POLLIN, 0 }, { errFd, POLLIN, 0 } };
  std::string* sinks[2] = { &result.Output, &result.Errors };
  int open = 2;
  while (open > 0)
  {
    const double remaining = timeoutSeconds - watch.Seconds();
    if (remaining <= 0)
    {
      return false;
    }
    const int waitMs = int(std::min(remaining * 1000.0 + 1.0, double(INT_MAX / 2)));
    const int ready = poll(fds, 2, waitMs);
    if (ready < 0 && errno != EINTR)
    {
      return true; // poll failed: stop collecting, waitpid below still reaps the child
    }
    for (int f = 0; f < 2 && ready > 0; ++f)
    {
      if (fds[f].fd >= 0 && (fds[f].revents & (POLLIN | POLLHUP | POLLERR)) && !DrainPipe(fds[f].fd, *sinks[f]))
      {
        fds[f].fd = -1; // poll ignores negative descriptors
        --open;
      }
    }
  }
  return true;
}
} // namespace

std::string CurrentExecutable()
{
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof(path) - 1);
  return n > 0 ? std::string(path, size_t(n)) : std::string();
}

ChildResult RunChildProcess(const std::vector<std::string>& arguments, double timeoutSeconds)
{
  ChildResult result;
  std::vector<char*> argv;
  for (const std::string& a : arguments)
  {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  int outPipe[2], errPipe[2];
  if (arguments.empty() || pipe2(outPipe, O_CLOEXEC) != 0)
  {
    result.Output = "cannot create a pipe";
    return result;
  }
  if (pipe2(errPipe, O_CLOEXEC) != 0)
  {
    close(outPipe[0]);
    close(outPipe[1]);
    result.Output = "cannot create a pipe";
    return result;
  }
  const Stopwatch watch;
  const pid_t pid = fork();
  if (pid == 0)
  {
    // Only async-signal-safe calls until exec (the parent may have threads).
    dup2(outPipe[1], STDOUT_FILENO);
    dup2(errPipe[1], STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(outPipe[1]);
  close(errPipe[1]);
  if (pid < 0)
  {
    close(outPipe[0]);
    close(errPipe[0]);
    result.Output = std::string("fork failed: ") + std::strerror(errno);
    return result;
  }
  result.Started = true;
  result.TimedOut = !CollectUntilClosed(outPipe[0], errPipe[0], watch, timeoutSeconds, result);
  if (result.TimedOut)
  {
    kill(pid, SIGKILL);
  }
  close(outPipe[0]);
  close(errPipe[0]);
  int status = 0;
  // Retried only when a signal interrupts the wait (bounded; the child was killed or has ended).
  for (int attempt = 0; attempt < 1000 && waitpid(pid, &status, 0) < 0 && errno == EINTR; ++attempt)
  {
  }
  result.Seconds = watch.Seconds();
  result.ExitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}
} // namespace slodcli
