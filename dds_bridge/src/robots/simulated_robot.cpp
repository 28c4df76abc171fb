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
  time_origins_ = runner.world().time_origin().count;
  // The world was put back before this robot's first read (a resumed run, its session ending
  // right after a reset, a restore or a load): everything, as after one.
  if (generation_ > 0 || time_origins_ > 0) mark_ = ReadMark::everything();
}

bool SimulatedRobot::execute(const robot::RobotCommand& command) {
  RobotModel* r = robot();
  return r && r->execute(command, runner_.world().time());
}

robot::Readings SimulatedRobot::read() {
  RobotModel* r = robot();
  if (!r) return {};
  const World& world = runner_.world();
  if (runner_.generation() != generation_ || world.time_origin().count != time_origins_) {
    // A reset, a restore or a new world: its first readings are new, whatever their counters.
    generation_ = runner_.generation();
    time_origins_ = world.time_origin().count;
    mark_ = ReadMark::everything();
  }
  return r->read(mark_, world.time());
}

}  // namespace macsim
