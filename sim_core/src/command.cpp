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

std::vector<uint8_t> LoadWorldRequest::wire() const {
  const std::string& text = file.empty() ? xml : file;
  return {text.begin(), text.end()};
}

std::string_view operation_name(const Command& c) {
  if (c.robot) return c.robot->name();
  if (c.request) return c.request->name();
  return {};
}

std::vector<uint8_t> wire_of(const Command& c) {
  return c.request ? c.request->wire() : std::vector<uint8_t>{};
}

std::string describe(const Command& c) {
  std::string text = std::string(to_string(c.source)) + " " + std::string(operation_name(c));
  if (!c.target.empty()) text += " " + c.target;
  for (double v : c.robot ? c.robot->values() : std::vector<double>{}) {
    char number[32];
    std::snprintf(number, sizeof number, " %g", v);
    text += number;
  }
  if (c.request && !c.robot) {
    const std::size_t bytes = c.request->wire().size();
    if (bytes > 0) text += " (" + std::to_string(bytes) + " bytes)";
  }
  return text;
}

Command robot_command(std::string robot, robot::RobotCommand command) {
  Command c;
  c.source = CommandSource::Robot;
  c.target = std::move(robot);
  c.robot = std::move(command);
  return c;
}

bool run_robot_command(const Command& c, World& world) {
  RobotModel* robot = world.robot(c.target);
  return robot && c.robot && robot->execute(*c.robot, world.time());
}

}  // namespace macsim
