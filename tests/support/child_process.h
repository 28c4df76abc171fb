// Integration tests' helpers: the child processes they start (always reaped), paths of the
// build and the sources, temporary directories, environment variables for the children.
#pragma once

#include <optional>
#include <string>

#include "macsim/process/child_process.h"

namespace macsim::test {

/// Path of a program built into build/bin.
std::string bin(const std::string& program);
/// Path of a file in the source tree.
std::string source(const std::string& relative);
/// Path of a file in the build tree (what the build wrote beside bin/).
std::string build_path(const std::string& relative);

/// The programs under test run as children: macsim::process::ChildProcess, by default with
/// stdout and stderr captured in one temporary file (output(), wait_for_output()), stopped
/// (SIGTERM, then SIGKILL after 5 s), reaped and its output removed by the destructor, and sent
/// SIGTERM if the test process dies first.
using ChildProcess = macsim::process::ChildProcess;

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
