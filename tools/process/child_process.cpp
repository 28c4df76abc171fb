#include "macsim/process/child_process.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

extern char** environ;

namespace macsim::process {

std::string sibling_program(const std::string& name) {
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? name : (self.parent_path() / name).string();
}

namespace {

/// The environment a child gets: this process's, with `extra` ("NAME=VALUE") replacing or adding.
std::vector<std::string> child_environment(const std::vector<std::string>& extra) {
  std::vector<std::string> result;
  auto name_of = [](const std::string& entry) { return entry.substr(0, entry.find('=')); };
  for (char** e = environ; e && *e; ++e) {
    const std::string entry = *e;
    bool replaced = false;
    for (const auto& x : extra) replaced = replaced || name_of(x) == name_of(entry);
    if (!replaced) result.push_back(entry);
  }
  result.insert(result.end(), extra.begin(), extra.end());
  return result;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> result;
  for (auto& s : strings) result.push_back(s.data());
  result.push_back(nullptr);
  return result;
}

/// write() of a message in the child after fork (no allocation, no stdio).
void say(const char* a, const char* b) {
  const char* parts[] = {a, b, "\n"};
  for (const char* p : parts) {
    if (::write(STDERR_FILENO, p, std::strlen(p)) < 0) return;
  }
}

}  // namespace

ChildProcess::ChildProcess(std::vector<std::string> argv, Options options)
    : options_(std::move(options)) {
  if (argv.empty()) throw std::invalid_argument("ChildProcess: no program given");
  // Everything the child needs is made before fork: between fork and exec it only calls
  // async-signal-safe functions (the parent may have other threads holding locks).
  int fd = -1;
  switch (options_.output.kind) {
    case Output::Kind::Capture: {
      char path_template[] = "/tmp/macsim-child-output-XXXXXX";
      fd = mkostemp(path_template, O_CLOEXEC);
      if (fd < 0) throw std::system_error(errno, std::generic_category(), "mkstemp");
      output_path_ = path_template;
      break;
    }
    case Output::Kind::File:
      fd = ::open(options_.output.path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      if (fd < 0) {
        throw std::system_error(errno, std::generic_category(),
                                "cannot open " + options_.output.path);
      }
      output_path_ = options_.output.path;
      break;
    case Output::Kind::Discard:
      fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
      if (fd < 0) throw std::system_error(errno, std::generic_category(), "/dev/null");
      break;
    case Output::Kind::Inherit:
      break;
  }
  std::vector<char*> args = pointers(argv);
  std::vector<std::string> environment;
  std::vector<char*> envp;
  if (!options_.environment.empty()) {
    environment = child_environment(options_.environment);
    envp = pointers(environment);
  }
  const pid_t parent = getpid();
  std::fflush(stdout);  // what this process buffered is written once, not by both
  std::fflush(stderr);
  pid_ = fork();
  if (pid_ < 0) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    if (options_.output.kind == Output::Kind::Capture) std::remove(output_path_.c_str());
    throw std::system_error(error, std::generic_category(), "fork");
  }
  if (pid_ == 0) {
    if (options_.die_with_parent) {
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(126);  // the parent ended before the line above
    }
    if (fd >= 0) {
      if (dup2(fd, STDOUT_FILENO) < 0) _exit(126);
      if (options_.merge_stderr && dup2(fd, STDERR_FILENO) < 0) _exit(126);
    }
    if (!options_.working_directory.empty() && chdir(options_.working_directory.c_str()) != 0) {
      say("cannot enter the working directory ", options_.working_directory.c_str());
      _exit(126);
    }
    if (envp.empty()) {
      execv(args[0], args.data());
    } else {
      execve(args[0], args.data(), envp.data());
    }
    say("exec failed: ", args[0]);
    _exit(127);
  }
  if (fd >= 0) ::close(fd);
}

ChildProcess::ChildProcess(std::vector<std::string> argv, Output output)
    : ChildProcess(std::move(argv), [&] {
        Options options;
        options.output = std::move(output);
        return options;
      }()) {}

ChildProcess::~ChildProcess() {
  stop(options_.stop_grace);
  if (options_.output.kind == Output::Kind::Capture) std::remove(output_path_.c_str());
}

std::optional<int> ChildProcess::wait_for_exit(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!exit_code_) {
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      break;
    }
    if (r < 0 && errno != EINTR) {
      exit_code_ = -1;  // not our child (any more): nothing to wait for
      break;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return exit_code_;
}

bool ChildProcess::running() { return !wait_for_exit(std::chrono::milliseconds(0)); }

void ChildProcess::signal(int signal_number) {
  if (running()) ::kill(pid_, signal_number);
}

int ChildProcess::stop(std::chrono::milliseconds grace, int first) {
  if (running()) {
    ::kill(pid_, first);
    if (!wait_for_exit(grace)) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      pid_t r;
      while ((r = waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
      }
      exit_code_ =
          r == pid_ ? (WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) : -1;
    }
  }
  return exit_code_.value_or(-1);
}

std::string ChildProcess::output() const {
  if (output_path_.empty()) return {};
  std::ifstream in(output_path_);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool ChildProcess::wait_for_output(const std::string& text, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (output().find(text) != std::string::npos) return true;
    if (!running()) return output().find(text) != std::string::npos;  // its last words
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace macsim::process
