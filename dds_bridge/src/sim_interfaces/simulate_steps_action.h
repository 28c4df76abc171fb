// The ROS 2 action simulation_interfaces/action/SimulateSteps served as rmw_fastrtps_cpp carries
// ROS 2 actions: the services send_goal, cancel_goal and get_result under
// <action>/_action/, the topics feedback and status. What the service StepSimulation cannot
// carry (one reply per request) an action can: progress and cancel.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/dds/ros2_service.h"
#include "macsim/msg/action_msgsPubSubTypes.h"
#include "macsim/msg/simulation_interfacesPubSubTypes.h"
#include "macsim/sim_core/runner.h"

namespace macsim {

/// Serves SimulateSteps: a goal steps the paused simulation its number of steps (one goal at a
/// time, as a step request), with feedback of the steps done every kFeedbackPeriod of wall time
/// and at its end; a cancel ends it at the step it reached. A goal sent while the simulation
/// plays, or while another step request runs, is accepted and aborted saying why, as the
/// action's definition asks.
class SimulateStepsAction {
 public:
  /// Serves the action `name` (e.g. "/macsim/simulate_steps") on the runner's world.
  SimulateStepsAction(dds::Participant& participant, Runner& runner, const std::string& name);
  ~SimulateStepsAction();
  SimulateStepsAction(const SimulateStepsAction&) = delete;
  SimulateStepsAction& operator=(const SimulateStepsAction&) = delete;

  /// How often a running goal's feedback goes out (wall time).
  static constexpr std::chrono::milliseconds kFeedbackPeriod{100};
  /// Goals that ended whose result is still kept (the oldest go first).
  static constexpr std::size_t kKeptResults = 64;

 private:
  using Uuid = std::array<uint8_t, 16>;
  using SendGoal = dds::ServiceServer<
      simulation_interfaces::action::dds_::SimulateSteps_SendGoal_Request_PubSubType,
      simulation_interfaces::action::dds_::SimulateSteps_SendGoal_Response_PubSubType>;
  using CancelGoal = dds::ServiceServer<action_msgs::srv::dds_::CancelGoal_Request_PubSubType,
                                        action_msgs::srv::dds_::CancelGoal_Response_PubSubType>;
  using GetResult = dds::ServiceServer<
      simulation_interfaces::action::dds_::SimulateSteps_GetResult_Request_PubSubType,
      simulation_interfaces::action::dds_::SimulateSteps_GetResult_Response_PubSubType>;
  struct Goal {
    action_msgs::msg::dds_::GoalInfo_ info;  // its id and when it was accepted
    int8_t status = 0;  // action_msgs GoalStatus STATUS_*
    uint64_t steps = 0, done = 0;
    simulation_interfaces::msg::dds_::Result_ result;
    std::vector<dds::RequestId> waiting;  // get_result requests answered when it ends
  };

  void on_send_goal(const SendGoal::Request& q, const dds::RequestId& id);
  void on_cancel(const CancelGoal::Request& q, const dds::RequestId& id);
  void on_get_result(const GetResult::Request& q, const dds::RequestId& id);
  /// On the simulation thread: starts the goal, or ends it at once saying why it cannot run.
  void start(const Uuid& id);
  /// Ends a goal with `status` and `result`: its result to those waiting, the status out.
  void end(Goal& goal, int8_t status, simulation_interfaces::msg::dds_::Result_ result);
  void feedback(const Goal& goal);
  /// Writes every kept goal's status (under mutex_).
  void publish_status();
  Goal* find(const Uuid& id);
  static bool terminal(int8_t status);

  /// Until the constructor has made the servers, a request's handler waits.
  void wait_until_served() const;

  Runner& runner_;
  std::atomic<bool> served_{false};
  std::mutex mutex_;               // guards goals_
  std::deque<Goal> goals_;         // accepted, oldest first
  std::optional<Uuid> executing_;  // the goal whose steps run (simulation thread only)
  std::chrono::steady_clock::time_point last_feedback_;  // simulation thread only
  dds::Writer<simulation_interfaces::action::dds_::SimulateSteps_FeedbackMessage_PubSubType>
      feedback_;
  dds::Writer<action_msgs::msg::dds_::GoalStatusArray_PubSubType> status_;
  // Servers last: destroyed first, so no request comes in while the rest goes.
  std::unique_ptr<GetResult> get_result_;
  std::unique_ptr<CancelGoal> cancel_goal_;
  std::unique_ptr<SendGoal> send_goal_;
};

}  // namespace macsim
