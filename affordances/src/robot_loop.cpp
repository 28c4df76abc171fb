#include "macsim/affordances/robot_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "macsim/dds/convert.h"
#include "macsim/dds/log.h"
#include "macsim/dds/topics.h"

namespace macsim::affordances {

namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;

constexpr double kTurnRate = 0.6;           // rad/s
constexpr const char* kLog = "robot loop";  // what its messages begin with

}  // namespace

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

void add_loop_options(macsim::dds::CommandLine& cli, LoopOptions& options) {
  const auto seconds = [](double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", s);
    return std::string(text);
  };
  cli.option("robot", "NAME", "robot namespace (default " + options.robot + ")", &options.robot);
  cli.flag("lockstep",
           "step the simulation from here (macsim --lockstep): reproducible, as fast as the "
           "machine allows",
           &options.lockstep);
  cli.option("timeout", "SECONDS",
             "give up after this much robot time (default " + seconds(options.timeout) + ")",
             &options.timeout);
  cli.option("discovery-timeout", "SECONDS",
             "wait this long for the robot (default " + seconds(options.discovery_timeout) + ")",
             &options.discovery_timeout);
  cli.option("restart-patience", "SECONDS",
             "wait this long for a simulator that went away (killed and resumed: macsim --resume) "
             "or a robot gone silent (default " +
                 seconds(options.restart_patience) + "; 0: give up at once)",
             &options.restart_patience);
}

std::string loop_options_problem(const LoopOptions& options) {
  if (!(options.timeout > 0) || !(options.discovery_timeout > 0) ||
      !(options.restart_patience >= 0) || options.robot.empty())
    return "--timeout and --discovery-timeout must be positive, --restart-patience not negative, "
           "--robot not empty";
  return {};
}

RobotLoop::RobotLoop(macsim::dds::Participant& participant, const LoopOptions& options)
    : loop_options_(options),
      drive_(participant, options.robot, macsim::dds::sensor_family(options.lockstep)),
      crane_(participant, options.robot, macsim::dds::sensor_family(options.lockstep)),
      cameras_(participant, options.robot, macsim::dds::sensor_family(options.lockstep)),
      laser_(participant, options.robot, true, macsim::dds::sensor_family(options.lockstep)),
      imu_(participant, options.robot, macsim::dds::sensor_family(options.lockstep)) {
  if (options.lockstep) {
    simulation_ = std::make_unique<macsim::client::SimulationClient>(participant);
    // A simulator that went away during a step comes back (macsim --resume) with every
    // set-point it had taken (they are in its session); the step request goes again once this
    // loop's readers and writers know the new process, after the set-points (the simulator
    // drops them if it had begun that request: given in its middle they would act at another
    // step than they did).
    simulation_->set_restart_patience(
        std::chrono::milliseconds(static_cast<int64_t>(options.restart_patience * 1000)), [this] {
          // The new simulator's data must reach this loop: each of its readers matched a new
          // writer (one that found the new process late would miss a step's image or IMU
          // sample, and the loop would decide a tick later than a run never killed). And the
          // set-points below must reach it: written before its readers matched, they never
          // would, and the step request that names them would be refused.
          const auto until = std::chrono::steady_clock::now() + 12s;
          while ((!simulator_renewed() || !drive_.commander_matched() || !crane_.matched() ||
                  drive_.command_readers() > 1 || crane_.command_readers() > 1 ||
                  laser_.command_readers() > 1) &&
                 std::chrono::steady_clock::now() < until)
            std::this_thread::sleep_for(20ms);
          std::this_thread::sleep_for(300ms);
          peers_seen_ = peers_seen();
          // The set-points again: a simulator killed after they were delivered and before its
          // step took them never wrote them. One that had begun the step request goes on with
          // those it took and drops these (macsim --resume).
          send_set_points();
        });
  }
}

RobotLoop::PeersSeen RobotLoop::peers_seen() const {
  return {drive_.odometry_writers_seen(), imu_.writers_seen(),
          cameras_.writers_seen(),        laser_.writers_seen(),
          crane_.writers_seen(),          drive_.command_readers_seen(),
          crane_.command_readers_seen(),  laser_.command_readers_seen()};
}

bool RobotLoop::simulator_renewed() const {
  const PeersSeen now = peers_seen();
  for (std::size_t i = 0; i < now.size(); ++i) {
    // A topic the simulator did not serve before (cameras off) is not waited for; the command
    // topics' new readers must have matched too.
    if (peers_seen_[i] > 0 && now[i] <= peers_seen_[i]) return false;
  }
  return now[0] > peers_seen_[0];  // the odometry at least
}

void RobotLoop::send_set_points() {
  drive_.drive(linear_, angular_);
  crane_.command(slew_, lift_, hoist_);
  crane_.magnet(magnet_);
  laser_.rotate(rotunit_);
  // In lock-step the next step request names these (commands_sent) and the simulator waits for
  // them before its first step: nothing here waits for DDS to acknowledge them.
}

RobotLoop::~RobotLoop() = default;

void RobotLoop::connect() {
  const std::string& robot = loop_options_.robot;
  const auto patience =
      std::chrono::milliseconds(static_cast<int>(loop_options_.discovery_timeout * 1000));
  const auto deadline = std::chrono::steady_clock::now() + patience;
  if (simulation_) {
    // Lock-step: the robot's data comes only when this controller steps the simulation.
    if (!simulation_->wait_for_server(patience)) {
      throw LoopError{Stop::NoRobot,
                      "no simulator answers simulation requests (lock-step needs macsim "
                      "--lockstep on the same --domain)"};
    }
    while (!drive_.commander_matched() || !crane_.matched()) {
      if (std::chrono::steady_clock::now() > deadline)
        throw LoopError{Stop::NoRobot, "robot '" + robot + "' serves no cmd_vel or crane"};
      std::this_thread::sleep_for(20ms);
    }
    auto reply = simulation_->step(1);
    if (!reply || reply->code() != mm::ERR_OK || reply->steps() == 0)
      throw LoopError{Stop::NoRobot, "the simulator did not step"};
    step_size_ = reply->sim_time() / static_cast<double>(reply->steps());
  }
  std::optional<macsim::client::RobotClient::Odometry> odometry;
  while (!(odometry = drive_.wait_for_odometry(100ms)) || !imu_.yaw()) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw LoopError{Stop::NoRobot,
                      "no odometry and IMU from robot '" + robot +
                          "' within the discovery timeout: is macsim (or kurt_adapter) "
                          "running with the same --domain and DDS profile?"};
    }
    if (simulation_) simulation_->step(10);
  }
  now_ = start_ = macsim::client::stamp_seconds(odometry->header());
  while (!crane_.matched() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(20ms);
  if (!crane_.matched()) throw LoopError{Stop::NoRobot, "robot '" + robot + "' has no crane"};
}

void RobotLoop::tick(double seconds) {
  send_set_points();
  const double target = now_ + seconds - 1e-6;
  const double began = now_;
  bool cloud_due = false;  // the tick's end wrote a cloud (its reply says so)
  if (simulation_) {
    const auto steps = static_cast<uint64_t>(std::max(1L, std::lround(seconds / step_size_)));
    // The robot's topics bring their newest sample at the tick's end (the controller reads
    // nothing in between), and the cameras render only while it looks: most of a lock-step
    // simulator's time would otherwise go to data nobody reads.
    uint32_t options = mm::STEP_PUBLISH_AT_END;
    if (!looking_) options |= mm::STEP_NO_CAMERAS;
    auto reply = simulation_->call(macsim::client::step_until::request(steps, 0, options));
    if (!reply) {
      throw LoopError{Stop::NoRobot,
                      macsim::client::describe(simulation_->last_outcome(), "simulation control")};
    }
    if (reply->code() == mm::ERR_COMMANDS_MISSING)
      throw LoopError{Stop::NoRobot, "the simulator refused the step: " + reply->message()};
    const auto& published = reply->published();
    cloud_due = std::find(published.begin(), published.end(),
                          macsim::dds::topics::points(loop_options_.robot)) != published.end();
  }
  std::optional<macsim::client::RobotClient::Odometry> odometry;
  auto deadline = std::chrono::steady_clock::now() + 10s;
  bool silent = false;  // said so: waiting for the robot to come back
  while (true) {
    odometry = drive_.wait_for_odometry(200ms);
    if (odometry && silent) {
      silent = false;
      macsim::log::info("{}: robot '{}' is back, its odometry at t = {:.3f} s", kLog,
                        loop_options_.robot, macsim::client::stamp_seconds(odometry->header()));
    }
    if (odometry && macsim::client::stamp_seconds(odometry->header()) >= target - 0.0105) break;
    if (std::chrono::steady_clock::now() > deadline) {
      if (silent || !(loop_options_.restart_patience > 0)) {
        throw LoopError{Stop::NoRobot, "robot '" + loop_options_.robot +
                                           "' went silent (no odometry for 10 s" +
                                           (silent ? " and the restart patience after" : "") + ")"};
      }
      // A simulator killed and restarting (macsim --resume) or an adapter gone: wait for it.
      silent = true;
      macsim::log::warn(
          "{}: robot '{}' went silent (no odometry for 10 s); waiting up to {:.0f} s "
          "for it to come back",
          kLog, loop_options_.robot, loop_options_.restart_patience);
      deadline =
          std::chrono::steady_clock::now() +
          std::chrono::milliseconds(static_cast<int64_t>(loop_options_.restart_patience * 1000));
    }
    if (!odometry && !simulation_) send_set_points();
  }
  // In lock-step the IMU's sample of this tick too (it comes on its own writer, and may come
  // after the odometry's): a heading one tick old would make two runs of one layout differ.
  while (simulation_) {
    const auto imu = imu_.latest();
    if (!imu || macsim::client::stamp_seconds(imu->header()) >= target - 0.0105) break;
    if (std::chrono::steady_clock::now() > deadline) break;  // the last one, then
    std::this_thread::sleep_for(1ms);
  }
  // And the cloud the tick completed, which its reply names: a cloud may come after the
  // odometry, and taken a tick late it would make two runs of one layout differ.
  while (cloud_due && !laser_.cloud(began + 1e-9)) {
    if (std::chrono::steady_clock::now() > deadline) {
      // (A reply repeated after a kill may name a cloud its killed writer never delivered.)
      macsim::log::warn("{}: the cloud the tick's reply named did not come within 10 s; going on",
                        kLog);
      break;
    }
    std::this_thread::sleep_for(1ms);
  }
  now_ = macsim::client::stamp_seconds(odometry->header());
  peers_seen_ = peers_seen();
  // Position: the odometry's distance travelled, along the IMU's heading.
  const auto& p = odometry->pose().pose().position();
  const double yaw = imu_.yaw().value_or(pose_.yaw);
  if (last_position_) {
    const double step = std::hypot(p.x() - last_position_->first, p.y() - last_position_->second);
    const double sign = odometry->twist().twist().linear().x() < 0 ? -1.0 : 1.0;
    const double heading = pose_.yaw + 0.5 * wrap(yaw - pose_.yaw);
    pose_.x += sign * step * std::cos(heading);
    pose_.y += sign * step * std::sin(heading);
  }
  last_position_ = {p.x(), p.y()};
  pose_.yaw = yaw;
  after_tick();
  if (elapsed() > loop_options_.timeout) {
    linear_ = angular_ = 0;
    drive_.stop();
    // Lock-step: the stop is taken by contract, by a step that names it, not left to race the
    // simulator's end (two runs of one layout would differ by whether it came in time).
    if (simulation_) (void)simulation_->step(1);
    char text[128];
    std::snprintf(text, sizeof text, "the run took longer than %.0f s of robot time",
                  loop_options_.timeout);
    throw LoopError{Stop::Timeout, text};
  }
}

void RobotLoop::wait(double seconds) {
  const double until = now_ + seconds;
  while (now_ < until - 1e-6) tick(std::min(kTick, until - now_));
}

void RobotLoop::turn_to(double yaw) {
  const double give_up = now_ + 20.0;
  while (true) {
    const double error = wrap(yaw - pose_.yaw);
    if (std::fabs(error) < 0.015 || now_ > give_up) break;
    const double rate = std::clamp(2.0 * error, -kTurnRate, kTurnRate);
    linear_ = 0;
    angular_ = std::copysign(std::max(std::fabs(rate), 0.12), error);
    tick();
  }
  linear_ = angular_ = 0;
  tick();
}

void RobotLoop::drive_to(double x, double y, double tolerance, double speed) {
  const double give_up = now_ + 60.0;
  bool turned = false;
  while (now_ < give_up) {
    const double dx = x - pose_.x, dy = y - pose_.y, distance = std::hypot(dx, dy);
    if (distance < tolerance) break;
    const double bearing = std::atan2(dy, dx), error = wrap(bearing - pose_.yaw);
    if (!turned || std::fabs(error) > 0.35) {
      turn_to(bearing);
      turned = true;
      continue;
    }
    // Past the goal (it is behind): stop rather than circle.
    if (std::fabs(error) > M_PI / 2) break;
    linear_ = std::clamp(1.2 * distance, 0.06, speed);
    angular_ = std::clamp(2.5 * error, -kTurnRate, kTurnRate);
    tick();
  }
  linear_ = angular_ = 0;
  tick();
}

bool RobotLoop::drive_straight(double distance, double speed, double stall_time,
                               double stall_progress) {
  const double heading = pose_.yaw;
  const Pose2 from = pose_;
  const double give_up = now_ + 30.0;
  double best = 0, best_at = now_;
  bool stalled = false;
  while (now_ < give_up) {
    const double done = std::hypot(pose_.x - from.x, pose_.y - from.y);
    const double left = std::fabs(distance) - done;
    if (left < 0.004) break;
    if (done > best + stall_progress) {
      best = done;
      best_at = now_;
    } else if (stall_time > 0 && now_ - best_at > stall_time) {
      stalled = true;
      break;
    }
    linear_ = std::copysign(std::clamp(1.5 * left, 0.04, speed), distance);
    angular_ = std::clamp(3.0 * wrap(heading - pose_.yaw), -0.3, 0.3);
    tick();
  }
  linear_ = angular_ = 0;
  tick();
  return !stalled;
}

bool RobotLoop::crane_to(double slew, double lift, double hoist, double timeout) {
  namespace d = macsim::robot::kurt3d;
  slew_ = slew;
  lift_ = std::clamp(lift, d::kLiftMin, d::kLiftMax);
  hoist_ = std::clamp(hoist, 0.0, d::kMaxHoist);
  const double give_up = now_ + timeout;
  while (now_ < give_up) {
    tick();
    const auto s = crane_.state();
    if (s && std::fabs(wrap(s->slew() - slew_)) < 0.03 && std::fabs(s->lift() - lift_) < 0.03 &&
        std::fabs(s->hoist() - hoist_) < 0.01) {
      return true;
    }
  }
  return false;
}

macsim::client::Cloud RobotLoop::take_cloud() {
  linear_ = angular_ = 0;
  wait(0.2);
  // A cloud is one turn of the rotating unit: take the first begun after the robot stood still.
  const double turn = 2 * M_PI / std::max(std::fabs(rotunit_), 0.1);
  const double stood = now_;
  const double give_up = now_ + 3 * turn + 1.0;
  while (now_ < give_up) {
    tick();
    if (auto cloud = laser_.cloud(stood + turn + 0.02)) return *cloud;
  }
  throw LoopError{Stop::NoCloud, "the laser gave no 3D cloud (is the rotating unit turning?)"};
}

Pose2 RobotLoop::to_odom(double bx, double by) const {
  const double c = std::cos(pose_.yaw), s = std::sin(pose_.yaw);
  return {pose_.x + c * bx - s * by, pose_.y + s * bx + c * by, 0};
}

Pose2 RobotLoop::to_base(double x, double y) const {
  const double c = std::cos(pose_.yaw), s = std::sin(pose_.yaw);
  const double dx = x - pose_.x, dy = y - pose_.y;
  return {c * dx + s * dy, -s * dx + c * dy, 0};
}

}  // namespace macsim::affordances
