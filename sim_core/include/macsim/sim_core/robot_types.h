// Robot types by name (the seed's registerRobotType): a world's <ROBOT><TYPE> picks one.
#pragma once

#include <string>
#include <vector>

#include "macsim/sim_core/kurt_robot.h"

namespace macsim {

/// Registers (or replaces) a robot type. Built in: "kurt3d" (the MACS KURT3D: crane with
/// magnet, LMS200 on a rotating unit) and "kurt2" (no crane, LMS200 fixed at the front).
void register_robot_type(const std::string& name, const KurtConfig& config);
/// The configuration of a type, or nullptr if it is not registered.
const KurtConfig* find_robot_type(const std::string& name);
/// Names of the registered types, sorted.
std::vector<std::string> robot_type_names();

}  // namespace macsim
