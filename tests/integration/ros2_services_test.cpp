// The ROS 2 side of macsim that is not a topic: the simulation_interfaces services, called as
// an rmw_fastrtps_cpp client calls them (rq/.../rr/... topics, replies tied by sample
// identity), and ros_discovery_info, which makes `ros2 node list` show macsim.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "macsim/dds/convert.h"
#include "macsim/dds/ros2_service.h"
#include "macsim/msg/action_msgsPubSubTypes.h"
#include "macsim/msg/rmw_dds_commonPubSubTypes.h"
#include "macsim/msg/simulation_interfacesPubSubTypes.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
#include "support/ros2_service_calls.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace si = simulation_interfaces::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;
namespace rc = si::Result_Constants;
namespace st = si::SimulationState_Constants;
namespace sa = simulation_interfaces::action::dds_;
namespace am = action_msgs;

namespace tag {  // each service as one type: its request and response types
struct DeleteEntity {
  using Req = ss::DeleteEntity_Request_PubSubType;
  using Resp = ss::DeleteEntity_Response_PubSubType;
};
struct GetAvailableWorlds {
  using Req = ss::GetAvailableWorlds_Request_PubSubType;
  using Resp = ss::GetAvailableWorlds_Response_PubSubType;
};
struct GetCurrentWorld {
  using Req = ss::GetCurrentWorld_Request_PubSubType;
  using Resp = ss::GetCurrentWorld_Response_PubSubType;
};
struct GetEntities {
  using Req = ss::GetEntities_Request_PubSubType;
  using Resp = ss::GetEntities_Response_PubSubType;
};
struct GetEntityBounds {
  using Req = ss::GetEntityBounds_Request_PubSubType;
  using Resp = ss::GetEntityBounds_Response_PubSubType;
};
struct GetEntityInfo {
  using Req = ss::GetEntityInfo_Request_PubSubType;
  using Resp = ss::GetEntityInfo_Response_PubSubType;
};
struct GetEntityState {
  using Req = ss::GetEntityState_Request_PubSubType;
  using Resp = ss::GetEntityState_Response_PubSubType;
};
struct GetSimulationState {
  using Req = ss::GetSimulationState_Request_PubSubType;
  using Resp = ss::GetSimulationState_Response_PubSubType;
};
struct GetSimulatorFeatures {
  using Req = ss::GetSimulatorFeatures_Request_PubSubType;
  using Resp = ss::GetSimulatorFeatures_Response_PubSubType;
};
struct GetSpawnables {
  using Req = ss::GetSpawnables_Request_PubSubType;
  using Resp = ss::GetSpawnables_Response_PubSubType;
};
struct LoadWorld {
  using Req = ss::LoadWorld_Request_PubSubType;
  using Resp = ss::LoadWorld_Response_PubSubType;
};
struct ResetSimulation {
  using Req = ss::ResetSimulation_Request_PubSubType;
  using Resp = ss::ResetSimulation_Response_PubSubType;
};
struct SetEntityState {
  using Req = ss::SetEntityState_Request_PubSubType;
  using Resp = ss::SetEntityState_Response_PubSubType;
};
struct SetSimulationState {
  using Req = ss::SetSimulationState_Request_PubSubType;
  using Resp = ss::SetSimulationState_Response_PubSubType;
};
struct SpawnEntity {
  using Req = ss::SpawnEntity_Request_PubSubType;
  using Resp = ss::SpawnEntity_Response_PubSubType;
};
struct StepSimulation {
  using Req = ss::StepSimulation_Request_PubSubType;
  using Resp = ss::StepSimulation_Response_PubSubType;
};
struct UnloadWorld {
  using Req = ss::UnloadWorld_Request_PubSubType;
  using Resp = ss::UnloadWorld_Response_PubSubType;
};
}  // namespace tag

/// One box, 0.2 m a side, as this project's XML spawns it.
const char* kCrate =
    "<ENVIRONMENT><OBJECT><ID>box</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>"
    "<DIMS>0.2,0.2,0.2</DIMS><POS>0,0,0.1</POS><USER_DATA>crate</USER_DATA></OBJECT></ENVIRONMENT>";

class SimulationInterfaces : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    macsim_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("macsim"), "--world", source("worlds/small_room.xml"),
                                 "--domain", std::to_string(domain_), "--cameras", "off"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ =
        std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "services_test"});
    calls_ = std::make_unique<Ros2ServiceCalls>(*participant_);
  }
  void TearDown() override {
    calls_.reset();
    participant_.reset();
    if (!macsim_) return;
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }
  /// Calls /macsim/<service> once its server is seen (one client per service, kept).
  template <class Service>
  typename Service::Resp::type call(const std::string& service,
                                    const typename Service::Req::type& request) {
    return calls_->call<typename Service::Req, typename Service::Resp>(service, request);
  }
  uint8_t state() {
    return call<tag::GetSimulationState>("get_simulation_state", {}).state().state();
  }
  uint8_t set_state(uint8_t target) {
    ss::SetSimulationState_Request_ q;
    q.state().state(target);
    return call<tag::SetSimulationState>("set_simulation_state", q).result().result();
  }
  ss::GetEntityState_Response_ entity_state(const std::string& name) {
    ss::GetEntityState_Request_ q;
    q.entity(name);
    return call<tag::GetEntityState>("get_entity_state", q);
  }
  ss::SpawnEntity_Response_ spawn(const std::string& name, bool rename, double x, double y) {
    ss::SpawnEntity_Request_ q;
    q.name(name);
    q.allow_renaming(rename);
    q.resource_string(kCrate);
    q.initial_pose().pose().position().x(x);
    q.initial_pose().pose().position().y(y);
    q.initial_pose().pose().orientation().w(1);
    return call<tag::SpawnEntity>("spawn_entity", q);
  }
  std::vector<std::string> entities(const si::EntityFilters_& filters) {
    ss::GetEntities_Request_ q;
    q.filters(filters);
    const auto r = call<tag::GetEntities>("get_entities", q);
    EXPECT_EQ(r.result().result(), rc::RESULT_OK) << r.result().error_message();
    return r.entities();
  }

  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<Ros2ServiceCalls> calls_;
};

bool contains(const std::vector<std::string>& all, const std::string& one) {
  return std::find(all.begin(), all.end(), one) != all.end();
}

TEST_F(SimulationInterfaces, PlayPauseStepResetAndStopAsTheStandardSays) {
  const auto features = call<tag::GetSimulatorFeatures>("get_simulator_features", {});
  const auto& f = features.features().features();
  namespace sf = si::SimulatorFeatures_Constants;
  for (uint16_t wanted :
       {sf::SPAWNING, sf::DELETING, sf::ENTITY_STATE_GETTING, sf::ENTITY_STATE_SETTING,
        sf::STEP_SIMULATION_MULTIPLE, sf::SIMULATION_STATE_PAUSE, sf::WORLD_LOADING}) {
    EXPECT_EQ(std::count(f.begin(), f.end(), wanted), 1) << "feature " << wanted;
  }
  EXPECT_EQ(std::count(f.begin(), f.end(), sf::NAMED_POSES), 0);
  EXPECT_EQ(features.features().spawn_formats(), std::vector<std::string>{"macsim_xml"});

  EXPECT_EQ(state(), st::STATE_PLAYING);
  ss::StepSimulation_Request_ steps;
  steps.steps(10);
  EXPECT_EQ(call<tag::StepSimulation>("step_simulation", steps).result().result(),
            rc::RESULT_OPERATION_FAILED);  // playing: no stepping on request
  EXPECT_EQ(set_state(st::STATE_PAUSED), rc::RESULT_OK);
  EXPECT_EQ(set_state(st::STATE_PAUSED),
            ss::SetSimulationState_Response_Constants::ALREADY_IN_TARGET_STATE);
  EXPECT_EQ(state(), st::STATE_PAUSED);

  // Paused, ten steps take the time exactly ten steps on (small_room steps 1 ms).
  const double before = dds::to_seconds(entity_state("kurt").state().header().stamp());
  const auto stepped = call<tag::StepSimulation>("step_simulation", steps);
  EXPECT_EQ(stepped.result().result(), rc::RESULT_OK) << stepped.result().error_message();
  const double after = dds::to_seconds(entity_state("kurt").state().header().stamp());
  EXPECT_NEAR(after - before, 10 * 0.001, 1e-9);
  std::this_thread::sleep_for(300ms);  // and nothing more while paused
  EXPECT_NEAR(dds::to_seconds(entity_state("kurt").state().header().stamp()), after, 1e-9);

  ss::ResetSimulation_Request_ reset;
  reset.scope(ss::ResetSimulation_Request_Constants::SCOPE_TIME);
  EXPECT_EQ(call<tag::ResetSimulation>("reset_simulation", reset).result().result(),
            rc::RESULT_FEATURE_UNSUPPORTED);  // time alone cannot go back
  reset.scope(ss::ResetSimulation_Request_Constants::SCOPE_TIME |
              ss::ResetSimulation_Request_Constants::SCOPE_STATE);
  EXPECT_EQ(call<tag::ResetSimulation>("reset_simulation", reset).result().result(), rc::RESULT_OK);
  EXPECT_EQ(dds::to_seconds(entity_state("kurt").state().header().stamp()), 0.0);

  // Stopped = paused at the start; playing again runs the clock.
  EXPECT_EQ(call<tag::StepSimulation>("step_simulation", steps).result().result(), rc::RESULT_OK);
  EXPECT_EQ(set_state(st::STATE_STOPPED), rc::RESULT_OK);
  EXPECT_EQ(state(), st::STATE_STOPPED);
  EXPECT_EQ(dds::to_seconds(entity_state("kurt").state().header().stamp()), 0.0);
  EXPECT_EQ(set_state(st::STATE_NO_WORLD),
            ss::SetSimulationState_Response_Constants::INCORRECT_TRANSITION);
  EXPECT_EQ(set_state(st::STATE_PLAYING), rc::RESULT_OK);
  EXPECT_EQ(state(), st::STATE_PLAYING);
  std::this_thread::sleep_for(300ms);
  EXPECT_GT(dds::to_seconds(entity_state("kurt").state().header().stamp()),
            0.1);  // 300 ms at rtf 1
}

TEST_F(SimulationInterfaces, EntitiesAreListedSpawnedMovedAndDeleted) {
  si::EntityFilters_ all;
  const auto everything = entities(all);
  EXPECT_TRUE(contains(everything, "kurt"));
  EXPECT_GE(everything.size(), 5u);  // the robot and the room's walls and objects
  si::EntityFilters_ robots;
  robots.categories().resize(1);
  robots.categories()[0].category(si::EntityCategory_Constants::CATEGORY_ROBOT);
  EXPECT_EQ(entities(robots), std::vector<std::string>{"kurt"});
  ss::GetEntityInfo_Request_ info_q;
  info_q.entity("kurt");
  const auto info = call<tag::GetEntityInfo>("get_entity_info", info_q);
  EXPECT_EQ(info.info().category().category(), si::EntityCategory_Constants::CATEGORY_ROBOT);

  // Spawned from this project's XML: one object takes the entity's name.
  const auto crate = spawn("crate", false, 1.0, -0.5);
  ASSERT_EQ(crate.result().result(), rc::RESULT_OK) << crate.result().error_message();
  EXPECT_EQ(crate.entity_name(), "crate");
  EXPECT_EQ(spawn("crate", false, 1.5, 0.5).result().result(),
            ss::SpawnEntity_Response_Constants::NAME_NOT_UNIQUE);
  const auto renamed = spawn("crate", true, 1.5, 0.5);
  ASSERT_EQ(renamed.result().result(), rc::RESULT_OK) << renamed.result().error_message();
  EXPECT_EQ(renamed.entity_name(), "crate_2");
  const auto placed = entity_state("crate");
  ASSERT_EQ(placed.result().result(), rc::RESULT_OK);
  EXPECT_NEAR(placed.state().pose().position().x(), 1.0, 0.01);
  EXPECT_NEAR(placed.state().pose().position().y(), -0.5, 0.01);
  EXPECT_NEAR(placed.state().pose().position().z(), 0.1, 0.01);
  ss::GetEntityBounds_Request_ bounds_q;
  bounds_q.entity("crate");
  const auto bounds = call<tag::GetEntityBounds>("get_entity_bounds", bounds_q);
  ASSERT_EQ(bounds.bounds().points().size(), 2u);
  EXPECT_NEAR(bounds.bounds().points()[0].x(), -0.1, 1e-9);
  EXPECT_NEAR(bounds.bounds().points()[1].z(), 0.1, 1e-9);  // the box is centred on its frame

  // Filters: a regular expression, tags (the user data), a sphere around the second crate.
  si::EntityFilters_ named;
  named.filter("^crate");
  EXPECT_EQ(entities(named), (std::vector<std::string>{"crate", "crate_2"}));
  si::EntityFilters_ tagged;
  tagged.tags().tags({"crate", "portable"});
  tagged.tags().filter_mode(si::TagsFilter_Constants::FILTER_MODE_ALL);
  EXPECT_EQ(entities(tagged).size(), 2u);
  si::EntityFilters_ near;
  near.bounds().type(si::Bounds_Constants::TYPE_SPHERE);
  near.bounds().points().resize(2);
  near.bounds().points()[0].x(1.5);
  near.bounds().points()[0].y(0.5);
  near.bounds().points()[1].x(0.15);
  EXPECT_EQ(entities(near), std::vector<std::string>{"crate_2"});
  si::EntityFilters_ broken;
  broken.filter("(unclosed");
  ss::GetEntities_Request_ broken_q;
  broken_q.filters(broken);
  EXPECT_EQ(call<tag::GetEntities>("get_entities", broken_q).result().result(),
            rc::RESULT_OPERATION_FAILED);

  // Set: a new pose and twist at once; hostile numbers and unknown names change nothing.
  ss::SetEntityState_Request_ set;
  set.entity("crate");
  set.state().pose().position().x(0.5);
  set.state().pose().position().y(-1.0);
  set.state().pose().position().z(0.1);
  set.state().pose().orientation().w(1);
  set.state().twist().linear().x(0.2);
  const auto moved = call<tag::SetEntityState>("set_entity_state", set);
  EXPECT_EQ(moved.result().result(), rc::RESULT_OK) << moved.result().error_message();
  const auto now = entity_state("crate");
  EXPECT_NEAR(now.state().pose().position().x(), 0.5, 0.05);
  EXPECT_NEAR(now.state().pose().position().y(), -1.0, 0.01);
  set.state().pose().position().x(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(call<tag::SetEntityState>("set_entity_state", set).result().result(),
            ss::SetEntityState_Response_Constants::INVALID_POSE);
  set.state().pose().position().x(1e308);
  EXPECT_EQ(call<tag::SetEntityState>("set_entity_state", set).result().result(),
            ss::SetEntityState_Response_Constants::INVALID_POSE);
  set.entity("no_such_thing");
  EXPECT_EQ(call<tag::SetEntityState>("set_entity_state", set).result().result(),
            rc::RESULT_NOT_FOUND);
  EXPECT_TRUE(std::isfinite(entity_state("crate").state().pose().position().x()));

  // Delete; a reset of everything removes what was spawned.
  ss::DeleteEntity_Request_ del;
  del.entity("crate");
  EXPECT_EQ(call<tag::DeleteEntity>("delete_entity", del).result().result(), rc::RESULT_OK);
  EXPECT_EQ(entity_state("crate").result().result(), rc::RESULT_NOT_FOUND);
  EXPECT_EQ(call<tag::DeleteEntity>("delete_entity", del).result().result(), rc::RESULT_NOT_FOUND);
  ss::ResetSimulation_Request_ reset;  // SCOPE_DEFAULT: all
  EXPECT_EQ(call<tag::ResetSimulation>("reset_simulation", reset).result().result(), rc::RESULT_OK);
  EXPECT_EQ(entity_state("crate_2").result().result(), rc::RESULT_NOT_FOUND);
  EXPECT_EQ(entities(all), everything);

  // What is not served says so.
  EXPECT_EQ(call<tag::UnloadWorld>("unload_world", {}).result().result(),
            rc::RESULT_FEATURE_UNSUPPORTED);
}

TEST_F(SimulationInterfaces, WorldsAreListedAndLoadedAndBadOnesRefused) {
  const auto available = call<tag::GetAvailableWorlds>("get_available_worlds", {});
  ASSERT_EQ(available.result().result(), rc::RESULT_OK);
  std::vector<std::string> names;
  for (const auto& w : available.worlds()) names.push_back(w.name());
  EXPECT_TRUE(contains(names, "small_room"));
  EXPECT_TRUE(contains(names, "DemoWorld_v1"));
  EXPECT_FALSE(contains(names, "cans"));  // an environment, not a world
  const auto spawnables = call<tag::GetSpawnables>("get_spawnables", {});
  bool cans = false;
  for (const auto& s : spawnables.spawnables())
    cans |= s.uri().find("objects/cans.xml") != std::string::npos;
  EXPECT_TRUE(cans);

  ss::LoadWorld_Request_ load;
  load.uri("file://" + source("worlds/small_room.xml"));
  const auto loaded = call<tag::LoadWorld>("load_world", load);
  ASSERT_EQ(loaded.result().result(), rc::RESULT_OK) << loaded.result().error_message();
  EXPECT_EQ(loaded.world().name(), "small_room");
  EXPECT_EQ(state(), st::STATE_STOPPED);  // a loaded world waits to be played
  EXPECT_EQ(call<tag::GetCurrentWorld>("get_current_world", {}).world().name(), "small_room");

  load.uri("file://" + source("worlds/world.sdf"));
  EXPECT_EQ(call<tag::LoadWorld>("load_world", load).result().result(),
            ss::LoadWorld_Response_Constants::UNSUPPORTED_FORMAT);
  load.uri("");
  EXPECT_EQ(call<tag::LoadWorld>("load_world", load).result().result(),
            ss::LoadWorld_Response_Constants::NO_RESOURCE);
  load.resource_string("<WORLD><OBJECT><ID>x</ID><SHAPE>BOX</WORLD>");
  const auto broken = call<tag::LoadWorld>("load_world", load);
  EXPECT_EQ(broken.result().result(), ss::LoadWorld_Response_Constants::RESOURCE_PARSE_ERROR);
  EXPECT_NE(broken.result().error_message().find("resource_string.xml"), std::string::npos)
      << broken.result().error_message();
  EXPECT_EQ(call<tag::GetCurrentWorld>("get_current_world", {}).world().name(), "small_room");
}

/// A ROS 2 action client of SimulateSteps as rmw_fastrtps carries one: three services under
/// /macsim/simulate_steps/_action/ and the feedback and status topics.
struct SimulateStepsClient {
  using Uuid = unique_identifier_msgs::msg::dds_::UUID_;
  explicit SimulateStepsClient(dds::Participant& p)
      : send_goal(p, std::string(kAction) + "send_goal"),
        cancel_goal(p, std::string(kAction) + "cancel_goal"),
        get_result(p, std::string(kAction) + "get_result"),
        feedback(p, "rt/macsim/simulate_steps/_action/feedback", 100000, dds::QosFamily::State),
        status(p, "rt/macsim/simulate_steps/_action/status", 100, dds::QosFamily::Latched) {}
  bool ready() {
    return send_goal.wait_for_service(10s) && cancel_goal.wait_for_service(10s) &&
           get_result.wait_for_service(10s);
  }
  static Uuid id(uint8_t n) {
    Uuid u;
    u.uuid().fill(0x5a);
    u.uuid()[15] = n;
    return u;
  }
  bool send(uint8_t n, uint64_t steps) {
    sa::SimulateSteps_SendGoal_Request_ q;
    q.goal_id(id(n));
    q.goal().steps(steps);
    const auto r = send_goal.call(q, 10s);
    return r && r->accepted();
  }
  sa::SimulateSteps_GetResult_Response_ result(uint8_t n, std::chrono::milliseconds timeout = 60s) {
    sa::SimulateSteps_GetResult_Request_ q;
    q.goal_id(id(n));
    return get_result.call(q, timeout).value_or(sa::SimulateSteps_GetResult_Response_{});
  }
  std::optional<am::srv::dds_::CancelGoal_Response_> cancel(std::optional<uint8_t> n) {
    am::srv::dds_::CancelGoal_Request_ q;
    if (n) q.goal_info().goal_id(id(*n));
    return cancel_goal.call(q, 10s);
  }
  /// The feedback of goal n, in order.
  std::vector<sa::SimulateSteps_Feedback_> feedback_of(uint8_t n) {
    std::vector<sa::SimulateSteps_Feedback_> of;
    for (const auto& m : feedback.all())
      if (m.goal_id().uuid() == id(n).uuid()) of.push_back(m.feedback());
    return of;
  }
  static constexpr const char* kAction = "/macsim/simulate_steps/_action/";
  dds::ServiceClient<sa::SimulateSteps_SendGoal_Request_PubSubType,
                     sa::SimulateSteps_SendGoal_Response_PubSubType>
      send_goal;
  dds::ServiceClient<am::srv::dds_::CancelGoal_Request_PubSubType,
                     am::srv::dds_::CancelGoal_Response_PubSubType>
      cancel_goal;
  dds::ServiceClient<sa::SimulateSteps_GetResult_Request_PubSubType,
                     sa::SimulateSteps_GetResult_Response_PubSubType>
      get_result;
  Samples<sa::SimulateSteps_FeedbackMessage_PubSubType> feedback;
  Samples<am::msg::dds_::GoalStatusArray_PubSubType> status;
};

TEST_F(SimulationInterfaces, SimulateStepsGivesProgressAndIsCancelledAtTheStepItReached) {
  namespace gs = am::msg::dds_::GoalStatus_Constants;
  namespace cg = am::srv::dds_::CancelGoal_Response_Constants;
  const auto f =
      call<tag::GetSimulatorFeatures>("get_simulator_features", {}).features().features();
  EXPECT_EQ(std::count(f.begin(), f.end(), si::SimulatorFeatures_Constants::STEP_SIMULATION_ACTION),
            1);
  SimulateStepsClient action(*participant_);
  ASSERT_TRUE(action.ready());

  // Playing: accepted, then aborted saying why (the action's definition).
  ASSERT_TRUE(action.send(1, 10));
  const auto playing = action.result(1);
  EXPECT_EQ(playing.status(), gs::STATUS_ABORTED);
  EXPECT_EQ(playing.result().result().result(), rc::RESULT_OPERATION_FAILED);
  EXPECT_NE(playing.result().result().error_message().find("playing"), std::string::npos);
  EXPECT_FALSE(action.send(1, 10)) << "a goal id taken twice";

  // Paused: 3,000 steps (small_room steps 1 ms) take the clock exactly 3 s on, with feedback
  // that counts up to them.
  ASSERT_EQ(set_state(st::STATE_PAUSED), rc::RESULT_OK);
  const double before = dds::to_seconds(entity_state("kurt").state().header().stamp());
  ASSERT_TRUE(action.send(2, 3000));
  const auto done = action.result(2);
  EXPECT_EQ(done.status(), gs::STATUS_SUCCEEDED);
  EXPECT_EQ(done.result().result().result(), rc::RESULT_OK);
  EXPECT_NEAR(dds::to_seconds(entity_state("kurt").state().header().stamp()) - before, 3.0, 1e-9);
  // The feedback topic and the result service are not ordered with each other: the last
  // feedback may come after the result.
  ASSERT_TRUE(action.feedback
                  .wait_for(
                      [&](const sa::SimulateSteps_FeedbackMessage_& m) {
                        return m.goal_id().uuid() == SimulateStepsClient::id(2).uuid() &&
                               m.feedback().completed_steps() == 3000;
                      },
                      5s)
                  .has_value())
      << "no feedback of the last step";
  auto progress = action.feedback_of(2);
  ASSERT_GE(progress.size(), 2u);
  for (std::size_t i = 0; i < progress.size(); ++i) {
    EXPECT_EQ(progress[i].completed_steps() + progress[i].remaining_steps(), 3000u);
    if (i > 0) {
      EXPECT_GT(progress[i].completed_steps(), progress[i - 1].completed_steps());
    }
  }
  EXPECT_EQ(progress.front().completed_steps(), 0u);
  EXPECT_EQ(progress.back().completed_steps(), 3000u);

  // A billion steps, cancelled once they run: the result names the step reached, and the
  // clock stops there.
  ASSERT_TRUE(action.send(3, 1000000000));
  const auto running = action.feedback.wait_for(
      [&](const sa::SimulateSteps_FeedbackMessage_& m) {
        return m.goal_id().uuid() == SimulateStepsClient::id(3).uuid() &&
               m.feedback().completed_steps() > 1000;
      },
      30s);
  ASSERT_TRUE(running.has_value()) << "no feedback of a running goal";
  const auto cancelled = action.cancel(3);
  ASSERT_TRUE(cancelled.has_value());
  EXPECT_EQ(cancelled->return_code(), cg::ERROR_NONE);
  ASSERT_EQ(cancelled->goals_canceling().size(), 1u);
  EXPECT_EQ(cancelled->goals_canceling()[0].goal_id().uuid(), SimulateStepsClient::id(3).uuid());
  const auto ended = action.result(3);
  EXPECT_EQ(ended.status(), gs::STATUS_CANCELED);
  const std::string why = ended.result().result().error_message();
  EXPECT_NE(why.find("cancelled by its client after"), std::string::npos) << why;
  EXPECT_NE(why.find("of 1000000000 steps"), std::string::npos) << why;
  const double stopped = dds::to_seconds(entity_state("kurt").state().header().stamp());
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(dds::to_seconds(entity_state("kurt").state().header().stamp()), stopped);
  EXPECT_LT(stopped - before, 3.0 + 1e6 * 0.001) << "a billion steps cannot have run";
  EXPECT_EQ(state(), st::STATE_PAUSED);
  // The status topic says what became of each goal.
  const auto statuses = action.status.wait_for(
      [](const am::msg::dds_::GoalStatusArray_& a) {
        return a.status_list().size() == 3 && a.status_list()[2].status() == gs::STATUS_CANCELED;
      },
      5s);
  ASSERT_TRUE(statuses.has_value());
  EXPECT_EQ(statuses->status_list()[0].status(), gs::STATUS_ABORTED);
  EXPECT_EQ(statuses->status_list()[1].status(), gs::STATUS_SUCCEEDED);

  // Cancelling it again, or a goal never sent, says which.
  EXPECT_EQ(action.cancel(3)->return_code(), cg::ERROR_GOAL_TERMINATED);
  EXPECT_EQ(action.cancel(9)->return_code(), cg::ERROR_UNKNOWN_GOAL_ID);
  EXPECT_EQ(action.result(9, 10s).status(), gs::STATUS_UNKNOWN);
  // The simulation steps on request again.
  ss::StepSimulation_Request_ one;
  one.steps(1);
  EXPECT_EQ(call<tag::StepSimulation>("step_simulation", one).result().result(), rc::RESULT_OK);
}

TEST_F(SimulationInterfaces, RosDiscoveryInfoNamesTheNodeAndItsEndpoints) {
  namespace rdc = rmw_dds_common::msg::dds_;
  Samples<rdc::ParticipantEntitiesInfo_PubSubType> graph(*participant_, "ros_discovery_info", 100,
                                                         dds::QosFamily::Latched);
  const auto macsim = graph.wait_for(
      [](const rdc::ParticipantEntitiesInfo_& p) {
        return p.node_entities_info_seq().size() == 1 &&
               p.node_entities_info_seq()[0].node_name() == "macsim";
      },
      10s);
  ASSERT_TRUE(macsim.has_value());
  const auto& node = macsim->node_entities_info_seq()[0];
  EXPECT_EQ(node.node_namespace(), "/");
  // 22 services: a request reader and a reply writer each, beside the topics
  EXPECT_GE(node.reader_gid_seq().size(), 22u + 5u);
  EXPECT_GE(node.writer_gid_seq().size(), 22u + 20u);
  const auto& gid = macsim->gid().data();
  EXPECT_EQ(gid[12], 0x00);  // the participant's entity id: 00 00 01 c1
  EXPECT_EQ(gid[15], 0xc1);
  for (const auto& w : node.writer_gid_seq()) {  // every endpoint of the same participant
    EXPECT_TRUE(std::equal(gid.begin(), gid.begin() + 12, w.data().begin()));
    EXPECT_EQ(w.data()[15] & 0x04, 0x00);  // a writer's entity kind: 0x02 or 0x03
  }
  for (const auto& r : node.reader_gid_seq()) EXPECT_EQ(r.data()[15] & 0x04, 0x04);  // readers
}

}  // namespace
}  // namespace macsim::test
