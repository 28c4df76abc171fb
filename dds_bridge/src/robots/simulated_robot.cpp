#include "robots/simulated_robot.h"

#include <stdexcept>

namespace macsim {

SimulatedRobot::SimulatedRobot(Runner& runner, std::string name)
    : runner_(runner), name_(std::move(name)) {
  RobotModel* r = robot();
  if (!r) throw std::invalid_argument("no robot named '" + name_ + "' in the world");
  capabilities_ = r->capabilities();
  frame_tree_ = r->frames();
  generation_ = runner.generation();
}

void SimulatedRobot::command_twist(double linear, double angular) {
  if (RobotModel* r = robot()) r->command_twist(linear, angular, runner_.world().time());
}

void SimulatedRobot::command_wheel_speeds(double left, double right) {
  if (RobotModel* r = robot()) r->command_wheel_speeds({left, right}, runner_.world().time());
}

void SimulatedRobot::command_rotunit(double speed) {
  if (RobotModel* r = robot()) r->command_rotunit(speed);
}

void SimulatedRobot::command_crane(double slew, double lift, double hoist) {
  if (RobotModel* r = robot()) r->command_crane({slew, lift, hoist});
}

void SimulatedRobot::command_magnet(bool on) {
  if (RobotModel* r = robot()) r->command_magnet(on);
}

robot::Readings SimulatedRobot::read() {
  RobotModel* r = robot();
  if (!r) return {};
  const double now = runner_.world().time();
  if (now < last_time_ || runner_.generation() != generation_) {
    // A reset or a new world: its first readings are new, whatever their counters say.
    generation_ = runner_.generation();
    mark_ = ReadMark::everything();
  }
  last_time_ = now;
  return r->read(mark_, now);
}

}  // namespace macsim
