// The demonstrator's world played by a controller against macsim in lock-step, as a test sees
// it: the controller's exit code and output, and the world's state once it stopped (objects,
// the door, the robot's ground truth), judged from the simulator's own topics.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/plan_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/test_domain.h"
#include "support/world_view.h"

namespace macsim::test {

struct DemoRun {
  int exit_code = -1;
  std::string output;
  std::map<std::string, macsim_msgs::msg::dds_::Object_> objects;
  std::optional<macsim_msgs::msg::dds_::DoorState_> door;
  std::optional<nav_msgs::msg::dds_::Odometry_> truth;
  /// What the controller published on rt/kurt/plan, in order (kurt_plan's plan as it acted).
  std::vector<plan_msgs::msg::dds_::Plan_> plans;
};

/// macsim --lockstep on `world` (with `seed` if not negative, and `macsim_args`) and `controller`
/// (a program of the build) stepping it, with `controller_args` besides; the world's state once
/// it stopped.
inline DemoRun play_demonstrator(const std::string& controller, const std::string& world, int seed,
                                 const std::vector<std::string>& controller_args = {},
                                 std::chrono::seconds limit = std::chrono::seconds(170),
                                 const std::vector<std::string>& macsim_args = {}) {
  using namespace std::chrono_literals;
  const std::string domain = std::to_string(unique_test_domain());
  std::vector<std::string> args{bin("macsim"), "--world", world, "--domain", domain, "--lockstep"};
  if (seed >= 0) {
    args.push_back("--seed");
    args.push_back(std::to_string(seed));
  }
  args.insert(args.end(), macsim_args.begin(), macsim_args.end());
  ChildProcess macsim(args);
  EXPECT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({std::stoi(domain), "", controller + "_test"});
  WorldView view(p);
  std::mutex plans_lock;
  std::vector<plan_msgs::msg::dds_::Plan_> plans;
  dds::Reader<plan_msgs::msg::dds_::Plan_PubSubType> plan_reader(
      p, dds::topics::plan("kurt"), dds::QosFamily::Latched, [&](const plan_msgs::msg::dds_::Plan_& plan) {
        std::lock_guard<std::mutex> guard(plans_lock);
        plans.push_back(plan);
      });
  std::vector<std::string> argv{bin(controller), "--domain", domain, "--lockstep"};
  argv.insert(argv.end(), controller_args.begin(), controller_args.end());
  ChildProcess demo(argv);
  DemoRun run;
  run.exit_code = demo.wait_for_exit(limit).value_or(-1);
  run.output = demo.output();
  // In lock-step nothing moves once the controller stopped stepping: the last state stands.
  std::this_thread::sleep_for(500ms);
  run.objects = view.snapshot();
  run.door = view.doors.latest();
  run.truth = view.truth.latest();
  {
    std::lock_guard<std::mutex> guard(plans_lock);
    run.plans = plans;
  }
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
  return run;
}

/// The cans (user data "can") standing on the switch's platform.
inline std::vector<const macsim_msgs::msg::dds_::Object_*> cans_on_platform(const DemoRun& run) {
  std::vector<const macsim_msgs::msg::dds_::Object_*> out;
  const auto platform = run.objects.find("doors/door_00/switch_component/platform");
  if (platform == run.objects.end()) return out;
  const auto& at = platform->second.pose().position();
  for (const auto& [name, object] : run.objects) {
    const auto& p = object.pose().position();
    if (object.user_data() == "can" && std::hypot(p.x() - at.x(), p.y() - at.y()) < 0.13 &&
        p.z() > at.z() - 0.01) {
      out.push_back(&object);
    }
  }
  return out;
}

/// The first can standing on the switch's platform, or nullptr.
inline const macsim_msgs::msg::dds_::Object_* can_on_platform(const DemoRun& run) {
  const auto cans = cans_on_platform(run);
  return cans.empty() ? nullptr : cans.front();
}

/// Everything the demonstrator must leave behind, asserted from the simulator's state: the
/// controller said SUCCESS; a magnetizable can on the switch's platform, the switch triggered by
/// weight (not virtually), the door open, the robot's ground truth beyond the partition.
inline void expect_through_the_door(const DemoRun& run, const std::string& what) {
  ASSERT_EQ(run.exit_code, 0) << what << "\n" << run.output;
  EXPECT_NE(run.output.find("SUCCESS"), std::string::npos) << run.output;
  const macsim_msgs::msg::dds_::Object_* can = can_on_platform(run);
  ASSERT_NE(can, nullptr) << what << ": no can on the switch's platform";
  EXPECT_TRUE(can->magnetizable());
  ASSERT_TRUE(run.door.has_value());
  EXPECT_TRUE(run.door->door().triggered()) << what;
  EXPECT_FALSE(run.door->door().virtually_triggered()) << what << ": opened by weight only";
  EXPECT_GT(run.door->door().opening(), 0.9) << what;
  ASSERT_TRUE(run.truth.has_value());
  // The partition is at x = 1.5 m; the robot's footprint is beyond it.
  EXPECT_GT(run.truth->pose().pose().position().x(), 1.5 + 0.3) << what;
  EXPECT_LT(std::fabs(run.truth->pose().pose().position().y()), 1.9) << what;
}

}  // namespace macsim::test
