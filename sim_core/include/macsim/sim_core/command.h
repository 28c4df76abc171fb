// What the runner executes: a command as a value (gz-sim's typed user commands): its source,
// its typed robot command or request, and where its answer goes. Values can be printed, counted and
// written to a session file; the executor of each source runs them, live and in a replay alike.
#pragma once

#include <any>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
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

/// A request a server queued for the world, as that server's own typed value (gz-sim's typed
/// user commands): the runner runs it with the executor set for its type (Runner::set_executor)
/// and refuses at push() a type no executor takes. Its name and bytes serve logs and session
/// files only; nothing is steered by them.
class Request {
 public:
  virtual ~Request() = default;
  /// The operation's name ("set_density", "load_world"), for logs and session files.
  virtual std::string_view name() const = 0;
  /// Its wire form for a session file: CDR; a world load, its file's path or its XML text.
  virtual std::vector<uint8_t> wire() const = 0;
};

/// The runner's own request (source Simulation): the robots named in Command::target
/// (comma-separated; empty: every robot) keep their last commands through this step.
struct KeepRobotCommands final : Request {
  std::string_view name() const override { return "keep_robot_commands"; }
  std::vector<uint8_t> wire() const override { return {}; }
};

/// A world load (source Simulation): from a file, or from XML text when `file` is empty.
/// Recorded once the new world runs; a replay's SessionWorldLoader parses it again.
struct LoadWorldRequest final : Request {
  std::string file;
  std::string xml;
  std::string_view name() const override { return file.empty() ? "load_world_xml" : "load_world"; }
  std::vector<uint8_t> wire() const override;
};

/// A server's request as a session file holds it: its name and bytes. Only a session read
/// holds one; replay_session() gives it to a RequestReader for the typed request before it runs.
struct WireRequest final : Request {
  std::string operation;
  std::vector<uint8_t> bytes;
  std::string_view name() const override { return operation; }
  std::vector<uint8_t> wire() const override { return bytes; }
};

/// One command for the world.
struct Command {
  CommandSource source = CommandSource::Local;
  std::string target;  ///< the robot a robot command is for (or the robots kept); else empty
  /// A robot command (source Robot): the typed command the robot carries out.
  std::optional<robot::RobotCommand> robot;
  /// A request (sources Supervisor, Simulation, Ros2Service, Pictures): its typed value.
  std::shared_ptr<const Request> request;
  std::any reply_to;  ///< where its answer goes (its server's; empty in a replay)
  /// A robot command: who sent it, if known (a replay does not know).
  std::optional<Sender> sent_by;
  /// A request that puts the world back (a reset, a snapshot restored, a world loaded): the
  /// last robot command each sender of its client sent before it. None of those acts after
  /// it, however late it arrives (Runner drops them).
  std::vector<Sender> sent_before;
  /// Local only: what it does. Every other source is run by its executor from the fields above.
  std::function<void(World&)> local;

  /// The request as an R, or nullptr when it is none or of another type.
  template <class R>
  const R* request_as() const {
    return dynamic_cast<const R*>(request.get());
  }
};

/// A command from `source` carrying `request` (a Request's subclass, built in place).
template <class R, class... Args>
Command request_command(CommandSource source, Args&&... args) {
  Command c;
  c.source = source;
  c.request = std::make_shared<const R>(std::forward<Args>(args)...);
  return c;
}

/// The command's operation as logs and sessions name it: the robot command's type name
/// ("twist"), the request's name, or "" (code run in-process).
std::string_view operation_name(const Command& command);

/// The bytes a session file keeps of the command: its request's wire form (none: empty).
std::vector<uint8_t> wire_of(const Command& command);

/// One line for logs: source, operation, target, values and message size.
std::string describe(const Command& command);

/// A command for the robot named `robot` (macsim/robot/robot_command.h: robot::Twist, ...).
Command robot_command(std::string robot, robot::RobotCommand command);

/// Runs a robot command on the world's robot; false (nothing done) for an unknown robot or a
/// command it does not have.
bool run_robot_command(const Command& command, World& world);

}  // namespace macsim
