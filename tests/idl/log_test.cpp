// The log: a line per call on stderr as given, the levels below the set one left out, timestamps and the level in front when asked.
#include "macsim/dds/log.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace macsim::test {
namespace {

/// What the calls in `body` wrote to stderr (file descriptor 2 sent to a file meanwhile).
template <class Body>
std::string stderr_of(Body body) {
  std::fflush(stderr);
  char path[] = "/tmp/macsim_log_testXXXXXX";
  const int file = mkstemp(path);
  EXPECT_GE(file, 0);
  const int saved = dup(2);
  dup2(file, 2);
  body();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  close(file);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(path);
  return text.str();
}

class Log : public ::testing::Test {
 protected:
  void TearDown() override {
    log::set_level(log::Level::info);
    log::set_timestamps(false);
  }
};

TEST_F(Log, InfoAndAboveAreWrittenAsGivenOneLineEach) {
  log::set_level(log::Level::info);
  const std::string out = stderr_of([] {
    log::debug("hidden {}", 1);
    log::info("macsim: loaded {} objects", 12);
    log::warn("macsim: warning: {}", "near");
    log::error("failed at {:.2f} s", 1.5);
  });
  EXPECT_EQ(out, "macsim: loaded 12 objects\nmacsim: warning: near\nfailed at 1.50 s\n");
}

TEST_F(Log, QuietKeepsWarningsAndErrorsVerboseAddsDebug) {
  log::set_level(log::Level::warn);
  EXPECT_FALSE(log::enabled(log::Level::info));
  EXPECT_EQ(stderr_of([] {
              log::info("a");
              log::warn("b");
            }),
            "b\n");
  log::set_level(log::Level::debug);
  EXPECT_EQ(stderr_of([] { log::debug("step {}", 7); }), "step 7\n");
  log::set_level(log::Level::off);
  EXPECT_EQ(stderr_of([] { log::error("nothing"); }), "");
}

TEST_F(Log, TimestampsPutTheTimeAndLevelFirst) {
  log::set_timestamps(true);
  const std::string out = stderr_of([] { log::warn("late by {} ms", 3); });
  EXPECT_TRUE(std::regex_match(
      out, std::regex(R"(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3} warning late by 3 ms\n)")))
      << out;
}

}  // namespace
}  // namespace macsim::test
