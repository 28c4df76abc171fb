// Robots are plug-ins: a type registered by name (here one the test writes, through RobotModel
// alone) is built from a world file, stepped, saved and restored with the world, and its typed
// events reach the world's; an unknown type is named with the known ones.
#include "macsim/sim_core/robot_model.h"

#include <gtest/gtest.h>
#include <ode/ode.h>

#include <cstring>
#include <utility>

#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "support/child_process.h"
#include "support/nudge_command.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

/// The smallest robot: one ball that counts its steps and reports every 100th as an event.
class CountingBall final : public RobotModel {
 public:
  CountingBall(const RobotSpec& spec, const RobotBuild& build) : RobotModel(spec) {
    body_ = dBodyCreate(build.world);
    dMass mass;
    dMassSetSphereTotal(&mass, 1.0, 0.1);
    dBodySetMass(body_, &mass);
    const Eigen::Vector3d p = spec.pose.position + Eigen::Vector3d(0, 0, 0.1);
    dBodySetPosition(body_, p.x(), p.y(), p.z());
    geom_ = dCreateSphere(build.space, 0.1);
    dGeomSetBody(geom_, body_);
  }
  ~CountingBall() override {
    dGeomDestroy(geom_);
    dBodyDestroy(body_);
  }
  bool execute(const robot::RobotCommand& command, double) override {
    if (const auto* twist = command.as<robot::Twist>()) {
      push_ = twist->linear;
    } else if (const auto* nudge = command.as<test::Nudge>()) {
      push_ = nudge->force;
    } else {
      return false;
    }
    return true;
  }
  void keep_command(double) override {}
  void before_step(double) override { dBodyAddForce(body_, push_, 0, 0); }
  void after_step(double now, double) override {
    if (++steps_ % 100 == 0) events_.push_back({WorldEvent::Type::Instability, now, name(), "tick"});
  }
  std::vector<WorldEvent> take_events() override { return std::exchange(events_, {}); }
  Pose base_footprint_pose() const override { return base_link_pose(); }
  Pose base_link_pose() const override {
    const dReal* p = dBodyGetPosition(body_);
    return {{p[0], p[1], p[2]}, Eigen::Quaterniond::Identity()};
  }
  Eigen::Vector3d linear_velocity() const override {
    const dReal* v = dBodyGetLinearVel(body_);
    return {v[0], v[1], v[2]};
  }
  Eigen::Vector3d angular_velocity() const override { return Eigen::Vector3d::Zero(); }
  PlanarOdometry odometry() const override { return {}; }
  robot::Capabilities capabilities() const override { return {}; }
  robot::Frames frames() const override { return {}; }
  robot::Readings read(ReadMark&, double now) const override {
    robot::Readings r;
    r.stamp = now;
    return r;
  }
  std::vector<ShapeView> shapes() const override { return {}; }
  std::vector<uint8_t> save_state() const override {
    std::vector<uint8_t> bytes(sizeof steps_ + sizeof push_);
    std::memcpy(bytes.data(), &steps_, sizeof steps_);
    std::memcpy(bytes.data() + sizeof steps_, &push_, sizeof push_);
    return bytes;
  }
  std::optional<std::string> state_problem(const std::vector<uint8_t>& bytes) const override {
    if (bytes.size() != sizeof steps_ + sizeof push_) return std::string("not a ball's state");
    return std::nullopt;
  }
  void load_state(const std::vector<uint8_t>& bytes, const BodyByName&) override {
    std::memcpy(&steps_, bytes.data(), sizeof steps_);
    std::memcpy(&push_, bytes.data() + sizeof steps_, sizeof push_);
  }
  std::vector<dxBody*> bodies() const override { return {body_}; }
  uint64_t steps() const { return steps_; }

 private:
  dBodyID body_;
  dGeomID geom_;
  uint64_t steps_ = 0;
  double push_ = 0;
  std::vector<WorldEvent> events_;
};

WorldSpec ball_world() {
  register_robot_type("counting_ball", [](const RobotSpec& spec, const RobotBuild& build) {
    return std::make_unique<CountingBall>(spec, build);
  });
  return load_world_string(R"(<WORLD><ROBOT><ID>ball</ID><TYPE>counting_ball</TYPE>
      <POS>0,0,0</POS></ROBOT><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE><POS>0,2,0</POS></ROBOT>
      </WORLD>)",
                           "ball.xml");
}

TEST(RobotModel, ARegisteredTypeIsBuiltFromAWorldFileAndStepped) {
  World world(ball_world());
  EXPECT_TRUE(robot_type_known("counting_ball"));
  ASSERT_EQ(world.robots().size(), 2u);
  auto* ball = world.robot_as<CountingBall>("ball");
  ASSERT_NE(ball, nullptr);
  EXPECT_EQ(world.robot_as<CountingBall>("kurt"), nullptr);
  test::run_for(world, 0.25);
  EXPECT_EQ(ball->steps(), world.steps());
  world.robot("ball")->execute(robot::Twist{2.0, 0.0}, world.time());  // a push of 2 N
  test::run_for(world, 0.5);
  EXPECT_GT(ball->base_link_pose().position.x(), 0.05);
}

// A plug-in's command travels as the built-in ones do: through the runner to its robot, into a
// session by its name, read back as its type and replayed to the same hashes; a robot without it
// refuses it.
TEST(RobotModel, APlugInsOwnCommandReachesItsRobotThroughTheRunnerAndSessions) {
  ASSERT_TRUE(test::nudge_registered());
  test::TempDir dir("macsim_plugin_command_");
  const std::string path = dir.path() + "/nudge.session";
  {
    Runner runner(ball_world(), RunSettings{true, 0.0});
    SessionHeader header;
    header.world_file = "ball.xml";
    header.hash_every = 50;
    runner.record(std::make_shared<SessionWriter>(path, header));
    ASSERT_TRUE(runner.push(robot_command("ball", test::Nudge{2.0})));
    ASSERT_TRUE(runner.push(robot_command("kurt", test::Nudge{2.0})));  // not the KURT's: refused
    for (int i = 0; i < 500; ++i) runner.step();
    EXPECT_GT(runner.world().robot("ball")->base_link_pose().position.x(), 0.05);
    EXPECT_EQ(runner.commands_run(CommandSource::Robot), 2u);
    runner.record(nullptr);
  }
  const Session session = read_session(path);
  ASSERT_EQ(session.commands.size(), 1u);  // the one that acted
  const auto* nudge = session.commands[0].command.robot->as<test::Nudge>();
  ASSERT_NE(nudge, nullptr);
  EXPECT_EQ(nudge->force, 2.0);
  Runner again(ball_world(), RunSettings{true, 0.0});
  const ReplayOutcome outcome =
      replay_session(session, again, [](const Command&) { return std::function<WorldSpec()>(); });
  EXPECT_TRUE(outcome.equal) << outcome.message;
  EXPECT_EQ(outcome.commands_run, 1u);
}

TEST(RobotModel, ItsEventsBecomeTheWorldsEvents) {
  World world(ball_world());
  test::run_for(world, 0.25);
  int ticks = 0;
  for (const WorldEvent& e : world.take_events()) {
    if (e.subject == "ball" && e.detail == "tick") ++ticks;
  }
  EXPECT_EQ(ticks, 2);  // steps 100 and 200 of 250
}

TEST(RobotModel, ItsStateIsPartOfTheWorldsHashAndSnapshot) {
  World world(ball_world());
  test::run_for(world, 0.1);
  const WorldSnapshot saved = world.snapshot();
  const uint64_t hash = world.state_hash();
  world.robot("ball")->execute(robot::Twist{1.0, 0.0}, world.time());  // its state only
  EXPECT_NE(world.state_hash(), hash);
  ASSERT_TRUE(world.restore(saved).ok());
  EXPECT_EQ(world.state_hash(), hash);
  EXPECT_EQ(world.robot_as<CountingBall>("ball")->steps(), 100u);
}

TEST(RobotModel, AnUnknownTypeIsNamedWithTheKnownOnes) {
  try {
    load_world_string(R"(<WORLD><ROBOT><ID>x</ID><TYPE>hovercraft</TYPE></ROBOT></WORLD>)",
                      "x.xml");
    FAIL() << "an unknown robot type was accepted";
  } catch (const WorldFileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("hovercraft"), std::string::npos) << what;
    EXPECT_NE(what.find("diff_drive"), std::string::npos) << what;
    EXPECT_NE(what.find("kurt3d"), std::string::npos) << what;
  }
  RobotSpec hovercraft;
  hovercraft.name = "x";
  hovercraft.type = "hovercraft";
  EXPECT_THROW(build_robot(hovercraft, RobotBuild{}), std::invalid_argument);
}

}  // namespace
}  // namespace macsim
