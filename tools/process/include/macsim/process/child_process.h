// A program started by this one as a child process: the simulators of the trial runners and
// benchmarks, the programs under test of the integration tests. One class for all of them:
// started with fork/exec (argv, extra environment), its output captured, appended to a file,
// discarded or inherited; waited for with a timeout; stopped with a signal and SIGKILL after a
// grace period; always reaped when the handle goes.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace macsim::process {

/// A program of the build next to this one (build/bin/NAME or PREFIX/bin/NAME), found through
/// /proc/self/exe; NAME alone (searched by nothing: exec needs a path) if that cannot be read.
std::string sibling_program(const std::string& name);

/// Where a child's standard output (and, with `Options::merge_stderr`, its standard error) goes.
struct Output {
  enum class Kind {
    Capture,  ///< a temporary file of its own, read with output(), removed with the handle
    File,     ///< `path`, appended to (created if missing), kept
    Discard,  ///< /dev/null
    Inherit,  ///< this process's own
  };
  Kind kind = Kind::Capture;
  std::string path;

  static Output capture() { return {Kind::Capture, {}}; }
  static Output file(std::string path) { return {Kind::File, std::move(path)}; }
  static Output discard() { return {Kind::Discard, {}}; }
  static Output inherit() { return {Kind::Inherit, {}}; }
};

struct Options {
  Output output = Output::capture();
  /// Standard error to the same place as standard output; false: this process's own.
  bool merge_stderr = true;
  /// "NAME=VALUE" entries set in the child's environment on top of this process's.
  std::vector<std::string> environment;
  /// The child gets SIGTERM when the thread that started it ends (PR_SET_PDEATHSIG), so a
  /// parent killed without stopping it takes it along. Start long-lived children from a thread
  /// that outlives them (the main thread).
  bool die_with_parent = true;
  /// The folder the child starts in (empty: this process's); one it cannot enter ends the child
  /// with exit code 126.
  std::string working_directory;
  /// How long the destructor waits after SIGTERM before SIGKILL.
  std::chrono::milliseconds stop_grace = std::chrono::seconds(5);
};

class ChildProcess {
 public:
  /// Starts argv[0] (a path: no PATH search) with `argv`. Throws std::system_error when no process
  /// can be made; a program that cannot be executed ends with exit code 127 and says why in its
  /// output.
  explicit ChildProcess(std::vector<std::string> argv, Options options = {});
  /// The same with the default options but `output`.
  ChildProcess(std::vector<std::string> argv, Output output);
  /// stop(options.stop_grace): SIGTERM, SIGKILL after the grace, reaped; a captured output removed.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Exit code (128 + signal when a signal ended it) once the process ended within `timeout`,
  /// else nullopt. Reaps it.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);
  /// True while the process runs (reaps it once it ended).
  bool running();
  /// Sends a signal (SIGINT, SIGTERM, SIGKILL, ...) if the process still runs.
  void signal(int signal_number);
  /// Sends `first` (SIGTERM or SIGINT), then SIGKILL if the process still runs after `grace`;
  /// returns its exit code once reaped (at once if it had ended).
  int stop(std::chrono::milliseconds grace = std::chrono::seconds(5), int first = SIGTERM);

  /// Everything the process wrote so far to a captured output or its file; empty otherwise.
  std::string output() const;
  /// Waits until `text` appears in output() (true), or the process ends or the timeout passes
  /// without it (false).
  bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout);
  /// The file its output goes to (Capture, File); empty otherwise.
  const std::string& output_path() const { return output_path_; }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
  Options options_;
  std::string output_path_;
};

}  // namespace macsim::process
