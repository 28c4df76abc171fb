#include "macsim/sim_core/robot_types.h"

#include <map>
#include <memory>
#include <mutex>

namespace macsim {

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, std::unique_ptr<KurtConfig>> types;
  Registry() {
    KurtConfig kurt3d;  // defaults: crane, rotating laser
    types["kurt3d"] = std::make_unique<KurtConfig>(kurt3d);
    KurtConfig kurt2;
    kurt2.crane = false;
    kurt2.laser = LaserMount::Fixed;
    kurt2.cameras.reset();  // the KURT2 has no stereo pair
    types["kurt2"] = std::make_unique<KurtConfig>(kurt2);
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void register_robot_type(const std::string& name, const KurtConfig& config) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().types[name] = std::make_unique<KurtConfig>(config);
}

const KurtConfig* find_robot_type(const std::string& name) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  auto found = registry().types.find(name);
  return found == registry().types.end() ? nullptr : found->second.get();
}

std::vector<std::string> robot_type_names() {
  std::lock_guard<std::mutex> lock(registry().mutex);
  std::vector<std::string> names;
  for (const auto& [name, config] : registry().types) names.push_back(name);
  return names;
}

}  // namespace macsim
