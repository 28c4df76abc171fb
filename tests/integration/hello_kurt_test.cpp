// macsim and helloKurt as separate processes on a private DDS domain: the robot really moves
// 1 m, odometry and ground truth agree, and controllers come and go without harming macsim.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <thread>

#include "macsim/dds/convert.h"
#include "macsim/dds/participant.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
using Odometry = nav_msgs::msg::dds_::Odometry_;

/// An odometry topic's samples, waited for by their sim-time stamp.
class LatestOdometry {
 public:
  LatestOdometry(dds::Participant& p, const std::string& topic) : samples_(p, topic, 50) {}
  std::optional<Odometry> get() { return samples_.latest(); }
  // Waits for a sample stamped at or after `sim_time`.
  std::optional<Odometry> wait_newer_than(double sim_time, std::chrono::seconds timeout) {
    return samples_.wait_for(
        [sim_time](const Odometry& o) { return dds::to_seconds(o.header().stamp()) >= sim_time; },
        timeout);
  }

 private:
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> samples_;
};

double stamp(const Odometry& o) { return dds::to_seconds(o.header().stamp()); }

// Planar distance between the positions of two samples.
double distance(const Odometry& a, const Odometry& b) {
  return std::hypot(a.pose().pose().position().x() - b.pose().pose().position().x(),
                    a.pose().pose().position().y() - b.pose().pose().position().y());
}

class HelloKurtTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    macsim_ = std::make_unique<ChildProcess>(std::vector<std::string>{
        bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
        std::to_string(domain_)});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ = std::make_unique<dds::Participant>(
        dds::ParticipantOptions{domain_, "", "hello_kurt_test"});
    odom_ = std::make_unique<LatestOdometry>(*participant_, dds::topics::odom("kurt"));
    truth_ = std::make_unique<LatestOdometry>(*participant_, dds::topics::ground_truth("kurt"));
    ASSERT_TRUE(truth_->wait_newer_than(0.0, 20s)) << "no ground truth from macsim";
    ASSERT_TRUE(odom_->wait_newer_than(0.0, 20s)) << "no odometry from macsim";
  }

  void TearDown() override {
    odom_.reset();
    truth_.reset();
    participant_.reset();
    if (macsim_) {
      macsim_->signal(SIGTERM);
      EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
    }
  }

  std::unique_ptr<ChildProcess> hello_kurt(std::vector<std::string> extra = {}) {
    std::vector<std::string> argv{bin("helloKurt"), "--domain", std::to_string(domain_)};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return std::make_unique<ChildProcess>(argv);
  }

  // Samples both topics once the robot has stood still long enough to have stopped.
  std::pair<Odometry, Odometry> settled_samples() {
    const double after = stamp(*truth_->get()) + 0.3;
    auto truth = truth_->wait_newer_than(after, 10s);
    auto odom = odom_->wait_newer_than(after, 10s);
    EXPECT_TRUE(truth && odom);
    return {*odom, *truth};
  }

  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<LatestOdometry> odom_, truth_;
};

TEST_F(HelloKurtTest, DrivesOneMetreAndOdometryAgreesWithGroundTruth) {
  const auto [odom_before, truth_before] = settled_samples();
  auto controller = hello_kurt();
  ASSERT_EQ(controller->wait_for_exit(90s), 0) << controller->output();
  EXPECT_NE(controller->output().find("arrived"), std::string::npos);
  const auto [odom_after, truth_after] = settled_samples();

  const double by_truth = distance(truth_after, truth_before);
  const double by_odom = distance(odom_after, odom_before);
  // helloKurt stops within 5 mm of 1 m by odometry, plus what it rolls while stopping at
  // <= 0.05 m/s (a 50 ms control period: 2.5 mm) and SPEED_CM's 1 cm/s truncation.
  std::printf("travelled by odometry %.4f m, by ground truth %.4f m\n", by_odom, by_truth);
  EXPECT_NEAR(by_odom, 1.0, 0.02);
  // Odometry vs ground truth: on a flat rigid floor the wheels roll without slip; the
  // contact's sink (<1 mm on a 60 mm radius, i.e. <1.7 %) bounds the difference: 2 cm.
  EXPECT_NEAR(by_truth, by_odom, 0.02);
  EXPECT_NEAR(by_truth, 1.0, 0.03);
  // It went straight ahead (+x in the world: the robot starts facing +x).
  EXPECT_GT(truth_after.pose().pose().position().x() - truth_before.pose().pose().position().x(),
            0.97);
  EXPECT_TRUE(macsim_->running());
}

TEST_F(HelloKurtTest, KillingTheControllerStopsTheRobotAndANewControllerWorks) {
  auto first = hello_kurt({"--distance", "3"});
  ASSERT_TRUE(first->wait_for_output("helloKurt: 0.2", 60s)) << first->output();
  first->signal(SIGKILL);
  ASSERT_TRUE(first->wait_for_exit(5s).has_value());
  const double killed_at = stamp(*truth_->get());

  // The simulator's 0.6 s command timeout stops the robot; it keeps running.
  auto stopped = truth_->wait_newer_than(killed_at + 1.2, 10s);
  ASSERT_TRUE(stopped);
  EXPECT_LT(std::fabs(stopped->twist().twist().linear().x()), 0.01);
  EXPECT_TRUE(macsim_->running());
  const auto [odom_before, truth_before] = settled_samples();
  EXPECT_LT(distance(truth_before, *stopped), 0.005);  // and stays stopped

  // A successor started while macsim still holds the killed participant (its 5 s lease) got no
  // odometry in about one of ten loaded full runs (cause not pinned down; probably Fast DDS 2.9
  // giving it the dead one's participant id and ports). After the lease it is served at once.
  std::this_thread::sleep_for(5s);
  auto second = hello_kurt({"--distance", "0.5", "--discovery-timeout", "30"});
  ASSERT_EQ(second->wait_for_exit(90s), 0) << second->output();
  const auto [odom_after, truth_after] = settled_samples();
  EXPECT_NEAR(distance(truth_after, truth_before), 0.5, 0.03);
  EXPECT_TRUE(macsim_->running());
}

}  // namespace
}  // namespace macsim::test
