#include "macsim/robot/robot_command.h"

#include <algorithm>
#include <map>
#include <mutex>

namespace macsim::robot {

std::optional<Twist> Twist::from_values(const std::vector<double>& v) {
  if (v.size() != 2) return std::nullopt;
  return Twist{v[0], v[1]};
}

std::optional<WheelSpeedCommand> WheelSpeedCommand::from_values(const std::vector<double>& v) {
  if (v.size() != 2) return std::nullopt;
  return WheelSpeedCommand{v[0], v[1]};
}

std::optional<RotunitSpeed> RotunitSpeed::from_values(const std::vector<double>& v) {
  if (v.size() != 1) return std::nullopt;
  return RotunitSpeed{v[0]};
}

std::optional<CraneTarget> CraneTarget::from_values(const std::vector<double>& v) {
  if (v.size() != 3) return std::nullopt;
  return CraneTarget{v[0], v[1], v[2]};
}

std::optional<MagnetSwitch> MagnetSwitch::from_values(const std::vector<double>& v) {
  if (v.size() != 1) return std::nullopt;
  return MagnetSwitch{v[0] != 0};
}

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, CommandDecoder, std::less<>> decoders;
  Registry() {
    add<Twist>();
    add<WheelSpeedCommand>();
    add<RotunitSpeed>();
    add<CraneTarget>();
    add<MagnetSwitch>();
  }
  template <class T>
  void add() {
    decoders[std::string(T::kName)] = decoder_of<T>();
  }
};

Registry& registry() {
  static Registry instance;
  return instance;
}

}  // namespace

bool register_command_type(std::string_view name, CommandDecoder decode) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.decoders.emplace(std::string(name), std::move(decode)).second;
}

std::optional<CommandDecoder> command_decoder(std::string_view name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  const auto found = r.decoders.find(name);
  if (found == r.decoders.end()) return std::nullopt;
  return found->second;
}

std::optional<RobotCommand> decode_command(std::string_view name, const std::vector<double>& values,
                                           std::string* why) {
  const auto decode = command_decoder(name);
  if (!decode) {
    if (why) *why = "no robot command '" + std::string(name) + "'";
    return std::nullopt;
  }
  auto command = (*decode)(values);
  if (!command && why) {
    *why = "robot command '" + std::string(name) + "' does not take " +
           std::to_string(values.size()) + " numbers";
  }
  return command;
}

std::vector<std::string> command_type_names() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, decode] : r.decoders) names.push_back(name);
  return names;
}

}  // namespace macsim::robot
