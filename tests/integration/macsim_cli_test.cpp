// The programs' command lines, run as a user would: help, bad input, validation, signals.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

TEST(MacsimCli, HelpListsTheCommonOptions) {
  for (const char* program : {"macsim", "helloKurt"}) {
    ChildProcess p({bin(program), "--help"});
    ASSERT_EQ(p.wait_for_exit(10s), 0) << program;
    EXPECT_NE(p.output().find("--domain N"), std::string::npos) << p.output();
    EXPECT_NE(p.output().find("--help"), std::string::npos);
  }
}

TEST(MacsimCli, MalformedWorldExitsNonZeroNamingFileAndLine) {
  const std::string path = ::testing::TempDir() + "malformed_world.xml";
  std::ofstream(path) << "<WORLD>\n  <ROBOT>\n    <ID>kurt</ID>\n  </ROBOT>\n  <OBJECT>\n</WORLD>\n";
  ChildProcess p({bin("macsim"), "--world", path, "--domain", std::to_string(unique_test_domain())});
  const auto code = p.wait_for_exit(20s);
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_NE(p.output().find(path + ":5: malformed XML: element not closed by its end tag <OBJECT>"),
            std::string::npos)
      << p.output();
  EXPECT_NE(p.output().find("malformed XML"), std::string::npos) << p.output();
}

TEST(MacsimCli, BadNumberInWorldNamesItsLine) {
  const std::string path = ::testing::TempDir() + "bad_number_world.xml";
  std::ofstream(path) << "<WORLD>\n<PHYSICS>\n<STEP>0.001</STEP>\n<GRAVITY>0,0,down</GRAVITY>\n"
                         "</PHYSICS>\n</WORLD>\n";
  ChildProcess p({bin("macsim"), "--world", path});
  EXPECT_EQ(p.wait_for_exit(20s), 1);
  EXPECT_NE(p.output().find(path + ":4: <GRAVITY>"), std::string::npos) << p.output();
}

TEST(MacsimCli, UsageErrorsExitTwo) {
  {
    ChildProcess p({bin("macsim")});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("--world FILE is required"), std::string::npos) << p.output();
  }
  {
    ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain", "300"});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("--domain"), std::string::npos) << p.output();
  }
  {
    ChildProcess p({bin("helloKurt"), "--speed", "fast"});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("bad value 'fast' for --speed"), std::string::npos) << p.output();
  }
}

TEST(MacsimCli, ValidatePrintsASummaryAndExitsZero) {
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--validate"});
  ASSERT_EQ(p.wait_for_exit(20s), 0) << p.output();
  EXPECT_NE(p.output().find("4 objects (3 portable, 1 fixed), 1 robots [kurt: kurt3d]"),
            std::string::npos)
      << p.output();
}

TEST(MacsimCli, RunsForADurationAsFastAsPossibleAndReportsTheStepRate) {
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                  std::to_string(unique_test_domain()), "--as-fast-as-possible", "--duration",
                  "2"});
  ASSERT_EQ(p.wait_for_exit(60s), 0) << p.output();
  EXPECT_NE(p.output().find("rt/kurt/cmd_vel"), std::string::npos) << p.output();
  EXPECT_NE(p.output().find("stopped at sim time 2.000 s after 2000 steps"), std::string::npos)
      << p.output();
}

TEST(MacsimCli, SigtermAndSigintStopCleanly) {
  for (int sig : {SIGTERM, SIGINT}) {
    ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                    std::to_string(unique_test_domain())});
    ASSERT_TRUE(p.wait_for_output("stepping", 20s)) << p.output();
    p.signal(sig);
    EXPECT_EQ(p.wait_for_exit(10s), 0) << p.output();
    EXPECT_NE(p.output().find("macsim: stopped at sim time"), std::string::npos) << p.output();
  }
}

TEST(HelloKurtCli, WithoutASimulatorItSaysSoAndExitsTwo) {
  ChildProcess p({bin("helloKurt"), "--domain", std::to_string(unique_test_domain()),
                  "--discovery-timeout", "2"});
  EXPECT_EQ(p.wait_for_exit(20s), 2) << p.output();
  EXPECT_NE(p.output().find("no odometry from robot 'kurt'"), std::string::npos) << p.output();
}

}  // namespace
}  // namespace macsim::test
