// What the runner executes: a command as a value (gz-sim's typed user commands): its source,
// its operation, its arguments, and where its answer goes. Values can be printed, counted and
// written to a session file; the executor of each source runs them, live and in a replay alike.
#pragma once

#include <any>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "macsim/robot/robot_command.h"

namespace macsim {

class World;

/// Who sent a command.
enum class CommandSource : uint8_t {
  Supervisor,   ///< a supervisor request (macsim_msgs SupervisorRequest)
  Simulation,   ///< simulation control (SimulationRequest), and what the runner does itself
  Ros2Service,  ///< a simulation_interfaces service request
  Pictures,     ///< a picture request (the scene is taken; the world is only read)
  Robot,        ///< a robot's command topic (cmd_vel, crane, magnet, ...)
  Local,        ///< code in this process (tests, programs embedding the runner): never recorded
};

/// How many sources there are.
inline constexpr std::size_t kCommandSources = 6;

/// The source's name in a session file ("supervisor", "robot", ...).
std::string_view to_string(CommandSource source);
/// The source of that name, or nullopt.
std::optional<CommandSource> command_source(std::string_view name);

/// Who sent a robot command and its place among what that sender sent (over DDS: the writer's
/// GUID and the sample's sequence number, which grows with every sample the writer sends).
struct Sender {
  std::array<uint8_t, 16> id{};
  uint64_t sequence = 0;
};

/// One command for the world.
struct Command {
  CommandSource source = CommandSource::Local;
  std::string operation;  ///< e.g. "set_density", "load_world"; a robot command's type name
  std::string target;     ///< the robot a robot command is for; empty otherwise
  /// A robot command (source Robot): the typed command the robot carries out.
  std::optional<robot::RobotCommand> robot;
  std::vector<uint8_t> message;  ///< a request's message in its wire form (CDR)
  std::any reply_to;             ///< where its answer goes (its server's; empty in a replay)
  /// A robot command: who sent it, if known (a replay does not know).
  std::optional<Sender> sent_by;
  /// A request that puts the world back (a reset, a snapshot restored, a world loaded): the
  /// last robot command each sender of its client sent before it. None of those acts after
  /// it, however late it arrives (Runner drops them).
  std::vector<Sender> sent_before;
  /// Local only: what it does. Every other source is run by its executor from the fields above.
  std::function<void(World&)> local;
};

/// One line for logs: source, operation, target, values and message size.
std::string describe(const Command& command);

/// A command for the robot named `robot` (macsim/robot/robot_command.h: robot::Twist, ...).
Command robot_command(std::string robot, robot::RobotCommand command);

/// Runs a robot command on the world's robot; false (nothing done) for an unknown robot or a
/// command it does not have.
bool run_robot_command(const Command& command, World& world);

}  // namespace macsim
