// A robot plug-in's own command type, as a plug-in declares one in its own files: a push along x
// (N), registered once by name ("nudge"). The tests of plug-in commands use it.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "macsim/robot/robot_command.h"

namespace macsim::test {

struct Nudge {
  static constexpr std::string_view kName = "nudge";
  double force = 0;
  std::vector<double> values() const { return {force}; }
  static std::optional<Nudge> from_values(const std::vector<double>& v) {
    if (v.size() != 1) return std::nullopt;
    return Nudge{v[0]};
  }
};

/// Registers Nudge (once per process); true once it is known.
inline bool nudge_registered() {
  static const bool known =
      robot::register_command_type<Nudge>() || robot::command_decoder(Nudge::kName).has_value();
  return known;
}

}  // namespace macsim::test
