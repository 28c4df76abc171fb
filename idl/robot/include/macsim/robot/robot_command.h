// A robot's command as a type, from the robot node through the simulator's runner (or the real
// robot's adapter) to the robot: a Twist is a Twist all the way, never a name matched at run
// time. The built-in commands are below; a robot plug-in declares its own in its own files
// (a struct with a name and its numbers, registered once: register_command_type<T>()), and it
// travels the same way. Names and numbers are only the written form, for sessions and logs.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

namespace macsim::robot {

/// cmd_vel: m/s forward, rad/s counter-clockwise, held until the command timeout.
struct Twist {
  static constexpr std::string_view kName = "twist";
  double linear = 0, angular = 0;
  std::vector<double> values() const { return {linear, angular}; }
  static std::optional<Twist> from_values(const std::vector<double>& v);
};

/// The wheel rims' speeds, m/s, held until the command timeout.
struct WheelSpeedCommand {
  static constexpr std::string_view kName = "wheel_speeds";
  double left = 0, right = 0;
  std::vector<double> values() const { return {left, right}; }
  static std::optional<WheelSpeedCommand> from_values(const std::vector<double>& v);
};

/// The rotating laser unit's speed, rad/s.
struct RotunitSpeed {
  static constexpr std::string_view kName = "rotunit";
  double speed = 0;
  std::vector<double> values() const { return {speed}; }
  static std::optional<RotunitSpeed> from_values(const std::vector<double>& v);
};

/// The crane's joint targets: slew (rad), lift (rad), hoist (m).
struct CraneTarget {
  static constexpr std::string_view kName = "crane";
  double slew = 0, lift = 0, hoist = 0;
  std::vector<double> values() const { return {slew, lift, hoist}; }
  static std::optional<CraneTarget> from_values(const std::vector<double>& v);
};

/// The magnet on or off.
struct MagnetSwitch {
  static constexpr std::string_view kName = "magnet";
  bool on = false;
  std::vector<double> values() const { return {on ? 1.0 : 0.0}; }
  static std::optional<MagnetSwitch> from_values(const std::vector<double>& v);
};

/// One command of any type T with `kName`, `values()` and `from_values()`: a value, cheap to
/// copy. A robot takes the types it has (`as<T>()`) and refuses the rest.
class RobotCommand {
 public:
  template <class T, class = decltype(T::kName)>
  RobotCommand(T command)  // NOLINT: every command type converts implicitly
      : model_(std::make_shared<const Model<T>>(std::move(command))) {}

  /// The command if it is a T, else nullptr.
  template <class T>
  const T* as() const {
    return model_->type() == typeid(T) ? &static_cast<const Model<T>&>(*model_).command : nullptr;
  }
  /// Its type's name ("twist", ...): its written form with values().
  std::string_view name() const { return model_->name(); }
  /// Its numbers (SI units), in its type's order.
  std::vector<double> values() const { return model_->values(); }

 private:
  struct Concept {
    virtual ~Concept() = default;
    virtual const std::type_info& type() const = 0;
    virtual std::string_view name() const = 0;
    virtual std::vector<double> values() const = 0;
  };
  template <class T>
  struct Model final : Concept {
    explicit Model(T c) : command(std::move(c)) {}
    const std::type_info& type() const override { return typeid(T); }
    std::string_view name() const override { return T::kName; }
    std::vector<double> values() const override { return command.values(); }
    T command;
  };
  std::shared_ptr<const Concept> model_;
};

/// Reads a command back from its written form, or nothing (numbers that do not fit).
using CommandDecoder = std::function<std::optional<RobotCommand>(const std::vector<double>&)>;

/// The decoder of the command type T.
template <class T>
CommandDecoder decoder_of() {
  return [](const std::vector<double>& v) {
    auto command = T::from_values(v);
    return command ? std::optional<RobotCommand>(std::move(*command)) : std::nullopt;
  };
}

/// Makes a command type known by its name (the built-in ones are); false if the name is taken.
bool register_command_type(std::string_view name, CommandDecoder decode);
template <class T>
bool register_command_type() {
  return register_command_type(T::kName, decoder_of<T>());
}

/// The decoder of the command type of that name, or nothing.
std::optional<CommandDecoder> command_decoder(std::string_view name);

/// The command written as `name` and `values` (a session's line), or nothing: an unknown name,
/// or numbers that do not fit it (`why` says which).
std::optional<RobotCommand> decode_command(std::string_view name, const std::vector<double>& values,
                                           std::string* why = nullptr);

/// The names of the command types known, sorted.
std::vector<std::string> command_type_names();

}  // namespace macsim::robot
