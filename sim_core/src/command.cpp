#include "macsim/sim_core/command.h"

#include <array>
#include <cstdio>
#include <utility>

#include "macsim/sim_core/world.h"

namespace macsim {

namespace {

constexpr std::array<std::pair<CommandSource, std::string_view>, 6> kSourceNames{{
    {CommandSource::Supervisor, "supervisor"},
    {CommandSource::Simulation, "simulation"},
    {CommandSource::Ros2Service, "ros2_service"},
    {CommandSource::Pictures, "pictures"},
    {CommandSource::Robot, "robot"},
    {CommandSource::Local, "local"},
}};
static_assert(kSourceNames.size() == kCommandSources, "a name for every CommandSource");

}  // namespace

std::string_view to_string(CommandSource source) {
  for (const auto& [s, name] : kSourceNames) {
    if (s == source) return name;
  }
  return "unknown";
}

std::optional<CommandSource> command_source(std::string_view name) {
  for (const auto& [s, n] : kSourceNames) {
    if (n == name) return s;
  }
  return std::nullopt;
}

std::string describe(const Command& c) {
  std::string text = std::string(to_string(c.source)) + " " + c.operation;
  if (!c.target.empty()) text += " " + c.target;
  for (double v : c.robot ? c.robot->values() : std::vector<double>{}) {
    char number[32];
    std::snprintf(number, sizeof number, " %g", v);
    text += number;
  }
  if (!c.message.empty()) text += " (" + std::to_string(c.message.size()) + " bytes)";
  return text;
}

Command robot_command(std::string robot, robot::RobotCommand command) {
  Command c;
  c.source = CommandSource::Robot;
  c.operation = std::string(command.name());
  c.target = std::move(robot);
  c.robot = std::move(command);
  return c;
}

bool run_robot_command(const Command& c, World& world) {
  RobotModel* robot = world.robot(c.target);
  return robot && c.robot && robot->execute(*c.robot, world.time());
}

}  // namespace macsim
