// The registry of robot types: the built-in ones, and what programs and tests register.
#include "macsim/sim_core/robot_model.h"

#include <map>
#include <mutex>
#include <stdexcept>

#include "macsim/sim_core/diff_drive_robot.h"
#include "macsim/sim_core/kurt_robot.h"

namespace macsim {

RobotModel::~RobotModel() = default;

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, RobotFactory> types;
  Registry() {
    types["kurt3d"] = kurt_factory(kurt3d_config());
    types["kurt2"] = kurt_factory(kurt2_config());
    types["diff_drive"] = diff_drive_factory(DiffDriveConfig{});
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void register_robot_type(const std::string& type, RobotFactory factory) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().types[type] = std::move(factory);
}

bool robot_type_known(const std::string& type) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  return registry().types.count(type) > 0;
}

std::vector<std::string> robot_type_names() {
  std::lock_guard<std::mutex> lock(registry().mutex);
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry().types) names.push_back(name);
  return names;
}

std::unique_ptr<RobotModel> build_robot(const RobotSpec& spec, const RobotBuild& build) {
  RobotFactory factory;
  {
    std::lock_guard<std::mutex> lock(registry().mutex);
    auto found = registry().types.find(spec.type);
    if (found == registry().types.end()) {
      throw std::invalid_argument("unknown robot type '" + spec.type + "'");
    }
    factory = found->second;
  }
  return factory(spec, build);
}

}  // namespace macsim
