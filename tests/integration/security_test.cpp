// DDS Security as deploy/security/make_security.sh sets it up: authenticated participants only,
// access control per identity, the supervisor encrypted. A controller identity drives the
// robot but cannot touch the supervisor; an operator can; a participant without credentials
// sees nothing.
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

class Secured : public ::testing::Test {
 protected:
  void SetUp() override {
    ChildProcess make({source("deploy/security/make_security.sh"), dir_, "--localhost"});
    ASSERT_EQ(make.wait_for_exit(60s), 0) << make.output();
    domain_ = unique_test_domain();
  }

  /// Starts `argv` as `identity` (its Fast DDS profile).
  ChildProcess as(const std::string& identity, std::vector<std::string> argv) const {
    ScopedEnv profile("FASTRTPS_DEFAULT_PROFILES_FILE", dir_ + "/" + identity + ".xml");
    argv.insert(argv.end(), {"--domain", std::to_string(domain_)});
    return ChildProcess(std::move(argv));
  }

  TempDir temp_{"macsim_security_"};
  const std::string dir_ = temp_.path();
  int domain_ = 0;
};

TEST_F(Secured, IdentitiesGetWhatTheirPermissionsGrantAndStrangersNothing) {
  ChildProcess sim =
      as("macsim", {bin("macsim"), "--world", source("worlds/small_room.xml"), "--cameras", "off"});
  ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();

  // The controller identity authenticates and drives the robot.
  ChildProcess controller = as("controller", {bin("helloKurt"), "--distance", "0.2"});
  EXPECT_EQ(controller.wait_for_exit(60s), 0) << controller.output();
  EXPECT_NE(controller.output().find("arrived"), std::string::npos) << controller.output();

  // ... but may not write supervisor requests: the writer is refused, the program says so.
  ChildProcess intruder = as("controller", {bin("dynamicObjectTest"), "1"});
  EXPECT_NE(intruder.wait_for_exit(30s), 0) << intruder.output();
  EXPECT_NE(intruder.output().find("cannot create a writer on rt/macsim/supervisor/request"),
            std::string::npos)
      << intruder.output();

  // The operator identity uses the supervisor (its traffic encrypted) and sees every effect.
  ChildProcess operator_client = as("operator", {bin("dynamicObjectTest"), "1"});
  EXPECT_EQ(operator_client.wait_for_exit(60s), 0) << operator_client.output();
  EXPECT_NE(operator_client.output().find("every effect seen"), std::string::npos)
      << operator_client.output();

  // A participant without credentials (the plain loopback profile) finds no robot.
  ScopedEnv plain("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/localhost.xml"));
  ChildProcess stranger({bin("helloKurt"), "--domain", std::to_string(domain_), "--distance", "0.2",
                         "--discovery-timeout", "4"});
  EXPECT_EQ(stranger.wait_for_exit(30s), 2) << stranger.output();
  EXPECT_NE(stranger.output().find("no odometry"), std::string::npos) << stranger.output();
}

}  // namespace
}  // namespace macsim::test
