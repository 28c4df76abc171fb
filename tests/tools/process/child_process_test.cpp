// macsim::process::ChildProcess on /bin/sh and /bin/sleep: exit codes, waits that time out, stop
// with SIGTERM or SIGINT and SIGKILL after the grace, output captured, to a file or discarded,
// the environment, a program that cannot be executed, and reaping by the destructor.
#include "macsim/process/child_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace {

using macsim::process::ChildProcess;
using macsim::process::Options;
using macsim::process::Output;
using namespace std::chrono_literals;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// True while a process of that id exists, zombie or not (a reaped child does not).
bool exists(pid_t pid) { return ::kill(pid, 0) == 0 || errno != ESRCH; }

TEST(ChildProcess, AProgramThatEndsGivesItsExitCode) {
  ChildProcess p({"/bin/sh", "-c", "exit 3"});
  EXPECT_EQ(p.wait_for_exit(5s), 3);
  EXPECT_FALSE(p.running());
  EXPECT_EQ(p.wait_for_exit(0ms), 3);  // asked again: the same code
  EXPECT_EQ(p.stop(), 3);              // nothing left to stop
}

TEST(ChildProcess, AWaitTimesOutWhileItRunsAndStopEndsItWithSigterm) {
  ChildProcess p({"/bin/sleep", "30"});
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(p.wait_for_exit(100ms), std::nullopt);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 100ms);
  EXPECT_TRUE(p.running());
  EXPECT_EQ(p.stop(), 128 + SIGTERM);
  EXPECT_FALSE(p.running());
  EXPECT_FALSE(exists(p.pid()));
}

TEST(ChildProcess, StopCanSendSigintFirst) {
  ChildProcess p({"/bin/sleep", "30"});
  EXPECT_EQ(p.stop(5s, SIGINT), 128 + SIGINT);
}

TEST(ChildProcess, StopSendsSigkillWhenTheGraceRunsOut) {
  // The shell ignores SIGTERM, and so does the sleep it becomes.
  ChildProcess p({"/bin/sh", "-c", "trap '' TERM; echo ready; exec /bin/sleep 30"});
  ASSERT_TRUE(p.wait_for_output("ready", 5s)) << p.output();
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(p.stop(300ms), 128 + SIGKILL);
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GE(took, 300ms);
  EXPECT_LT(took, 5s);
  EXPECT_FALSE(exists(p.pid()));
}

TEST(ChildProcess, SignalSendsAnySignal) {
  ChildProcess p({"/bin/sleep", "30"});
  p.signal(SIGUSR1);
  EXPECT_EQ(p.wait_for_exit(5s), 128 + SIGUSR1);
  p.signal(SIGTERM);  // ended: nothing is sent
  EXPECT_EQ(p.wait_for_exit(0ms), 128 + SIGUSR1);
}

TEST(ChildProcess, TheDestructorStopsAndReapsEvenAProcessIgnoringSigterm) {
  pid_t plain = -1, stubborn = -1;
  const auto t0 = std::chrono::steady_clock::now();
  {
    ChildProcess a({"/bin/sleep", "30"});
    Options options;
    options.stop_grace = 200ms;
    ChildProcess b({"/bin/sh", "-c", "trap '' TERM; echo ready; exec /bin/sleep 30"}, options);
    ASSERT_TRUE(b.wait_for_output("ready", 5s));
    plain = a.pid();
    stubborn = b.pid();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 10s);
  EXPECT_FALSE(exists(plain));  // not even a zombie
  EXPECT_FALSE(exists(stubborn));
}

TEST(ChildProcess, OutputIsCapturedFromStdoutAndStderrAndRemovedWithTheHandle) {
  std::string path;
  {
    ChildProcess p({"/bin/sh", "-c", "echo to-stdout; echo to-stderr >&2"});
    EXPECT_EQ(p.wait_for_exit(5s), 0);
    EXPECT_NE(p.output().find("to-stdout"), std::string::npos) << p.output();
    EXPECT_NE(p.output().find("to-stderr"), std::string::npos) << p.output();
    EXPECT_TRUE(p.wait_for_output("to-stderr", 0ms));
    path = p.output_path();
    EXPECT_TRUE(std::filesystem::exists(path));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(ChildProcess, WaitForOutputSaysNoWhenTheProcessEndsWithoutIt) {
  ChildProcess p({"/bin/sh", "-c", "echo something else"});
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(p.wait_for_output("never printed", 10s));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
}

TEST(ChildProcess, OutputToAFileIsAppendedAndKept) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("macsim_process_test_" + std::to_string(::getpid()) + ".log");
  std::ofstream(path) << "before\n";
  {
    ChildProcess p({"/bin/sh", "-c", "echo out; echo err >&2"}, Output::file(path));
    EXPECT_EQ(p.wait_for_exit(5s), 0);
    EXPECT_EQ(p.output_path(), path);
    EXPECT_EQ(p.output(), read(path));
  }
  EXPECT_EQ(read(path), "before\nout\nerr\n");
  std::filesystem::remove(path);
}

TEST(ChildProcess, OutputToAFileThatCannotBeOpenedIsRefusedBeforeStarting) {
  EXPECT_THROW(ChildProcess({"/bin/true"}, Output::file("/nonexistent/dir/log")),
               std::system_error);
}

TEST(ChildProcess, DiscardedOutputIsNotKept) {
  ChildProcess p({"/bin/sh", "-c", "echo out"}, Output::discard());
  EXPECT_EQ(p.wait_for_exit(5s), 0);
  EXPECT_EQ(p.output(), "");
  EXPECT_EQ(p.output_path(), "");
}

TEST(ChildProcess, TheEnvironmentIsInheritedWithEntriesAddedOrReplaced) {
  setenv("MACSIM_PROCESS_TEST_KEPT", "kept", 1);
  setenv("MACSIM_PROCESS_TEST_REPLACED", "old", 1);
  Options options;
  options.environment = {"MACSIM_PROCESS_TEST_REPLACED=new", "MACSIM_PROCESS_TEST_ADDED=added"};
  ChildProcess p({"/bin/sh", "-c",
                  "echo \"$MACSIM_PROCESS_TEST_KEPT $MACSIM_PROCESS_TEST_REPLACED "
                  "$MACSIM_PROCESS_TEST_ADDED\""},
                 options);
  EXPECT_EQ(p.wait_for_exit(5s), 0);
  EXPECT_EQ(p.output(), "kept new added\n");
  unsetenv("MACSIM_PROCESS_TEST_KEPT");
  unsetenv("MACSIM_PROCESS_TEST_REPLACED");
}

TEST(ChildProcess, AProgramThatCannotBeExecutedEndsWith127AndSaysSo) {
  ChildProcess p({"/nonexistent/program", "--flag"});
  EXPECT_EQ(p.wait_for_exit(5s), 127);
  EXPECT_NE(p.output().find("/nonexistent/program"), std::string::npos) << p.output();
}

TEST(ChildProcess, SiblingProgramsAreBesideThisOne) {
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe");
  EXPECT_EQ(macsim::process::sibling_program("macsim"), (self.parent_path() / "macsim").string());
}

}  // namespace
