// Nothing a controller sent before a reset acts after it, whatever order DDS delivers them in:
// a real macsim, a controller whose drive command DDS delivers about a second late (its own
// flow controller) while its reset request goes at once. The request names the command
// (client/commands_sent.h), and macsim drops it when it comes; a command sent after the reset
// still acts. In lock-step and in real time.
// And lock-step by contract: a step request names the commands it steps on, and macsim waits
// for a late one before the first step, or refuses the request naming one that never comes.
#include "macsim/client/commands_sent.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/late_writer.h"
#include "support/latest_sample.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;
namespace sv = client::supervisor;
using Twist = geometry_msgs::msg::dds_::Twist_PubSubType;

/// A controller of macsim on small_room.xml whose cmd_vel is delivered about `kLate` late.
class LateCommand : public ::testing::TestWithParam<bool> {
 protected:
  static constexpr auto kLate = 1500ms;

  void SetUp() override {
    domain_ = unique_test_domain();
    std::vector<std::string> args{bin("macsim"),
                                  "--world",
                                  source("worlds/small_room.xml"),
                                  "--domain",
                                  std::to_string(domain_),
                                  "--cameras",
                                  "off",
                                  "--command-wait",
                                  "5"};
    if (lockstep()) args.push_back("--lockstep");
    macsim_ = std::make_unique<ChildProcess>(args);
    ASSERT_TRUE(
        macsim_->wait_for_output(lockstep() ? "stepping on request" : "macsim: serving", 30s))
        << macsim_->output();
    participant_ = std::make_unique<dds::Participant>(
        dds::ParticipantOptions{domain_, "", "commands_sent_test"});
    supervisor_ = std::make_unique<client::SupervisorClient>(*participant_);
    simulation_ = std::make_unique<client::SimulationClient>(*participant_);
    truth_ = std::make_unique<Samples<nav_msgs::msg::dds_::Odometry_PubSubType>>(
        *participant_, dds::topics::ground_truth("kurt"), 10, dds::QosFamily::State);
    cmd_vel_ = std::make_unique<LateWriter<Twist>>(domain_, dds::topics::cmd_vel("kurt"), kLate);
    ASSERT_TRUE(supervisor_->wait_for_server(20s));
    ASSERT_TRUE(simulation_->wait_for_server(20s));
    for (int i = 0; i < 100 && cmd_vel_->matched() == 0; ++i) std::this_thread::sleep_for(50ms);
    ASSERT_EQ(cmd_vel_->matched(), 1);
  }
  void TearDown() override {
    cmd_vel_.reset();
    truth_.reset();
    simulation_.reset();
    supervisor_.reset();
    participant_.reset();
    if (macsim_) {
      macsim_->signal(SIGTERM);
      EXPECT_EQ(macsim_->wait_for_exit(20s), 0) << macsim_->output();
    }
  }
  bool lockstep() const { return GetParam(); }

  /// Writes a twist through the late writer, noted as the client's writers note theirs.
  void drive(double speed) {
    client::note_command_sent(cmd_vel_->write(dds::planar_twist(speed, 0.0)), domain_);
  }
  /// Resets the world; true if it was done before the late command was delivered.
  bool reset_before_delivery() {
    const auto reply = supervisor_->call(sv::reset(mm::RESET_EVERYTHING));
    EXPECT_TRUE(reply && reply->code() == mm::ERR_OK);
    return !cmd_vel_->delivered(0ms);
  }
  /// How far the robot went in 0.5 s of sim time (lock-step: stepped; real time: waited),
  /// by ground truth, and the state hash at the end (lock-step only).
  std::pair<double, uint64_t> travelled() {
    if (!lockstep()) {
      const double x0 = x_after(-1);
      std::this_thread::sleep_for(800ms);
      return {x_after(-1) - x0, 0};
    }
    const auto first = simulation_->step(10);
    if (!first) return {NAN, 0};
    const double x0 = x_after(first->sim_time());
    const auto reply = simulation_->step(500);
    if (!reply) return {NAN, 0};
    return {x_after(reply->sim_time()) - x0, reply->state_hash()};
  }
  /// The robot's x by the newest ground truth stamped `time` or later (sim time, s).
  double x_after(double time) {
    const auto at = truth_->wait_for(
        [&](const auto& o) { return dds::to_seconds(o.header().stamp()) >= time - 0.02; }, 10s);
    EXPECT_TRUE(at.has_value()) << "no ground truth at sim time " << time;
    return at ? at->pose().pose().position().x() : NAN;
  }

  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<client::SupervisorClient> supervisor_;
  std::unique_ptr<client::SimulationClient> simulation_;
  std::unique_ptr<Samples<nav_msgs::msg::dds_::Odometry_PubSubType>> truth_;
  std::unique_ptr<LateWriter<Twist>> cmd_vel_;
};

TEST_P(LateCommand, ACommandSentBeforeAResetAndDeliveredAfterItNeverActs) {
  if (lockstep()) {
    ASSERT_TRUE(simulation_->step(10).has_value());  // ground truth comes
  }
  ASSERT_TRUE(truth_->wait_for_count(1, 10s));
  // The reference: reset with nothing in flight.
  ASSERT_TRUE(supervisor_->call(sv::reset(mm::RESET_EVERYTHING)).has_value());
  const auto [still, reference] = travelled();
  EXPECT_LT(std::fabs(still), 1e-3);

  drive(0.0);  // leaves at once: the flow controller's period has room for one sample
  drive(0.5);  // leaves about kLate later
  ASSERT_TRUE(reset_before_delivery()) << "the reset's reply came after the command arrived";
  ASSERT_TRUE(cmd_vel_->delivered(10s));  // now macsim has it, after the reset
  const auto [moved, hash] = travelled();
  EXPECT_LT(std::fabs(moved), 1e-3) << "the command sent before the reset drove the robot";
  if (lockstep()) {
    EXPECT_EQ(hash, reference);
  }

  // A command sent after the reset acts, late or not.
  ASSERT_TRUE(cmd_vel_->delivered(10s));
  std::this_thread::sleep_for(kLate);  // the flow controller's period is free again
  drive(0.5);
  ASSERT_TRUE(cmd_vel_->delivered(10s));
  const auto [driven, _] = travelled();
  EXPECT_GT(driven, 0.05);

  macsim_->signal(SIGTERM);
  EXPECT_EQ(macsim_->wait_for_exit(20s), 0);
  // The late one, and the stop before it when the reset overtook that too.
  const std::string said = " robot commands sent before a reset";
  const std::string out = macsim_->output();
  const auto at = out.find(said);
  ASSERT_NE(at, std::string::npos) << out;
  const auto count = out.substr(out.rfind(' ', at - 1) + 1, at - out.rfind(' ', at - 1) - 1);
  EXPECT_TRUE(count == "1" || count == "2") << out;
  macsim_.reset();
}

/// The same controller, stepping the simulation.
class LateStepCommand : public LateCommand {};

TEST_P(LateStepCommand, AStepWaitsForTheLateCommandItNamesAndActsOnItFromItsFirstStep) {
  ASSERT_TRUE(simulation_->step(10).has_value());
  ASSERT_TRUE(truth_->wait_for_count(1, 10s));
  drive(0.0);  // leaves at once
  drive(0.5);  // leaves at the flow controller's next period: the step request below names it
  // Its 510 steps take a few milliseconds; had the first not waited for the command, the robot
  // would have stood through them. (How long the wait was depends on where in its period the
  // flow controller was: a wall-time bound failed under load.)
  const auto [moved, _] = travelled();
  EXPECT_GT(moved, 0.05) << "the late command did not drive the robot in the steps after it";
}

TEST_P(LateStepCommand, AStepWhoseNamedCommandNeverComesIsRefusedNamingItWithNoStep) {
  const auto before = simulation_->step(10);
  ASSERT_TRUE(before.has_value());
  dds::SampleId never;  // a writer of this process that macsim never hears
  never.writer = {0x01, 0x0f, 0x5a, 0x5a, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0x12, 0x03};
  never.sequence = 3;
  client::note_command_sent(never, domain_);
  const auto reply = simulation_->step(10, 20s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->code(), mm::ERR_COMMANDS_MISSING) << reply->message();
  EXPECT_NE(reply->message().find("robot command 3 of writer 01.0f.5a.5a"), std::string::npos)
      << reply->message();
  EXPECT_EQ(reply->steps(), before->steps());  // not one step
  EXPECT_EQ(reply->steps_done(), 0u);
}

TEST_P(LateStepCommand, ANonFiniteCommandNamedCountsAsArrivedAndDrivesNothing) {
  ASSERT_TRUE(simulation_->step(10).has_value());
  ASSERT_TRUE(truth_->wait_for_count(1, 10s));
  drive(0.0);
  drive(std::nan(""));  // late, and dropped by macsim when it comes: the step goes on then
  const auto [moved, _] = travelled();
  EXPECT_LT(std::fabs(moved), 1e-3);
  EXPECT_TRUE(std::isfinite(moved)) << "a step was refused";
}

INSTANTIATE_TEST_SUITE_P(Lockstep, LateStepCommand, ::testing::Values(true),
                         [](const auto&) { return "Lockstep"; });

INSTANTIATE_TEST_SUITE_P(LockstepAndRealTime, LateCommand, ::testing::Bool(),
                         [](const auto& test) { return test.param ? "Lockstep" : "RealTime"; });

}  // namespace
}  // namespace macsim::test
