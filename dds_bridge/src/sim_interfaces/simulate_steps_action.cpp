#include "sim_interfaces/simulate_steps_action.h"

#include <algorithm>
#include <functional>
#include <thread>

#include "macsim/dds/log.h"
#include "sim_interfaces/sim_interfaces_dispatch.h"

namespace macsim {

namespace am = action_msgs::msg::dds_;
namespace gs = action_msgs::msg::dds_::GoalStatus_Constants;
namespace cg = action_msgs::srv::dds_::CancelGoal_Response_Constants;
namespace sa = simulation_interfaces::action::dds_;
namespace si = simulation_interfaces::msg::dds_;
namespace rc = si::Result_Constants;
using sim_interfaces::result;

namespace {

builtin_interfaces::msg::dds_::Time_ wall_now() {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  builtin_interfaces::msg::dds_::Time_ t;
  t.sec(static_cast<int32_t>(ns / 1000000000));
  t.nanosec(static_cast<uint32_t>(ns % 1000000000));
  return t;
}

bool zero(const std::array<uint8_t, 16>& id) {
  return std::all_of(id.begin(), id.end(), [](uint8_t b) { return b == 0; });
}

/// a at or before b.
bool not_after(const builtin_interfaces::msg::dds_::Time_& a,
               const builtin_interfaces::msg::dds_::Time_& b) {
  return a.sec() < b.sec() || (a.sec() == b.sec() && a.nanosec() <= b.nanosec());
}

std::string steps_text(uint64_t done, uint64_t asked) {
  return std::to_string(done) + " of " + std::to_string(asked) + " steps";
}

}  // namespace

SimulateStepsAction::SimulateStepsAction(dds::Participant& participant, Runner& runner,
                                         const std::string& name)
    : runner_(runner),
      feedback_(participant, "rt" + name + "/_action/feedback", dds::QosFamily::State),
      status_(participant, "rt" + name + "/_action/status", dds::QosFamily::Latched) {
  // A request may come before its server's pointer is set: the handlers wait for it.
  get_result_ = std::make_unique<GetResult>(
      participant, name + "/_action/get_result",
      [this](const GetResult::Request& q, const dds::RequestId& id) { on_get_result(q, id); });
  cancel_goal_ = std::make_unique<CancelGoal>(
      participant, name + "/_action/cancel_goal",
      [this](const CancelGoal::Request& q, const dds::RequestId& id) { on_cancel(q, id); });
  send_goal_ = std::make_unique<SendGoal>(
      participant, name + "/_action/send_goal",
      [this](const SendGoal::Request& q, const dds::RequestId& id) { on_send_goal(q, id); });
  served_.store(true);
  std::lock_guard<std::mutex> lock(mutex_);
  publish_status();  // an empty list: late joiners see the action's status topic served
}

void SimulateStepsAction::wait_until_served() const {
  while (!served_.load()) std::this_thread::yield();
}

SimulateStepsAction::~SimulateStepsAction() {
  send_goal_.reset();
  cancel_goal_.reset();
  get_result_.reset();
}

bool SimulateStepsAction::terminal(int8_t status) {
  return status == gs::STATUS_SUCCEEDED || status == gs::STATUS_CANCELED ||
         status == gs::STATUS_ABORTED;
}

SimulateStepsAction::Goal* SimulateStepsAction::find(const Uuid& id) {
  for (auto& g : goals_)
    if (g.info.goal_id().uuid() == id) return &g;
  return nullptr;
}

void SimulateStepsAction::on_send_goal(const SendGoal::Request& q, const dds::RequestId& id) {
  wait_until_served();
  SendGoal::Response response;
  response.stamp(wall_now());
  const Uuid& uuid = q.goal_id().uuid();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // A goal id already taken, or no room in the runner's queue: rejected (a ROS 2 action
    // says no more than that; the simulator's log says why).
    if (find(uuid) || zero(uuid)) {
      response.accepted(false);
    } else {
      Goal goal;
      goal.info.goal_id(q.goal_id());
      goal.info.stamp(response.stamp());
      goal.status = gs::STATUS_ACCEPTED;
      goal.steps = q.goal().steps();
      goals_.push_back(std::move(goal));
      while (goals_.size() > kKeptResults && terminal(goals_.front().status)) goals_.pop_front();
      response.accepted(runner_.push([this, id = uuid](World&) { start(id); }));
      if (!response.accepted()) {
        goals_.pop_back();
        log::warn("macsim: SimulateSteps goal rejected: {}", runner_.queue_full_message());
      } else {
        publish_status();
      }
    }
  }
  send_goal_->reply(id, response);
}

void SimulateStepsAction::start(const Uuid& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Goal* goal = find(id);
  if (!goal || goal->status != gs::STATUS_ACCEPTED) {
    // Cancelled before it began.
    if (goal && goal->status == gs::STATUS_CANCELING)
      end(*goal, gs::STATUS_CANCELED,
          result(rc::RESULT_OPERATION_FAILED, "cancelled before its first step"));
    return;
  }
  if (!runner_.settings().paused) {
    end(*goal, gs::STATUS_ABORTED,
        result(rc::RESULT_OPERATION_FAILED,
               "the simulation is playing: pause it first (set_simulation_state)"));
    return;
  }
  if (goal->steps == 0) {
    end(*goal, gs::STATUS_SUCCEEDED, result(rc::RESULT_OK));
    return;
  }
  StepRequest request;
  request.steps = goal->steps;
  request.each_step = [this, id](const World&) {
    std::lock_guard<std::mutex> stepped(mutex_);
    Goal* g = find(id);
    if (!g) return;
    ++g->done;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_feedback_ >= kFeedbackPeriod || g->done == g->steps) {
      last_feedback_ = now;
      feedback(*g);
    }
  };
  request.done = [this, id](bool completed) {
    std::lock_guard<std::mutex> ended(mutex_);
    executing_.reset();
    Goal* g = find(id);
    if (!g) return;
    if (completed) {
      end(*g, gs::STATUS_SUCCEEDED, result(rc::RESULT_OK));
    } else if (g->status == gs::STATUS_CANCELING) {
      end(*g, gs::STATUS_CANCELED,
          result(rc::RESULT_OPERATION_FAILED,
                 "cancelled by its client after " + steps_text(g->done, g->steps)));
    } else {
      end(*g, gs::STATUS_ABORTED,
          result(rc::RESULT_OPERATION_FAILED,
                 "ended after " + steps_text(g->done, g->steps) +
                     ": paused, reset, another world loaded, or a body went unstable (see the "
                     "events)"));
    }
  };
  executing_ = id;
  if (!runner_.request_steps(std::move(request))) {
    executing_.reset();
    end(*goal, gs::STATUS_ABORTED,
        result(rc::RESULT_INCORRECT_STATE, "another step request is still running"));
    return;
  }
  goal->status = gs::STATUS_EXECUTING;
  last_feedback_ = std::chrono::steady_clock::now();
  feedback(*goal);  // 0 done: the goal runs
  publish_status();
}

void SimulateStepsAction::on_cancel(const CancelGoal::Request& q, const dds::RequestId& id) {
  wait_until_served();
  CancelGoal::Response response;
  const Uuid& uuid = q.goal_info().goal_id().uuid();
  const auto& stamp = q.goal_info().stamp();
  const bool any_stamp = stamp.sec() != 0 || stamp.nanosec() != 0;
  bool running = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Goal* named = zero(uuid) ? nullptr : find(uuid);
    for (auto& g : goals_) {
      const bool chosen = zero(uuid)
                              ? !any_stamp || not_after(g.info.stamp(), stamp)
                              : &g == named || (any_stamp && not_after(g.info.stamp(), stamp));
      if (!chosen || terminal(g.status) || g.status == gs::STATUS_CANCELING) continue;
      running = running || g.status == gs::STATUS_EXECUTING;
      g.status = gs::STATUS_CANCELING;
      response.goals_canceling().push_back(g.info);
    }
    if (response.goals_canceling().empty()) {
      response.return_code(!zero(uuid) && !named              ? cg::ERROR_UNKNOWN_GOAL_ID
                           : named && terminal(named->status) ? cg::ERROR_GOAL_TERMINATED
                                                              : cg::ERROR_NONE);
    } else {
      response.return_code(cg::ERROR_NONE);
      publish_status();
    }
  }
  // The running goal ends at the step it reached: a pause ends a step request (the
  // simulation was paused for it, and stays so). A goal not begun ends when its turn comes.
  if (running) {
    const bool queued = runner_.push([this](World&) {
      bool canceling = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        const Goal* g = executing_ ? find(*executing_) : nullptr;
        canceling = g && g->status == gs::STATUS_CANCELING;
      }
      if (canceling) runner_.pause();  // its done() ends it, under the lock
    });
    if (!queued) response.return_code(cg::ERROR_REJECTED);
  }
  cancel_goal_->reply(id, response);
}

void SimulateStepsAction::on_get_result(const GetResult::Request& q, const dds::RequestId& id) {
  wait_until_served();
  const Uuid& uuid = q.goal_id().uuid();
  GetResult::Response response;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Goal* goal = find(uuid);
    if (goal && !terminal(goal->status)) {
      goal->waiting.push_back(id);  // answered when it ends
      return;
    }
    response.status(goal ? goal->status : gs::STATUS_UNKNOWN);
    if (goal) response.result().result(goal->result);
  }
  get_result_->reply(id, response);
}

void SimulateStepsAction::end(Goal& goal, int8_t status, si::Result_ outcome) {
  goal.status = status;
  goal.result = std::move(outcome);
  GetResult::Response response;
  response.status(status);
  response.result().result(goal.result);
  for (const auto& id : goal.waiting) get_result_->reply(id, response);
  goal.waiting.clear();
  publish_status();
}

void SimulateStepsAction::feedback(const Goal& goal) {
  sa::SimulateSteps_FeedbackMessage_ message;
  message.goal_id(goal.info.goal_id());
  message.feedback().completed_steps(goal.done);
  message.feedback().remaining_steps(goal.steps - goal.done);
  feedback_.write(message);
}

void SimulateStepsAction::publish_status() {
  am::GoalStatusArray_ all;
  for (const auto& g : goals_) {
    am::GoalStatus_ s;
    s.goal_info(g.info);
    s.status(g.status);
    all.status_list().push_back(s);
  }
  status_.write(all);
}

}  // namespace macsim
