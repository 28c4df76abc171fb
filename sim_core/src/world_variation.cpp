#include "macsim/sim_core/world_variation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>

#include "macsim/sim_core/world_loader.h"

namespace macsim {

namespace {

/// Whether anything of this kind stands in the way of a placed object (walls and ramps bound
/// the area instead; door parts stand where the area should not reach).
bool obstacle(const ObjectSpec& object) {
  return object.kind == ObjectKind::Object || object.kind == ObjectKind::SwitchBase;
}

/// Whether `name` is `id` or ends with "/" + `id` (the path of import ids down to it).
bool name_ends_with(const std::string& name, const std::string& id) {
  return name == id || (name.size() > id.size() && name.compare(name.size() - id.size(), id.size(), id) == 0 &&
                        name[name.size() - id.size() - 1] == '/');
}

constexpr double kRobotRadius = 0.35;     // m: a KURT3D with its crane folded
constexpr std::size_t kMaxPlaced = 1000;  // each placement checks all placed before it

}  // namespace

std::vector<std::string> vary_world(WorldSpec& spec, uint32_t seed) {
  if (!spec.variation) {
    throw WorldFileError(spec.file, 0,
                         "this world has no <VARIATION>: nothing to vary by a seed (see "
                         "worlds/README.md)");
  }
  const VariationSpec& v = *spec.variation;
  std::mt19937 rng(seed);
  auto uniform = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  struct Placed {
    Eigen::Vector2d at;
    double radius;
  };
  std::vector<Placed> taken;
  auto words_of = [](const std::string& text) {  // <OBJECTS> names one user data or several, spaced
    std::vector<std::string> words;
    std::istringstream in(text);
    for (std::string word; in >> word;) words.push_back(word);
    return words;
  };
  // The objects each group places: the main area's first, then each <PLACE>'s.
  std::vector<std::vector<std::string>> kinds{words_of(v.user_data)};
  for (const PlaceGroup& g : v.groups) kinds.push_back(words_of(g.user_data));
  std::vector<std::vector<std::size_t>> chosen(kinds.size());
  std::size_t placing = 0;
  for (std::size_t i = 0; i < spec.objects.size(); ++i) {
    const ObjectSpec& o = spec.objects[i];
    std::size_t group = kinds.size();
    for (std::size_t k = 0; k < kinds.size() && group == kinds.size(); ++k)
      if (std::find(kinds[k].begin(), kinds[k].end(), o.user_data) != kinds[k].end()) group = k;
    if (o.kind == ObjectKind::Object && group < kinds.size()) {  // portable or fixed
      chosen[group].push_back(i);
      ++placing;
    } else if (obstacle(o)) {
      taken.push_back({o.pose.position.head<2>(), footprint_radius(o)});
    }
  }
  if (placing > kMaxPlaced) {
    throw WorldFileError(v.source.file, v.source.line,
                         "<VARIATION> places at most " + std::to_string(kMaxPlaced) +
                             " objects; its <OBJECTS> name " + std::to_string(placing));
  }
  std::vector<std::string> moved;
  // A place in `area` clear of everything taken; with `whole`, the footprint inside it too.
  struct Where {
    Eigen::Vector4d area;
    bool whole;
    double clearance;
    SourceLocation source;
  };
  const Where main_area{v.area, v.inside, v.clearance, v.source};
  auto place = [&](const Where& where, double radius, const std::string& what) {
    Eigen::Vector4d area = where.area;
    if (where.whole) {
      area += Eigen::Vector4d(radius, radius, -radius, -radius);
      if (area[0] > area[2] || area[1] > area[3]) {
        throw WorldFileError(where.source.file, where.source.line,
                             "<VARIATION>: " + what + " (" + std::to_string(radius) +
                                 " m from its middle) does not fit inside <AREA>");
      }
    }
    for (int attempt = 0; attempt < 2000; ++attempt) {
      const Eigen::Vector2d at(uniform(area[0], area[2]), uniform(area[1], area[3]));
      const bool free = std::all_of(taken.begin(), taken.end(), [&](const Placed& p) {
        return (p.at - at).norm() >= p.radius + radius + where.clearance;
      });
      if (free) {
        taken.push_back({at, radius});
        return at;
      }
    }
    throw WorldFileError(where.source.file, where.source.line,
                         "<VARIATION>: no room for " + what + " with a clearance of " +
                             std::to_string(where.clearance) + " m (seed " + std::to_string(seed) +
                             ")");
  };
  auto log = [&moved](const std::string& name, const Eigen::Vector2d& at, double yaw) {
    char line[256];
    std::snprintf(line, sizeof line, "%s at %.3f, %.3f, heading %.0f deg", name.c_str(), at.x(),
                  at.y(), yaw * 180.0 / M_PI);
    moved.emplace_back(line);
  };
  if (!v.robot_area) {
    // The robots stay where they are: nothing is placed on them.
    for (const auto& robot : spec.robots)
      taken.push_back({robot.pose.position.head<2>(), kRobotRadius});
  } else {
    for (auto& robot : spec.robots) {
      const Eigen::Vector2d at =
          place({*v.robot_area, false, v.clearance, v.source}, kRobotRadius, "robot '" + robot.name + "'");
      const double yaw = uniform(-M_PI, M_PI);
      robot.pose.position.head<2>() = at;
      robot.pose.orientation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
      log("robot " + robot.name, at, yaw);
    }
  }
  // One colour per material: objects that look alike behave alike, as the seed's cans do.
  std::vector<Color> palette = v.colors;
  std::shuffle(palette.begin(), palette.end(), rng);
  std::map<std::string, std::size_t> colour_of;
  // Places object `i` somewhere in `where`, at any heading.
  auto move = [&](std::size_t i, const Where& where) {
    ObjectSpec& o = spec.objects[i];
    const Eigen::Vector2d at = place(where, footprint_radius(o), "object '" + o.name + "'");
    const double yaw = uniform(-M_PI, M_PI);
    o.pose.position.head<2>() = at;
    o.pose.orientation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * o.pose.orientation;
    log(o.name, at, yaw);
  };
  for (std::size_t i : chosen.front()) {
    move(i, main_area);
    ObjectSpec& o = spec.objects[i];
    const bool keep =
        std::find(v.keep_colors.begin(), v.keep_colors.end(), o.material) != v.keep_colors.end();
    if (!palette.empty() && !o.components.empty() && !keep) {
      const auto [entry, fresh] = colour_of.try_emplace(o.material, colour_of.size());
      o.components.front().color = palette[entry->second % palette.size()];
    }
  }
  // Drawn last: the places of a world that gains a range stay what they were.
  for (const JointForceRange& range : v.joint_forces) {
    const double force = range.lo < range.hi ? uniform(range.lo, range.hi) : range.lo;
    int matched = 0;
    for (JointSpec& joint : spec.joints) {
      if (!name_ends_with(joint.name, range.joint)) continue;
      joint.max_force = force;
      ++matched;
      char line[256];
      std::snprintf(line, sizeof line, "%s max force %.3f", joint.name.c_str(), force);
      moved.emplace_back(line);
    }
    if (matched == 0) {
      throw WorldFileError(range.source.file, range.source.line,
                           "<VARY_JOINT>: no joint's name ends with '" + range.joint + "'");
    }
  }
  // Then each <PLACE>: a world that gains one keeps what it placed before.
  for (std::size_t k = 0; k < v.groups.size(); ++k) {
    const PlaceGroup& g = v.groups[k];
    if (chosen[k + 1].empty()) {
      throw WorldFileError(g.source.file, g.source.line,
                           "<PLACE>: no object has the user data '" + g.user_data + "'");
    }
    for (std::size_t i : chosen[k + 1]) move(i, {g.area, g.inside, g.clearance, g.source});
  }
  return moved;
}

}  // namespace macsim
