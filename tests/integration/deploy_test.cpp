// deploy/: the systemd units render for this checkout, pass `systemd-analyze verify` (which
// fails on a unit whose program does not exist), and the simulator's unit runs: its ExecStart
// with its Environment defaults expanded starts macsim, which steps and exits cleanly.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

std::string read(const std::string& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Deploy, ServiceUnitsRenderAndVerify) {
  TempDir dir("macsim_units_");
  ChildProcess install({source("deploy/install_services.sh"), dir.path()});
  ASSERT_EQ(install.wait_for_exit(120s), 0) << install.output();
  for (const char* unit : {"macsim.service", "kurt_adapter.service", "macsim-discovery.service"}) {
    const std::string text = read(dir.path() + "/" + unit);
    EXPECT_NE(text.find("ExecStart=" + source("")), std::string::npos) << unit << ":\n" << text;
    EXPECT_EQ(text.find("@ROOT@"), std::string::npos) << unit;
  }
  // The check is real: a unit whose program is missing fails it.
  std::ofstream(dir.path() + "/broken.service")
      << "[Service]\nExecStart=" << dir.path() << "/no_such_program\n";
  ChildProcess verify({"/usr/bin/systemd-analyze", "verify", dir.path() + "/broken.service"});
  EXPECT_NE(verify.wait_for_exit(60s), 0) << verify.output();
}

TEST(Deploy, TheSimulatorsUnitStartsMacsim) {
  TempDir dir("macsim_units_");
  ChildProcess install({source("deploy/install_services.sh"), dir.path()});
  ASSERT_EQ(install.wait_for_exit(120s), 0) << install.output();
  // Expand ${VAR} in ExecStart from the unit's Environment= defaults, as systemd does
  // (no /etc/default/macsim here); keep the test on its own domain and on loopback.
  const std::string text = read(dir.path() + "/macsim.service");
  std::map<std::string, std::string> env;
  std::string exec;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, std::regex("Environment=([A-Z_]+)=(.*)"))) env[m[1]] = m[2];
    if (line.rfind("ExecStart=", 0) == 0) exec = line.substr(10);
  }
  env["MACSIM_DOMAIN"] = std::to_string(unique_test_domain());
  env["MACSIM_PROFILE"] = source("deploy/dds/localhost.xml");
  std::vector<std::string> argv;
  std::istringstream words(exec);
  for (std::string word; words >> word;) {
    std::smatch m;
    if (std::regex_match(word, m, std::regex("\\$\\{([A-Z_]+)\\}"))) {
      ASSERT_TRUE(env.count(m[1])) << "no default for " << word;
      word = env[m[1]];
    }
    argv.push_back(word);
  }
  ASSERT_GE(argv.size(), 2u) << text;
  argv.insert(argv.end(), {"--duration", "0.5", "--as-fast-as-possible"});
  ChildProcess macsim(argv);
  EXPECT_EQ(macsim.wait_for_exit(60s), 0) << macsim.output();
  EXPECT_NE(macsim.output().find("DemoWorld_v1"), std::string::npos) << macsim.output();
  EXPECT_NE(macsim.output().find("stopped at sim time 0.500"), std::string::npos)
      << macsim.output();
}

}  // namespace
}  // namespace macsim::test
