// A child process for integration tests: started with fork/exec, output captured, always reaped.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace macsim::test {

/// Path of a program built into build/bin.
std::string bin(const std::string& program);
/// Path of a file in the source tree.
std::string source(const std::string& relative);

/// Runs a program; stdout and stderr go to one temporary file. The destructor terminates
/// (SIGTERM, then SIGKILL after 5 s) and reaps the process if it is still running.
class ChildProcess {
 public:
  explicit ChildProcess(std::vector<std::string> argv);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Exit code (or 128 + signal) once the process ended within `timeout`, else nullopt.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);
  /// Sends a signal (SIGTERM, SIGINT, SIGKILL ...) if the process still runs.
  void signal(int signal_number);
  bool running();
  /// Everything the process printed so far.
  std::string output() const;
  /// Waits until `text` appears in the output (or the process ends, or the timeout passes).
  bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout);
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
  std::string output_path_;
};

/// A fresh directory under /tmp (named `prefix` + random), removed with everything in it.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Sets an environment variable for the children started while it lives, then restores it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace macsim::test
