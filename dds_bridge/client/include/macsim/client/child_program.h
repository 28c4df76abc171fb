// A program started by this one as a child process (a simulator for trial runners and
// benchmarks): its output goes to a log file; it is stopped (SIGTERM, then SIGKILL) and reaped
// when the handle goes.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace macsim::client {

/// A program of the build next to this one (build/bin/NAME), found through /proc/self/exe.
std::string sibling_program(const std::string& name);

class ChildProgram {
 public:
  /// Starts argv[0] with argv; stdout and stderr to `log` (appended).
  ChildProgram(const std::vector<std::string>& argv, const std::string& log);
  ~ChildProgram();
  ChildProgram(const ChildProgram&) = delete;
  ChildProgram& operator=(const ChildProgram&) = delete;

  /// True while the process runs.
  bool running();
  /// Exit code (128 + signal when killed) once it ended within `timeout`; nullopt otherwise.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  /// SIGTERM, then SIGKILL after `grace`; returns the exit code.
  int stop(std::chrono::milliseconds grace = std::chrono::seconds(5));
  pid_t pid() const { return pid_; }
  const std::string& log() const { return log_; }

 private:
  pid_t pid_ = -1;
  std::optional<int> code_;
  std::string log_;
};

}  // namespace macsim::client
