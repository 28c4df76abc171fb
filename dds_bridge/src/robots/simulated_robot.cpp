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

bool SimulatedRobot::execute(const robot::RobotCommand& command) {
  RobotModel* r = robot();
  return r && r->execute(command, runner_.world().time());
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
