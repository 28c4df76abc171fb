#include "trial_robot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <thread>
#include <vector>

#include "macsim/client/latest.h"
#include "macsim/client/robot_client.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/robot/kurt3d_description.h"

namespace affordances {

namespace mm = macsim_msgs::msg::dds_;
namespace sv = macsim::client::supervisor;
namespace until = macsim::client::step_until;
using Conditions = std::vector<until::Condition>;
using namespace std::chrono_literals;
using namespace std::string_literals;
using macsim::client::stamp_seconds;

namespace {

// Time in a trial. The robot's encoder frames (odometry, ground truth, crane state) come every
// 10 ms of sim time, the laser's sweeps every 1/75 s, from the reset on. The controller decides
// only at 6 ms past a multiple of 20 ms (a tick; the first requests step 6 ms, every later one
// a whole number of ticks: the world's step must divide 2 ms), so the newest frame due is always
// the one stamped within the last 8 ms, and the one before it is older: which sample a decision
// reads never depends on how fast DDS delivered it. Where the controller has nothing to decide
// but when to stop (drive to a distance, wait for the crane, push, climb), one request steps
// until the simulator finds its condition true at a tick (reading the same newest samples the
// controller would), and brings back the readings of every tick it needs.
constexpr double kFirst = 0.006;
constexpr double kTick = 0.02;
constexpr double kFrameWindow = 0.008;
// The perception instant, once the crane swung out of the cameras' view (it turns at 1 rad/s):
// the sweep of 0.8 s is 6 ms old, the one before 19 ms; the cameras (1.25 Hz from the reset on)
// took their pair at 0.801 s.
constexpr double kPerceiveAt = 0.806;
constexpr double kScanWindow = 0.012;

// The KURT3D's crane, from its description.
namespace description = macsim::robot::kurt3d;
constexpr double kBaseHeight = description::kBaseHeight;
constexpr double kPivotX = description::kPivotX, kPivotZ = description::kPivotHeight,
                 kBoom = description::kBoomLength;
constexpr double kLiftMin = description::kLiftMin, kLiftMax = description::kLiftMax;
constexpr double kMagnetBelowTip = description::kMagnetBelowTip;
// Out of the laser's plane while it looks (the boom ahead would shadow the sweep).
constexpr double kAsideSlew = -0.75;

uint64_t mix(uint64_t trace, uint64_t value) {
  uint64_t z = trace ^ (value + 0x9E3779B97F4A7C15ull + (trace << 6) + (trace >> 2));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

namespace {

/// A box component at (x, y, z) in the object's frame.
mm::Component_ box(const std::array<float, 3>& colour, double sx, double sy, double sz, double x,
                   double y, double z) {
  mm::Component_ c;
  c.shape(mm::SHAPE_BOX);
  c.size({sx, sy, sz});
  c.pose().orientation().w(1.0);
  c.pose().position(macsim::dds::point(x, y, z));
  c.color({colour[0], colour[1], colour[2], 1.0f});
  return c;
}

// The walls of passages and doorsteps: 0.3 m wide, 0.4 m high.
constexpr double kWallWidth = 0.3, kWallHeight = 0.4, kDoorstepWallDepth = 0.15;

}  // namespace

/// The object (or ramp) the supervisor spawns for a trial, as its seed drew it.
mm::Object_ trial_object(const TrialSpec& s) {
  mm::Object_ object;
  mm::Component_ c;
  c.pose().orientation().w(1.0);
  c.color({s.colour[0], s.colour[1], s.colour[2], 1.0f});
  object.pose().orientation().w(1.0);
  object.name("trial_object");
  object.material(s.material);
  object.magnetizable(s.magnetizable);
  object.density(s.density > 0 ? s.density : 1000.0);
  object.user_data("trial");
  double z = s.height() / 2;
  switch (s.shape) {
    case Shape::Box:
    case Shape::Joist:
    case Shape::Step:
      c.shape(mm::SHAPE_BOX);
      c.size({s.size[0], s.size[1], s.size[2]});
      break;
    case Shape::Cylinder:
      c.shape(mm::SHAPE_CYLINDER);
      c.size({s.size[0] / 2, 0, s.size[2]});
      break;
    case Shape::LyingCylinder:  // its axis across the robot's way, turned by yaw
      c.shape(mm::SHAPE_CYLINDER);
      c.size({s.size[0] / 2, 0, s.size[2]});
      object.pose().orientation(macsim::dds::quaternion(
          std::cos(s.yaw / 2) * std::sin(M_PI / 4), std::sin(s.yaw / 2) * std::sin(M_PI / 4),
          std::sin(s.yaw / 2) * std::cos(M_PI / 4), std::cos(s.yaw / 2) * std::cos(M_PI / 4)));
      break;
    case Shape::Sphere:
      c.shape(mm::SHAPE_SPHERE);
      c.size({s.size[0] / 2, 0, 0});
      break;
    case Shape::Ramp:
      c.shape(mm::SHAPE_BOX);
      object.kind(mm::KIND_RAMP);
      object.ramp({s.ramp_width, s.ramp_height, s.ramp_angle});
      z = 0;
      break;
    case Shape::Doorstep:  // the bar, and a wall on each side of it (the frame's origin: floor)
    case Shape::Passage: {
      z = 0;
      const bool door = s.shape == Shape::Doorstep;
      const double depth = door ? kDoorstepWallDepth : s.size[0];
      for (double side : {-1.0, 1.0}) {
        object.components().push_back(box(s.colour, depth, kWallWidth, kWallHeight, 0,
                                          side * (s.gap + kWallWidth) / 2, kWallHeight / 2));
      }
      if (!door) break;
      c = box(s.colour, s.size[0], s.gap, s.size[2], 0, 0, s.size[2] / 2);
      break;
    }
  }
  object.portable(!s.fixed && s.shape != Shape::Ramp);
  if (s.shape != Shape::Passage) object.components().push_back(c);
  object.pose().position(macsim::dds::point(s.x, s.y, z));
  return object;
}

/// The object a stack trial's crane carries, where it stands beside the robot.
mm::Object_ carried_object(const Carried& a) {
  mm::Object_ object;
  object.name("carried_object");
  object.material(a.material);
  object.magnetizable(true);
  object.density(a.density);
  object.portable(true);
  object.user_data("trial");
  object.pose().orientation().w(1.0);
  object.pose().position(macsim::dds::point(a.x, a.y, a.size[2] / 2));
  mm::Component_ c = box(a.colour, a.size[0], a.size[1], a.size[2], 0, 0, 0);
  if (a.shape == Shape::Cylinder) {
    c.shape(mm::SHAPE_CYLINDER);
    c.size({a.size[0] / 2, 0, a.size[2]});
  }
  object.components().push_back(c);
  return object;
}

/// The robot and its simulator as a trial uses them over DDS: the clients, the lock-step
/// advance, the commands, the readings, the supervisor's calls, and the trial under way.
struct TrialLink {
  explicit TrialLink(const InstanceOptions& options)
      : o(options),
        participant({options.domain, options.profile, "affordance_trials"}),
        drive(participant, options.robot, kReading),
        crane(participant, options.robot, kReading),
        cameras(participant, options.robot, kReading),
        laser(participant, options.robot, true, kReading),
        supervisor(participant),
        simulation(participant),
        truth(participant, macsim::dds::topics::ground_truth(options.robot), kReading) {}
  /// A lock-step simulator sends each sample once, at a request's end: read reliably, so that
  /// one lost on a network is sent again.
  static constexpr auto kReading = macsim::dds::QosFamily::LockstepSensor;

  InstanceOptions o;
  macsim::dds::Participant participant;
  macsim::client::RobotClient drive;
  macsim::client::Crane crane;
  macsim::client::StereoCamera cameras;
  macsim::client::Laser laser;
  macsim::client::SupervisorClient supervisor;
  macsim::client::SimulationClient simulation;
  macsim::client::Latest<nav_msgs::msg::dds_::Odometry_PubSubType> truth;

  // the trial under way
  double now = 0;
  double dt = 0;  // the world's step, s (from the first step's reply)
  uint64_t steps = 0, hash = 0, trace = 0;
  double speed = 0;
  macsim::affordances::SensorInputs inputs;  // the last look's (keep_inputs)

  /// How many timeouts a simulator still there may take to answer or to send a sample. A
  /// loaded machine delays, it does not lose: a simulator that left is noticed sooner (its
  /// participant unmatched, or an acknowledged request silent: the client's Gone).
  static constexpr int kPatience = 6;
  std::chrono::milliseconds patience() const { return kPatience * o.timeout; }

  mm::SupervisorReply_ call(const sv::Request& request, const char* what) {
    auto reply = supervisor.call(request, patience());
    if (!reply) {
      throw InstanceLost(
          std::string("no supervisor reply to ") + what + ": " +
          macsim::client::describe(supervisor.last_outcome(), "supervisor", o.domain));
    }
    if (reply->code() != 0)
      throw std::runtime_error(std::string(what) + " refused: " + reply->message());
    return *reply;
  }

  /// The simulator's participant is still there: its robot's command readers are matched (a
  /// killed one is unmatched when its lease ends).
  bool simulator_present() const { return drive.commander_matched() && crane.matched(); }

  /// Polls `ready` until it holds: the instance is lost when its simulator left (looked at
  /// after the timeout), or when it stays there but silent for the patience (hung).
  template <class Ready>
  void await(Ready ready, const std::function<std::string()>& what) {
    const auto start = std::chrono::steady_clock::now();
    while (!ready()) {
      const auto waited = std::chrono::steady_clock::now() - start;
      if (waited > o.timeout && !simulator_present())
        throw InstanceLost(what() + ": its simulator left");
      if (waited > patience()) {
        throw InstanceLost(what() + " in " + std::to_string(patience().count() / 1000) +
                           " s: its simulator is matched but silent (hung?)");
      }
      std::this_thread::sleep_for(200us);
    }
  }

  /// Steps of one tick.
  int tick_steps() const { return static_cast<int>(std::lround(kTick / dt)); }
  /// Ticks from now to `until` (sim time).
  int ticks_to(double until) const {
    return static_cast<int>(std::max(0L, std::lround((until - now) / kTick)));
  }

  /// One lock-step request of at most `n` steps, robot commands delivered first: ended early
  /// when a group of `conditions` holds at a tick, `samples` read at every tick. The topics
  /// bring only the newest sample of each at its end (nothing reads them before), the drive
  /// command holds through it, and the cameras render only when asked.
  mm::SimulationReply_ step(int n, const Conditions& conditions = {},
                            const Conditions& samples = {}, bool render = false) {
    // The request names the robot commands sent before it (commands_sent): the simulator waits
    // for them, however late DDS delivers them.
    uint32_t options = mm::STEP_PUBLISH_AT_END | mm::STEP_HOLD_COMMANDS;
    if (!render) options |= mm::STEP_NO_CAMERAS;
    if (o.hash_every_step) options |= mm::STEP_TRACE_HASH;
    auto request = until::request(static_cast<uint64_t>(n), dt > 0 ? tick_steps() : 1, options);
    request.hold_robots({o.robot});  // this instance's robot only: others drive their own
    request.until(conditions);
    request.samples(samples);
    for (auto* list : {&request.until(), &request.samples()}) {
      for (auto& c : *list) c.robot(o.robot);  // this instance's robot (objects ignore it)
    }
    // A long request takes its sim time on top of the answer's own allowance (at least real
    // time).
    const auto timeout =
        patience() + std::chrono::milliseconds(static_cast<int64_t>(std::ceil(n * dt * 1000)));
    auto reply = simulation.call(request, timeout);
    if (!reply) {
      throw InstanceLost("no step reply: " + macsim::client::describe(simulation.last_outcome(),
                                                                      "simulation control",
                                                                      o.domain));
    }
    if (reply->code() == mm::ERR_NOT_APPLICABLE)  // cancelled: paused, reset or replaced
      throw InstanceLost("step cancelled: " + reply->message());
    if (reply->code() != 0) throw std::runtime_error("step refused: " + reply->message());
    now = reply->sim_time();
    steps = reply->steps();
    hash = reply->state_hash();
    trace = mix(trace, o.hash_every_step ? reply->step_trace() : hash);
    return *reply;
  }

  /// One tick of the controller: 20 ms.
  void tick() { step(tick_steps()); }
  /// Steps `seconds` (a multiple of a tick) in one request.
  mm::SimulationReply_ advance(double seconds, const Conditions& samples = {}) {
    return step(static_cast<int>(std::lround(seconds / dt)), {}, samples);
  }

  void set_speed(double v) {
    speed = v;
    drive.drive(v, 0.0);
  }
  void crane_to(double slew, double lift, double hoist) { crane.command(slew, lift, hoist); }
  void magnet(bool on) { crane.magnet(on); }

  /// The newest sample of a topic due by now: stamped after `now - window`. Waits for it.
  template <class Get>
  auto newest(Get get, double window, const char* what) -> typename decltype(get())::value_type {
    std::optional<typename decltype(get())::value_type> found;
    await(
        [&] {
          auto sample = get();
          // Not older than the window, and not from a trial before the last reset.
          if (!sample) return false;
          const double stamp = stamp_seconds(sample->header());
          if (stamp > now - window + 1e-9 && stamp <= now + 1e-9) found = std::move(sample);
          return found.has_value();
        },
        [&] { return std::string("no ") + what + " for sim time " + std::to_string(now); });
    return *found;
  }
  kurt_msgs::msg::dds_::CraneState_ crane_state() {
    return newest([&] { return crane.state(); }, kFrameWindow, "crane state");
  }
  double odometry_x() {
    return newest([&] { return drive.latest_odometry(); }, kFrameWindow, "odometry")
        .pose()
        .pose()
        .position()
        .x();
  }
  nav_msgs::msg::dds_::Odometry_ ground_truth() {
    return newest([&] { return truth.get(); }, kFrameWindow, "ground truth");
  }
  mm::Object_ object(uint32_t id) { return call(sv::get_object(id), "get_object").object(); }

  /// Waits (in ticks) until the crane's joints are within tolerance of the targets, or `limit`
  /// seconds passed; `samples` read at every tick of the wait (none when it had not to wait).
  std::vector<double> wait_crane(double slew, double lift, double hoist, double limit,
                                 bool until_held = false, const Conditions& samples = {}) {
    const double end = now + limit;
    const auto s = crane_state();
    const bool there = std::fabs(s.slew() - slew) < 0.02 && std::fabs(s.lift() - lift) < 0.02 &&
                       std::fabs(s.hoist() - hoist) < 0.006;
    if (there || (until_held && !s.held_object().empty()) || now >= end - 1e-9) return {};
    // The same test at every tick, in the simulator.
    Conditions conditions{until::near(mm::STEP_READ_CRANE_SLEW, slew, 0.02),
                          until::near(mm::STEP_READ_CRANE_LIFT, lift, 0.02),
                          until::near(mm::STEP_READ_CRANE_HOIST, hoist, 0.006)};
    if (until_held) conditions.push_back(until::above(mm::STEP_READ_CRANE_HOLDING, 0.5, 1));
    return step(ticks_to(end) * tick_steps(), conditions, samples).samples();
  }

  void begin() {
    // Nothing of the last trial acts after the reset, however late DDS delivers it: the
    // request names the last command of each writer, and the simulator drops them.
    call(sv::reset(mm::RESET_EVERYTHING), "reset");
    // Sim time starts again at 0: a sample of the last trial could pass for one of this
    // trial's with the same stamp until this trial's came (a network slow to repair a loss).
    // Each topic's samples come in order, and the last trial read its last images and clouds.
    drive.forget_odometry();
    crane.forget();
    cameras.forget();
    laser.forget();
    truth.forget();
    now = 0;
    trace = 0;
    speed = 0;
  }

  uint32_t spawn(const mm::Object_& object) {
    return call(sv::create_object(object, false), "create_object").object_id();
  }
};

/// A trial's robot: it looks (perceive), reaches, and carries out the behaviours (stack,
/// traverse, lift, push, climb) over the link.
struct TrialRobot::Impl : TrialLink {
  explicit Impl(const InstanceOptions& options) : TrialLink(options) {}

  /// Looks: the crane swung out of the laser's plane (its boom at `lift`), then one stereo pair
  /// and one sweep.
  Percept perceive(double lift = 0.0) {
    crane_to(kAsideSlew, lift, 0.0);
    if (dt == 0) {
      // The instance's first look: its world's step, from the first step's reply.
      step(1);
      dt = now;
      if (!(dt > 0) || std::fabs(std::remainder(0.002, dt)) > 1e-9)
        throw std::runtime_error("the world's step (" + std::to_string(dt) +
                                 " s) does not divide 2 ms");
      step(static_cast<int>(std::lround(kFirst / dt)) - 1);
    } else {
      step(static_cast<int>(std::lround(kFirst / dt)));
    }
    step(static_cast<int>(std::lround((kPerceiveAt - now) / dt)), {}, {}, true);  // the pair
    Percept p;
    const double window = 1.0 / o.camera_rate;
    std::optional<macsim::client::StereoFrame> frame;
    await(
        [&] { return (frame = cameras.latest(now - window + 1e-9)) && frame->stamp <= now + 1e-9; },
        [&] { return "no stereo pair for sim time " + std::to_string(now); });
    perceive_image(*frame, p);
    auto scan = newest([&] { return laser.scan(); }, kScanWindow, "laser scan");
    perceive_scan(scan, SensorMount{}, p);
    if (o.keep_inputs) inputs = {frame, scan, std::nullopt};
    return p;
  }

  /// Drives `travel` m straight ahead by odometry (at most 4 s): top speed, then slowing down
  /// on what is left.
  void drive_by(double travel) {
    const double x_start = odometry_x();
    if (travel <= 0.01) return;
    constexpr double kGain = 3, kTop = 0.5;
    const double limit = now + 4.0;
    while (ticks_to(limit) > 0) {
      const double left = travel - (odometry_x() - x_start);
      if (left < 0.004) break;
      set_speed(std::clamp(left * kGain, 0.05, kTop));
      // Top speed until less than kTop / kGain is left: nothing to decide before. Then the
      // speed follows what is left every 0.2 s, the stop looked at every tick.
      const int ticks = left * kGain >= kTop ? ticks_to(limit) : std::min(ticks_to(limit), 10);
      step(ticks * tick_steps(),
           {until::above(mm::STEP_READ_ODOMETRY_X,
                         x_start + travel - (left * kGain >= kTop ? kTop / kGain : 0.004))});
    }
    set_speed(0);
  }

  /// Where the crane's tip must go over what the robot perceived, with the boom at `lift`: the
  /// slew and how far to drive first. Its middle: the near face by the laser and half its
  /// apparent width further (the cameras see its width across, not its depth along the way),
  /// to the side by the camera's bearing.
  struct Reach {
    double slew = 0, travel = 0;
  };
  Reach reach(const Percept& p, double lift) const {
    const double depth = p.width_m > 0 ? std::clamp(p.width_m, 0.03, 0.15) : 0.08;
    const double x = p.laser_range + depth / 2;
    const double y =
        std::tan(p.bearing) * (x - description::kLeftCamera[0]) + description::kLeftCamera[1];
    const double radius = kBoom * std::cos(lift);
    const double ahead = std::sqrt(std::max(0.0, radius * radius - y * y));
    return {std::atan2(y, ahead), x - kPivotX - ahead};
  }

  /// The boom's lift that puts its tip `above` m over the floor (within its range).
  static double lift_for(double above) {
    return std::clamp(std::asin(std::clamp((above - kBaseHeight - kPivotZ) / kBoom, -1.0, 1.0)),
                      kLiftMin, kLiftMax - 0.3);
  }

  /// Stack: picks the carried object beside the robot (magnet down until it holds), drives in
  /// to the base it perceived, lowers the object to 1 cm over the base's top and lets go. The
  /// label comes from both objects' poses 1 s later.
  Outcome stack(const TrialSpec& s, Percept& p, uint32_t base, uint32_t carried) {
    Outcome out;
    // Nowhere to put the load: the trial is refused, not labelled (none of 1,000 trials).
    if (!p.seen || !p.laser_hit)
      throw std::runtime_error("the cameras or the laser did not find the base to stack on");
    // The pick, boom level at the carried object's place: it hangs from the magnet, its top
    // where the magnet caught it.
    constexpr double kPickSlew = 1.3, kMaxHoist = 0.3;
    crane_to(kPickSlew, 0.0, 0.0);
    wait_crane(kPickSlew, 0.0, 0.0, 3.0);
    magnet(true);
    crane_to(kPickSlew, 0.0, kMaxHoist);
    wait_crane(kPickSlew, 0.0, kMaxHoist, 3.0, true);
    const auto held = crane_state();
    if (held.held_object().empty())
      throw std::runtime_error("the magnet did not catch the carried object");
    p.carried_height = kBaseHeight + kPivotZ - kMagnetBelowTip - held.hoist();
    // Up, the carried object's bottom 4 cm over the base's top, then in and over the base.
    const double top = p.laser_height;
    const double lift = lift_for(top + p.carried_height + kMagnetBelowTip + 0.04);
    // Where lift trials put the magnet (a load on a long base lands off its middle: the
    // label is what this robot's placement gets).
    const Reach r = reach(p, lift);
    crane_to(kPickSlew, lift, 0.0);
    wait_crane(kPickSlew, lift, 0.0, 2.0);
    drive_by(r.travel);
    crane_to(r.slew, lift, 0.0);
    wait_crane(r.slew, lift, 0.0, 3.0);
    // Down to 1 cm over the top, a moment to settle, and let go.
    const double tip_z = kBaseHeight + kPivotZ + kBoom * std::sin(lift);
    const double down =
        std::clamp(tip_z - kMagnetBelowTip - p.carried_height - top - 0.01, 0.0, kMaxHoist);
    crane_to(r.slew, lift, down);
    wait_crane(r.slew, lift, down, 2.0);
    advance(0.2);
    magnet(false);
    advance(1.0);
    // Both poses 1 s after the release.
    const mm::Object_ a = object(carried), b = object(base);
    auto up_z = [](const mm::Object_& thing) {  // the z of the object's own z axis, in the world
      const auto& q = thing.pose().orientation();
      return 1 - 2 * (q.x() * q.x() + q.y() * q.y());
    };
    out.a_tilt = std::acos(std::clamp(up_z(a), -1.0, 1.0));
    switch (s.shape) {
      case Shape::LyingCylinder:  // its axis from level
        out.b_tilt = std::asin(std::min(1.0, std::fabs(up_z(b))));
        break;
      case Shape::Sphere:
        out.b_tilt = 0;
        break;
      default:
        out.b_tilt = std::acos(std::clamp(up_z(b), -1.0, 1.0));
    }
    const double b_top = b.pose().position().z() + s.height() / 2;
    out.settle = a.pose().position().z() - s.carried.size[2] / 2 - b_top;
    out.offset = std::hypot(a.pose().position().x() - b.pose().position().x(),
                            a.pose().position().y() - b.pose().position().y());
    out.moved = std::hypot(b.pose().position().x() - s.x, b.pose().position().y() - s.y);
    // The base tipped over or rolled away (5 cm: a base only nudged by a load sliding off moves
    // less, lying cylinders up to 6 cm in 1,000 trials; spheres that roll go up to 34 cm):
    // toppled; it stood and held the object upright on its top: stacked; it stood and the
    // object came off: slid_off.
    if (out.b_tilt >= 0.35 || out.moved >= 0.05)
      out.label = "toppled";
    else if (out.a_tilt < 0.2 && std::fabs(out.settle) < 0.015)
      out.label = "stacked";
    else
      out.label = "slid_off";
    return out;
  }

  /// Traverse: one turn of the rotating scanner standing still (the 3D cloud ahead), then
  /// straight at the obstacle at 0.4 m/s for at most 6 s. Traversable when the robot's middle
  /// got past the obstacle's far edge as it stood (over it, through it, or pushing it away).
  Outcome traverse(const TrialSpec& s, Percept& p) {
    const uint64_t seen = laser.clouds();
    const double look_from = now;
    laser.rotate(2 * M_PI);  // a turn a second: a cloud of about 75 sweeps
    step(ticks_to(now + 1.04) * tick_steps());
    std::optional<macsim::client::Cloud> cloud;
    await(
        [&] {
          return laser.clouds() > seen && (cloud = laser.cloud(look_from)) &&
                 cloud->stamp <= now + 1e-9;
        },
        [&] { return "no 3D cloud for sim time " + std::to_string(now); });
    perceive_cloud(*cloud, SensorMount{}, p);
    if (o.keep_inputs) inputs.cloud = cloud;
    laser.rotate(0);
    const double far = s.x + s.reach_ahead();
    Outcome out;
    // At most 6 s: the farthest edge, 1.55 m, takes 3.9 s at full speed. No stop command after
    // it: nothing steps after it in this trial, and the next trial's reset stops the robot.
    const Track track = drive_past(far, 6.0);
    double last_x = track.x0;
    for (const auto& [x, z] : track.at) {
      last_x = x;
      out.progress = std::max(out.progress, x - track.x0);
      out.rise = std::max(out.rise, z - track.z0);
    }
    out.passed = last_x - far;
    out.label = last_x >= far ? "traversable" : "not_traversable";
    return out;
  }

  Outcome lift(const Percept& p, uint32_t id) {
    const double z0 = object(id).pose().position().z();
    std::optional<double> z_up;  // the object's height once the boom is up, if a wait read it
    Outcome out;
    if (p.seen && p.laser_hit) {
      // The boom low enough that the magnet hangs 2 cm over the top with the hoist in.
      const double top = p.laser_height;
      const double lift = lift_for(top + kMagnetBelowTip + 0.02);
      const auto [slew, travel] = reach(p, lift);
      // Drive in (by odometry) while the crane swings over.
      crane_to(slew, lift, 0.0);
      drive_by(travel);
      wait_crane(slew, lift, 0.0, 2.0);
      // Down onto it with the magnet on, 1.5 cm further than the top: the magnet rests on it.
      magnet(true);
      const double tip_z = kBaseHeight + kPivotZ + kBoom * std::sin(lift);
      const double down = std::clamp(tip_z - kMagnetBelowTip - top + 0.015, 0.0, 0.3);
      crane_to(slew, lift, down);
      wait_crane(slew, lift, down, 1.0, true);
      advance(0.1);
      // Up: the hoist in and the boom 0.3 rad higher.
      crane_to(slew, lift + 0.3, 0.0);
      // Where the object is once the boom is up: the last sample of that wait (it always waits:
      // the boom turns 0.3 rad at 1 rad/s).
      const auto up = wait_crane(slew, lift + 0.3, 0.0, 1.2, false,
                                 {until::reading(mm::STEP_READ_OBJECT_Z, id)});
      if (!up.empty()) z_up = up.back();
    }
    const double z1 = z_up ? *z_up : object(id).pose().position().z();
    const double z2 = advance(1.0, {until::reading(mm::STEP_READ_OBJECT_Z, id)}).samples().back();
    out.raised = std::min(z1, z2) - z0;
    out.label = out.raised >= 0.05 ? "liftable" : "not_liftable";
    return out;
  }

  Outcome push(uint32_t id) {
    const mm::Object_ start = object(id);
    crane_to(kAsideSlew, 0.6, 0.0);  // the boom up and aside: only the bumper touches
    Outcome out;
    set_speed(0.4);
    // 3 s, the object's turning about horizontal axes read at every tick.
    const auto reply = step(ticks_to(now + 3.0) * tick_steps(), {},
                            {until::reading(mm::STEP_READ_OBJECT_TILT_RATE, id)});
    for (double tilt_rate : reply.samples()) out.rolled += tilt_rate * kTick;
    set_speed(0);
    const auto end = advance(0.4, {until::reading(mm::STEP_READ_OBJECT_X, id),
                                   until::reading(mm::STEP_READ_OBJECT_Y, id)})
                         .samples();
    out.moved = std::hypot(end[end.size() - 2] - start.pose().position().x(),
                           end.back() - start.pose().position().y());
    if (out.moved < 0.10)
      out.label = "stalled";
    else
      out.label = out.rolled >= M_PI ? "rolled" : "pushed";
    return out;
  }

  /// Where the robot's middle (ground truth) was when a drive began, and at every tick of it.
  struct Track {
    double x0 = 0, z0 = 0;
    std::vector<std::array<double, 2>> at;  ///< x, z
  };
  /// Straight ahead at 0.4 m/s in one request of at most `seconds` that ends when the robot's
  /// middle is past `edge` or it made no 2 cm of headway for a second.
  Track drive_past(double edge, double seconds) {
    const auto start = ground_truth();
    Track track{start.pose().pose().position().x(), start.pose().pose().position().z(), {}};
    set_speed(0.4);
    const auto reply =
        step(ticks_to(now + seconds) * tick_steps(),
             {until::above(mm::STEP_READ_TRUTH_X, std::nextafter(edge, -1e9), 0),
              until::stalled(mm::STEP_READ_TRUTH_X, 1.0, 0.02, 1)},
             {until::reading(mm::STEP_READ_TRUTH_X), until::reading(mm::STEP_READ_TRUTH_Z)});
    const auto& samples = reply.samples();
    for (std::size_t i = 0; i + 1 < samples.size(); i += 2)
      track.at.push_back({samples[i], samples[i + 1]});
    return track;
  }

  Outcome climb(const TrialSpec& s) {
    crane_to(kAsideSlew, 0.6, 0.0);
    const double top_x = s.x + s.ramp_height / std::tan(s.ramp_angle);
    Outcome out;
    // At most 8 s: until the robot's middle is past the top, or stalled.
    const Track track = drive_past(top_x, 8.0);
    const double x0 = track.x0, z0 = track.z0;
    double best_x = x0, last_x = x0, last_z = z0;
    for (const auto& [x, z] : track.at) {
      last_x = x;
      last_z = z;
      out.rise = std::max(out.rise, last_z - z0);
      if (last_x > best_x + 0.02) best_x = last_x;
    }
    const bool reached = last_x >= top_x;
    out.progress = best_x - x0;
    if (reached)
      out.label = "climbed";
    else if (out.rise >= 0.02 && (last_z < z0 + out.rise - 0.01 || last_x < best_x - 0.03))
      out.label = "slid_back";
    else
      out.label = "stalled";
    return out;
  }
};

TrialRobot::TrialRobot(const InstanceOptions& options) : impl_(std::make_unique<Impl>(options)) {}
TrialRobot::~TrialRobot() = default;

void TrialRobot::connect(std::chrono::milliseconds timeout) {
  Impl& m = *impl_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto left = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                 std::chrono::steady_clock::now());
  };
  const std::string where = " on domain " + std::to_string(m.o.domain);
  if (!m.simulation.wait_for_server(left())) throw InstanceLost("no simulation control" + where);
  auto features = m.simulation.call(macsim::client::SimulationClient::request(mm::SIM_FEATURES),
                                    std::max(left(), std::chrono::milliseconds(1000)));
  if (!features) {
    throw InstanceLost("no answer to SIM_FEATURES" + where + ": " +
                       macsim::client::describe(m.simulation.last_outcome(), "simulation control"));
  }
  if (features->features().find("lockstep") == std::string::npos ||
      features->features().find("supervisor") == std::string::npos)
    throw InstanceLost("the participant" + where +
                       " is not a lock-step simulator (features: " + features->features() + ")");
  if (!m.supervisor.wait_for_server(left())) throw InstanceLost("no supervisor" + where);
  // The rotating unit too: a command to a reader not matched yet would be lost.
  while (!m.drive.commander_matched() || !m.crane.matched() || m.truth.matched() == 0 ||
         !m.laser.matched()) {
    if (left().count() <= 0) throw InstanceLost("no robot '" + m.o.robot + "'" + where);
    std::this_thread::sleep_for(20ms);
  }
  // A first look, thrown away: the first camera pair a simulator renders after it started
  // differs from every later rendering of the same scene in a few pixels (one level of shading),
  // so no trial may be an instance's first.
  m.begin();
  m.perceive();
}

TrialRecord TrialRobot::run(const TrialSpec& spec) {
  Impl& m = *impl_;
  const auto wall_start = std::chrono::steady_clock::now();
  TrialRecord record;
  record.spec = spec;
  m.begin();
  const uint32_t id = m.spawn(trial_object(spec));
  const uint32_t carried =
      spec.affordance == Affordance::Stack ? m.spawn(carried_object(spec.carried)) : 0;
  // Traverse looks with the boom up as it drives (out of the cloud's reach).
  record.percept = m.perceive(spec.affordance == Affordance::Traverse ? 0.6 : 0.0);
  switch (spec.affordance) {
    case Affordance::Lift:
      record.outcome = m.lift(record.percept, id);
      break;
    case Affordance::Push:
      record.outcome = m.push(id);
      break;
    case Affordance::Climb:
      record.outcome = m.climb(spec);
      break;
    case Affordance::Stack:
      record.outcome = m.stack(spec, record.percept, id, carried);
      break;
    case Affordance::Traverse:
      record.outcome = m.traverse(spec, record.percept);
      break;
  }
  if (m.o.keep_inputs) record.inputs = std::move(m.inputs);
  record.sim_time = m.now;
  record.steps = m.steps;
  record.final_hash = m.hash;
  record.trace = m.trace;
  record.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return record;
}

}  // namespace affordances
