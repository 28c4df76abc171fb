// The seed's example programs as DDS clients, each against its own simulator process.
#include <gtest/gtest.h>
#include <signal.h>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

class Examples : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    domain_ = std::to_string(unique_test_domain());
    macsim_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"),
                                 "--domain", domain_, "--cameras", "off"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
  }
  void TearDown() override {
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }
  std::string domain_;
  std::unique_ptr<ChildProcess> macsim_;
};

TEST_P(Examples, DynamicObjectTestSeesEveryEffect) {
  ChildProcess example({bin("dynamicObjectTest"), std::to_string(GetParam()), "--domain", domain_,
                        "--textures", source("worlds/DemoEnvironment_v1/textures")});
  ASSERT_EQ(example.wait_for_exit(90s), 0) << example.output();
  EXPECT_NE(example.output().find("every effect seen"), std::string::npos) << example.output();
  EXPECT_EQ(example.output().find("NOT SEEN"), std::string::npos) << example.output();
}

INSTANTIATE_TEST_SUITE_P(SeedTable2, Examples, ::testing::Values(1, 2, 3, 4));

TEST(InterfaceTest, LoadsAWorldIntoTheRunningSimulator) {
  const std::string domain = std::to_string(unique_test_domain());
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                       domain, "--cameras", "off"});
  ASSERT_TRUE(macsim.wait_for_output("stepping", 30s)) << macsim.output();
  ChildProcess load(
      {bin("interfaceTest"), "-load", source("worlds/DemoWorld_v1.xml"), "--domain", domain});
  ASSERT_EQ(load.wait_for_exit(60s), 0) << load.output();
  EXPECT_NE(load.output().find("24 objects, 1 doors"), std::string::npos) << load.output();
  ChildProcess bad(
      {bin("interfaceTest"), "-load", source("worlds/no/such/world.xml"), "--domain", domain});
  EXPECT_EQ(bad.wait_for_exit(60s), 1) << bad.output();
  EXPECT_NE(bad.output().find("no such world file"), std::string::npos) << bad.output();
  EXPECT_TRUE(macsim.running());
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0);
}

TEST(DynamicObjectTestCli, WithoutATestNumberItSaysHowToCallIt) {
  ChildProcess p({bin("dynamicObjectTest"), "--domain", std::to_string(unique_test_domain())});
  EXPECT_EQ(p.wait_for_exit(10s), 2);
  EXPECT_NE(p.output().find("test number 1 to 4"), std::string::npos) << p.output();
}

}  // namespace
}  // namespace macsim::test
