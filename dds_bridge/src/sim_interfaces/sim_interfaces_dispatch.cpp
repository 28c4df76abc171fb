#include "sim_interfaces/sim_interfaces_dispatch.h"

#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

#include "macsim/dds/convert.h"
#include "macsim/dds/wire.h"
#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim::sim_interfaces {

namespace fs = std::filesystem;
namespace rc = si::Result_Constants;
namespace cat = si::EntityCategory_Constants;
namespace bt = si::Bounds_Constants;

namespace {

/// Longest name filter taken (a regular expression; std::regex recurses on its length).
constexpr std::size_t kMaxFilterLength = 512;

/// One entity: an object or a robot.
struct Entity {
  std::string name;
  std::optional<ObjectId> object;
  const RobotModel* robot = nullptr;
};

std::vector<Entity> entities(const World& world) {
  std::vector<Entity> all;
  for (const auto& robot : world.robots())
    all.push_back({robot->name(), std::nullopt, robot.get()});
  for (ObjectId id : world.objects().object_ids())
    all.push_back({world.objects().object(id)->name, id, nullptr});
  return all;
}

std::optional<Entity> find_entity(const World& world, const std::string& name) {
  for (const auto& robot : world.robots()) {
    if (robot->name() == name) return Entity{name, std::nullopt, robot.get()};
  }
  if (auto id = world.objects().find_object(name)) return Entity{name, *id, nullptr};
  return std::nullopt;
}

std::string not_found(const std::string& name) {
  return "no entity named '" + name + "' (GetEntities lists them)";
}

/// The entity a request names; if there is none, `response` says NOT_FOUND.
template <class Response>
std::optional<Entity> named(const World& world, const std::string& name, Response& response) {
  auto e = find_entity(world, name);
  if (!e) response.result(result(rc::RESULT_NOT_FOUND, not_found(name)));
  return e;
}

Pose pose_of(const World& world, const Entity& e) {
  if (e.robot) return e.robot->base_link_pose();
  return world.objects().object_state(*e.object).value.pose;
}

uint8_t category_of(const World& world, const Entity& e) {
  if (e.robot) return cat::CATEGORY_ROBOT;
  return world.objects().object(*e.object)->portable ? cat::CATEGORY_OBJECT
                                                     : cat::CATEGORY_STATIC_OBJECT;
}

const char* kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::Object:
      return "object";
    case ObjectKind::Wall:
      return "wall";
    case ObjectKind::Ramp:
      return "ramp";
    case ObjectKind::SwitchBase:
      return "switch_base";
    case ObjectKind::SwitchPlatform:
      return "switch_platform";
    case ObjectKind::DoorFrame:
      return "door_frame";
    case ObjectKind::DoorLeaf:
      return "door_leaf";
  }
  return "object";
}

/// Tags: the kind, portable or fixed, magnetizable, the user data (objects); robot and type.
std::vector<std::string> tags_of(const World& world, const Entity& e) {
  if (e.robot) return {"robot", e.robot->spec().type};
  const ObjectSpec& o = *world.objects().object(*e.object);
  std::vector<std::string> tags{kind_name(o.kind), o.portable ? "portable" : "fixed"};
  if (o.magnetizable) tags.push_back("magnetizable");
  if (!o.user_data.empty()) tags.push_back(o.user_data);
  return tags;
}

/// The box around one component, in its object's frame.
Eigen::AlignedBox3d component_box(const ComponentSpec& c) {
  Eigen::Vector3d half;
  switch (c.shape) {
    case Shape::Box:
      half = c.size / 2;
      break;
    case Shape::Cylinder:
      half = {c.size.x(), c.size.x(), c.size.z() / 2};
      break;
    default:
      half = Eigen::Vector3d::Constant(c.size.x());
      break;  // sphere
  }
  Eigen::AlignedBox3d box;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? 1 : -1) * half.x(), (corner & 2 ? 1 : -1) * half.y(),
                                (corner & 4 ? 1 : -1) * half.z());
    box.extend(c.pose.position + c.pose.orientation * local);
  }
  return box;
}

/// The entity's box in its own frame (robots: the KURT's chassis and crane, roughly).
Eigen::AlignedBox3d local_box(const World& world, const Entity& e) {
  if (e.robot) return {Eigen::Vector3d(-0.3, -0.25, -0.1), Eigen::Vector3d(0.3, 0.25, 0.45)};
  Eigen::AlignedBox3d box;
  for (const auto& c : world.objects().object(*e.object)->components) box.extend(component_box(c));
  return box;
}

/// The entity's box in the world frame (around its rotated local box).
Eigen::AlignedBox3d world_box(const World& world, const Entity& e) {
  const Eigen::AlignedBox3d local = local_box(world, e);
  const Pose pose = pose_of(world, e);
  Eigen::AlignedBox3d box;
  for (int corner = 0; corner < 8; ++corner) {
    box.extend(pose.position +
               pose.orientation *
                   local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  }
  return box;
}

Eigen::Vector3d vec(const geometry_msgs::msg::dds_::Vector3_& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec(const geometry_msgs::msg::dds_::Point_& p) { return {p.x(), p.y(), p.z()}; }
geometry_msgs::msg::dds_::Vector3_ msg(const Eigen::Vector3d& v) {
  return dds::vector3(v.x(), v.y(), v.z());
}

Pose pose_from(const geometry_msgs::msg::dds_::Pose_& p) {
  const auto& q = p.orientation();
  return {vec(p.position()), Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z())};
}

geometry_msgs::msg::dds_::Pose_ pose_msg(const Pose& p) {
  geometry_msgs::msg::dds_::Pose_ m;
  m.position(dds::point(p.position.x(), p.position.y(), p.position.z()));
  const Eigen::Quaterniond q = p.orientation.normalized();
  m.orientation(dds::quaternion(q.x(), q.y(), q.z(), q.w()));
  return m;
}

si::EntityState_ state_of(const World& world, const Entity& e) {
  si::EntityState_ s;
  s.header(dds::header(world.time(), "world"));
  s.pose(pose_msg(pose_of(world, e)));
  Eigen::Vector3d linear, angular;
  if (e.robot) {
    linear = e.robot->linear_velocity();
    angular = e.robot->angular_velocity();
  } else {
    const ObjectState o = world.objects().object_state(*e.object).value;
    linear = o.linear_velocity;
    angular = o.angular_velocity;
  }
  s.twist().linear(msg(linear));
  s.twist().angular(msg(angular));
  return s;  // acceleration: not measured, zero
}

/// The frame a request names: the world ("" or "world") or an entity; nothing if unknown.
std::optional<Pose> frame_pose(const World& world, const std::string& frame) {
  if (frame.empty() || frame == "world") return Pose{};
  if (auto e = find_entity(world, frame)) return pose_of(world, *e);
  return std::nullopt;
}

/// The entities the filters pass, or an error Result.
std::optional<si::Result_> select(const si::EntityFilters_& f, const World& world,
                                  std::vector<Entity>& out) {
  std::optional<std::regex> name;
  if (!f.filter().empty()) {
    if (f.filter().size() > kMaxFilterLength) {
      return result(rc::RESULT_OPERATION_FAILED,
                    "the name filter is longer than " + std::to_string(kMaxFilterLength));
    }
    try {
      name.emplace(f.filter(), std::regex::extended | std::regex::nosubs);
    } catch (const std::regex_error& e) {
      return result(rc::RESULT_OPERATION_FAILED, "the name filter '" + f.filter() +
                                                     "' is no POSIX extended regular "
                                                     "expression: " +
                                                     e.what());
    }
  }
  const auto& b = f.bounds();
  if (b.type() == bt::TYPE_CONVEX_HULL) {
    return result(rc::RESULT_FEATURE_UNSUPPORTED,
                  "bounds of TYPE_CONVEX_HULL are not supported "
                  "(TYPE_BOX and TYPE_SPHERE are)");
  }
  if (b.type() > bt::TYPE_SPHERE) {
    return result(rc::RESULT_OPERATION_FAILED, "unknown bounds type " + std::to_string(b.type()));
  }
  if (b.type() != bt::TYPE_EMPTY && b.points().size() != 2) {
    return result(rc::RESULT_OPERATION_FAILED,
                  "bounds of TYPE_BOX and TYPE_SPHERE take 2 points; got " +
                      std::to_string(b.points().size()));
  }
  for (const auto& p : b.points()) {
    if (!vec(p).allFinite()) return result(rc::RESULT_OPERATION_FAILED, "bounds must be finite");
  }
  for (const Entity& e : entities(world)) {
    if (name && !std::regex_search(e.name, *name)) continue;
    if (!f.categories().empty() &&
        std::none_of(f.categories().begin(), f.categories().end(),
                     [&](const auto& c) { return c.category() == category_of(world, e); })) {
      continue;
    }
    if (!f.tags().tags().empty()) {
      const auto tags = tags_of(world, e);
      auto has = [&](const std::string& t) { return std::count(tags.begin(), tags.end(), t) > 0; };
      const auto& wanted = f.tags().tags();
      const bool all = f.tags().filter_mode() == si::TagsFilter_Constants::FILTER_MODE_ALL;
      if (all ? !std::all_of(wanted.begin(), wanted.end(), has)
              : std::none_of(wanted.begin(), wanted.end(), has)) {
        continue;
      }
    }
    if (b.type() == bt::TYPE_BOX) {
      const Eigen::Vector3d a = vec(b.points()[0]), c = vec(b.points()[1]);
      const Eigen::AlignedBox3d box(a.cwiseMin(c), a.cwiseMax(c));
      if (!box.intersects(world_box(world, e))) continue;
    } else if (b.type() == bt::TYPE_SPHERE) {
      const double radius = b.points()[1].x();
      if (world_box(world, e).exteriorDistance(vec(b.points()[0])) > radius) continue;
    }
    out.push_back(e);
  }
  return std::nullopt;
}

/// World or environment files (by their root element) in a folder, sorted; only files `roots`
/// let be read are opened.
std::vector<fs::path> xml_files(const fs::path& folder, const char* root, const DataRoots& roots) {
  std::vector<fs::path> found;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    if (!entry.is_regular_file(error) || entry.path().extension() != ".xml") continue;
    std::optional<std::string> bytes;
    try {
      bytes = roots.read(entry.path().string());
    } catch (const FileRefused&) {
      continue;  // e.g. a link out of the roots
    }
    tinyxml2::XMLDocument doc;
    if (!bytes || doc.Parse(bytes->data(), bytes->size()) != tinyxml2::XML_SUCCESS) continue;
    if (doc.RootElement() && std::string(doc.RootElement()->Name()) == root) {
      found.push_back(entry.path());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

/// The folders to search, each with its subfolders two levels down: the one holding the world's
/// file, the data roots, and the sources given inside them (those outside the roots or that are
/// no folder are named in `unknown`).
std::vector<fs::path> search_folders(const World& world, const std::vector<std::string>& sources,
                                     std::string& unknown) {
  const DataRoots& roots = world.data_roots();
  std::vector<fs::path> starts;
  std::error_code error;
  if (!world.spec().file.empty()) {
    const fs::path home = fs::absolute(world.spec().file, error).parent_path();
    if (roots.contains(home.string())) starts.push_back(home.lexically_normal());
  }
  starts.insert(starts.end(), roots.folders().begin(), roots.folders().end());
  std::vector<fs::path> folders;
  const auto add = [&folders](const fs::path& folder) {
    if (std::find(folders.begin(), folders.end(), folder) == folders.end()) {
      folders.push_back(folder);
    }
  };
  for (const fs::path& start : starts) {
    add(start);
    for (auto it = fs::recursive_directory_iterator(start, error);
         !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
      if (it.depth() >= 1) it.disable_recursion_pending();
      if (it->is_directory(error)) add(it->path());
    }
  }
  for (const std::string& s : sources) {
    const fs::path folder = uri_path(s);
    if (!roots.contains(folder.string())) {  // said before looking: no hint of what is there
      unknown += (unknown.empty() ? "" : ", ") + s + " (outside the data roots)";
    } else if (fs::is_directory(folder, error)) {
      add(folder);
    } else {
      unknown += (unknown.empty() ? "" : ", ") + s;
    }
  }
  return folders;
}

bool name_taken(const World& world, const std::string& name) {
  if (find_entity(world, name)) return true;
  for (const Entity& e : entities(world)) {
    if (e.name.rfind(name + "/", 0) == 0) return true;
  }
  return false;
}

}  // namespace

std::string uri_path(const std::string& uri) {
  return uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
}

si::Result_ result(uint8_t code, const std::string& message) {
  si::Result_ r;
  r.result(code);
  r.error_message(message);
  return r;
}

ss::GetSimulatorFeatures_Response_ features() {
  namespace f = si::SimulatorFeatures_Constants;
  ss::GetSimulatorFeatures_Response_ r;
  r.features().features() = {f::SPAWNING,
                             f::DELETING,
                             f::ENTITY_TAGS,
                             f::ENTITY_BOUNDS,
                             f::ENTITY_BOUNDS_BOX,
                             f::ENTITY_CATEGORIES,
                             f::SPAWNING_RESOURCE_STRING,
                             f::ENTITY_STATE_GETTING,
                             f::ENTITY_STATE_SETTING,
                             f::ENTITY_INFO_GETTING,
                             f::SPAWNABLES,
                             f::SIMULATION_RESET,
                             f::SIMULATION_RESET_TIME,
                             f::SIMULATION_RESET_STATE,
                             f::SIMULATION_RESET_SPAWNED,
                             f::SIMULATION_STATE_GETTING,
                             f::SIMULATION_STATE_SETTING,
                             f::SIMULATION_STATE_PAUSE,
                             f::STEP_SIMULATION_SINGLE,
                             f::STEP_SIMULATION_MULTIPLE,
                             f::STEP_SIMULATION_ACTION,
                             f::WORLD_LOADING,
                             f::WORLD_RESOURCE_STRING,
                             f::WORLD_INFO_GETTING,
                             f::AVAILABLE_WORLDS,
                             f::SPAWNING_ENTITIES};
  r.features().custom_info(
      "MACSim-DDS: an ODE simulation of the KURT3D. Entities are the world's objects (by their "
      "unique names) and robots. Spawn and load take this project's XML (macsim_xml): an "
      "<ENVIRONMENT> to spawn, a <WORLD> to load. Reset scopes: STATE, TIME|STATE, and "
      "DEFAULT/ALL (spawned objects go). The macsim_msgs topics serve the full supervisor.");
  r.features().spawn_formats().push_back("macsim_xml");
  return r;
}

ss::GetEntities_Response_ get_entities(const ss::GetEntities_Request_& q, const World& world) {
  ss::GetEntities_Response_ r;
  std::vector<Entity> found;
  if (auto error = select(q.filters(), world, found)) {
    r.result(*error);
    return r;
  }
  for (const Entity& e : found) r.entities().push_back(e.name);
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetEntitiesStates_Response_ get_entities_states(const ss::GetEntitiesStates_Request_& q,
                                                    const World& world) {
  ss::GetEntitiesStates_Response_ r;
  std::vector<Entity> found;
  if (auto error = select(q.filters(), world, found)) {
    r.result(*error);
    return r;
  }
  for (const Entity& e : found) {
    r.entities().push_back(e.name);
    r.states().push_back(state_of(world, e));
  }
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetEntityState_Response_ get_entity_state(const ss::GetEntityState_Request_& q,
                                              const World& world) {
  ss::GetEntityState_Response_ r;
  const auto e = named(world, q.entity(), r);
  if (!e) return r;
  r.state(state_of(world, *e));
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::SetEntityState_Response_ set_entity_state(const ss::SetEntityState_Request_& q, World& world) {
  constexpr uint8_t kInvalidPose = ss::SetEntityState_Response_Constants::INVALID_POSE;
  ss::SetEntityState_Response_ r;
  const auto e = named(world, q.entity(), r);
  if (!e) return r;
  if (e->robot) {
    r.result(result(rc::RESULT_OPERATION_FAILED,
                    "a robot moves by its wheels: its state cannot be set (reset the simulation "
                    "to put it back)"));
    return r;
  }
  const auto& s = q.state();
  const auto frame = frame_pose(world, s.header().frame_id());
  if (!frame) {
    r.result(result(rc::RESULT_OPERATION_FAILED,
                    "unknown frame '" + s.header().frame_id() + "': give world or an entity"));
    return r;
  }
  const Pose local = pose_from(s.pose());
  if (auto p = bounds::position_problem(local.position)) {
    r.result(result(kInvalidPose, "pose.position: " + *p));
    return r;
  }
  if (auto p = bounds::orientation_problem(local.orientation)) {
    r.result(result(kInvalidPose, "pose.orientation: " + *p));
    return r;
  }
  const Pose target = *frame * Pose{local.position, local.orientation.normalized()};
  const Eigen::Vector3d linear = frame->orientation * vec(s.twist().linear());
  const Eigen::Vector3d angular = frame->orientation * vec(s.twist().angular());
  if (auto p = bounds::magnitude_problem(linear, bounds::kMaxSpeed, "twist.linear")) {
    r.result(result(rc::RESULT_OPERATION_FAILED, *p));
    return r;
  }
  if (auto p = bounds::magnitude_problem(angular, bounds::kMaxAngularSpeed, "twist.angular")) {
    r.result(result(rc::RESULT_OPERATION_FAILED, *p));
    return r;
  }
  // A body that takes no velocity (fixed, frozen, a door's part) takes a zero twist only.
  const ObjectId id = *e->object;
  const Status free = world.objects().free_body(id, "twist");
  if (!free.ok() && (linear.norm() > 0 || angular.norm() > 0)) {
    r.result(result(rc::RESULT_OPERATION_FAILED, free.message));
    return r;
  }
  const Status moved = world.edit().set_pose(id, target, PenetrationPolicy::Refuse);
  if (!moved.ok()) {  // penetrating, or a door's part (moved with its door)
    r.result(result(
        moved.code == ErrorCode::InvalidArgument ? kInvalidPose : rc::RESULT_OPERATION_FAILED,
        moved.message));
    return r;
  }
  if (free.ok()) {  // checked above: these cannot fail
    world.edit().set_linear_velocity(id, linear);
    world.edit().set_angular_velocity(id, angular);
  }
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetEntityInfo_Response_ get_entity_info(const ss::GetEntityInfo_Request_& q,
                                            const World& world) {
  ss::GetEntityInfo_Response_ r;
  const auto e = named(world, q.entity(), r);
  if (!e) return r;
  r.info().category().category(category_of(world, *e));
  r.info().tags(tags_of(world, *e));
  if (e->robot) {
    r.info().description("robot of type " + e->robot->spec().type);
  } else {
    const ObjectSpec& o = *world.objects().object(*e->object);
    char mass[64];
    std::snprintf(mass, sizeof mass, "%.4g kg", o.mass());
    r.info().description(std::string(o.portable ? "portable " : "fixed ") + kind_name(o.kind) +
                         " of " + std::to_string(o.components.size()) + " shape(s), material " +
                         o.material + (o.portable ? ", " + std::string(mass) : std::string()));
  }
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetEntityBounds_Response_ get_entity_bounds(const ss::GetEntityBounds_Request_& q,
                                                const World& world) {
  ss::GetEntityBounds_Response_ r;
  const auto e = named(world, q.entity(), r);
  if (!e) return r;
  const Eigen::AlignedBox3d box = local_box(world, *e);
  r.bounds().type(bt::TYPE_BOX);
  r.bounds().points() = {msg(box.min()), msg(box.max())};
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::SpawnEntity_Response_ spawn_entity(const ss::SpawnEntity_Request_& q, World& world) {
  namespace sc = ss::SpawnEntity_Response_Constants;
  ss::SpawnEntity_Response_ r;
  auto fail = [&r](uint8_t code, const std::string& message) {
    r.result(result(code, message));
    return r;
  };
  if (q.uri().empty() && q.resource_string().empty()) {
    return fail(sc::NO_RESOURCE, "give uri (an <ENVIRONMENT> file) or resource_string (its XML)");
  }
  if (!q.entity_namespace().empty()) {
    return fail(sc::NAMESPACE_INVALID,
                "entity namespaces are not supported: the KURT's topics are named by the world");
  }
  const std::string file = uri_path(q.uri());
  if (!file.empty() && !world.data_roots().contains(file)) {  // said before anything else
    return fail(sc::RESOURCE_PARSE_ERROR, DataRoots::outside_message(file));
  }
  if (!file.empty() && fs::path(file).extension() != ".xml") {
    return fail(sc::UNSUPPORTED_FORMAT, "'" + q.uri() + "' is no macsim_xml file (.xml)");
  }
  // The name: the one asked for, or (renaming allowed) the first free one of name_2, name_3...
  std::string base = q.name();
  if (base.empty() && q.allow_renaming()) base = "entity";
  if (base.empty()) return fail(sc::NAME_INVALID, "no name given and allow_renaming is false");
  if (auto p = bounds::id_problem(base)) return fail(sc::NAME_INVALID, "name: " + *p);
  std::string name = base;
  for (int n = 2; name_taken(world, name); ++n) {
    if (!q.allow_renaming()) {
      return fail(sc::NAME_NOT_UNIQUE, "an entity named '" + name + "' exists already");
    }
    name = base + "_" + std::to_string(n);
  }
  const auto frame = frame_pose(world, q.initial_pose().header().frame_id());
  if (!frame) {
    return fail(sc::INVALID_POSE, "unknown frame '" + q.initial_pose().header().frame_id() +
                                      "': give world or an entity");
  }
  const Pose local = pose_from(q.initial_pose().pose());
  if (auto p = bounds::position_problem(local.position)) return fail(sc::INVALID_POSE, *p);
  if (auto p = bounds::orientation_problem(local.orientation)) return fail(sc::INVALID_POSE, *p);
  const Pose pose = *frame * Pose{local.position, local.orientation.normalized()};
  WorldSpec environment;
  try {
    environment =
        file.empty()
            ? load_environment_string(q.resource_string(), name, world.spec().materials,
                                      "resource_string.xml")
            : load_environment_file(file, name, world.spec().materials, world.data_roots());
  } catch (const std::exception& e) {  // missing, refused (outside the roots) or malformed
    return fail(sc::RESOURCE_PARSE_ERROR, e.what());
  }
  if (environment.objects.empty()) return fail(sc::RESOURCE_PARSE_ERROR, "it holds no object");
  if (!environment.robots.empty()) {
    return fail(sc::UNSUPPORTED_FORMAT, "robots cannot be spawned: a world file places them");
  }
  const bool single =
      environment.objects.size() == 1 && environment.joints.empty() && environment.doors.empty();
  if (single) environment.objects.front().name = name;  // one object: the entity itself
  const auto added = world.edit().add_environment(std::move(environment), pose);
  if (!added.ok()) {
    return fail(added.status.code == ErrorCode::LimitReached ? rc::RESULT_OPERATION_FAILED
                                                             : sc::INVALID_POSE,
                added.status.message);
  }
  r.entity_name(name);
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::SpawnEntities_Response_ spawn_entities(const ss::SpawnEntities_Request_& q, World& world) {
  ss::SpawnEntities_Response_ r;
  bool failed = false;
  for (const si::SpawnEntity_& s : q.spawn_requests()) {
    ss::SpawnEntity_Request_ one;
    one.name(s.name());
    one.allow_renaming(s.allow_renaming());
    one.uri(s.entity_resource().uri());
    one.resource_string(s.entity_resource().resource_string());
    one.entity_namespace(s.entity_namespace());
    one.initial_pose(s.initial_pose());
    const auto spawned = spawn_entity(one, world);
    si::SpawnResult_ each;
    each.result(spawned.result());
    each.entity_name(spawned.entity_name());
    failed = failed || spawned.result().result() != rc::RESULT_OK;
    r.results().push_back(each);
  }
  r.result(failed ? result(ss::SpawnEntities_Response_Constants::ENTITIES_SPAWN_FAILED,
                           "at least one spawn failed: see results")
                  : result(rc::RESULT_OK));
  return r;
}

ss::DeleteEntity_Response_ delete_entity(const ss::DeleteEntity_Request_& q, World& world) {
  ss::DeleteEntity_Response_ r;
  const auto e = find_entity(world, q.entity());
  if (e && e->robot) {
    r.result(result(rc::RESULT_OPERATION_FAILED, "robots cannot be deleted (load another world)"));
    return r;
  }
  std::vector<ObjectId> doomed;
  if (e) {
    doomed.push_back(*e->object);
  } else if (!q.entity().empty()) {  // a spawned group: every object under the name
    for (const Entity& each : entities(world)) {
      if (each.object && each.name.rfind(q.entity() + "/", 0) == 0) doomed.push_back(*each.object);
    }
  }
  if (doomed.empty()) {
    r.result(result(rc::RESULT_NOT_FOUND, not_found(q.entity())));
    return r;
  }
  for (ObjectId id : doomed) world.edit().destroy_object(id);  // a door's parts may be gone already
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetSpawnables_Response_ get_spawnables(const ss::GetSpawnables_Request_& q,
                                           const World& world) {
  ss::GetSpawnables_Response_ r;
  std::string unknown;
  for (const fs::path& folder : search_folders(world, q.sources(), unknown)) {
    for (const fs::path& file : xml_files(folder, "ENVIRONMENT", world.data_roots())) {
      si::Spawnable_ s;
      s.uri("file://" + file.string());
      s.description("macsim_xml environment " + file.filename().string());
      r.spawnables().push_back(s);
    }
  }
  r.result(result(rc::RESULT_OK, unknown.empty() ? "" : "not folders, not searched: " + unknown));
  return r;
}

ss::GetCurrentWorld_Response_ get_current_world(const World& world) {
  ss::GetCurrentWorld_Response_ r;
  r.world().name(world.spec().name);
  if (!world.spec().file.empty()) {
    std::error_code error;
    r.world().world_resource().uri("file://" + fs::absolute(world.spec().file, error).string());
  }
  r.world().description(std::to_string(world.objects().object_count()) + " objects, " +
                        std::to_string(world.robots().size()) + " robot(s), " +
                        std::to_string(world.doors().door_count()) + " door(s)");
  r.result(result(rc::RESULT_OK));
  return r;
}

ss::GetAvailableWorlds_Response_ get_available_worlds(const ss::GetAvailableWorlds_Request_& q,
                                                      const World& world) {
  ss::GetAvailableWorlds_Response_ r;
  if (!q.filter().tags().empty()) {
    r.result(result(rc::RESULT_FEATURE_UNSUPPORTED, "worlds carry no tags"));
    return r;
  }
  std::string unknown;
  for (const fs::path& folder : search_folders(world, q.additional_sources(), unknown)) {
    for (const fs::path& file : xml_files(folder, "WORLD", world.data_roots())) {
      si::WorldResource_ w;
      w.name(file.stem().string());
      w.world_resource().uri("file://" + file.string());
      w.description("macsim_xml world " + file.filename().string());
      r.worlds().push_back(w);
    }
  }
  if (!unknown.empty() && !q.continue_on_error() && r.worlds().empty()) {
    r.result(result(rc::RESULT_OPERATION_FAILED, "not folders: " + unknown));
  } else {
    r.result(result(rc::RESULT_OK, unknown.empty() ? "" : "not folders, not searched: " + unknown));
  }
  return r;
}

ss::ResetSimulation_Response_ reset_simulation(const ss::ResetSimulation_Request_& q,
                                               World& world) {
  namespace sc = ss::ResetSimulation_Request_Constants;
  ss::ResetSimulation_Response_ r;
  const int scope = q.scope();
  const int all = sc::SCOPE_TIME | sc::SCOPE_STATE | sc::SCOPE_SPAWNED;
  if (scope == sc::SCOPE_DEFAULT || scope == sc::SCOPE_ALL || scope == all) {
    world.reset(ResetScope::Everything);
  } else if (scope == sc::SCOPE_STATE) {
    world.reset(ResetScope::Poses);
  } else if (scope == (sc::SCOPE_TIME | sc::SCOPE_STATE)) {
    world.reset(ResetScope::PosesAndTime);
  } else {
    r.result(result(rc::RESULT_FEATURE_UNSUPPORTED,
                    "scope " + std::to_string(scope) +
                        ": time goes back only with the state (TIME|STATE = 3), spawned objects "
                        "go only with everything (DEFAULT, ALL); STATE alone keeps time"));
    return r;
  }
  r.result(result(rc::RESULT_OK));
  return r;
}

namespace {

/// A service whose requests a session records: its name there, how its request is read back,
/// and how a replay runs it.
struct RecordedService {
  const char* name;
  std::shared_ptr<const Request> (*read)(const WireRequest&);
  void (*replay_on)(Runner&);
};

/// The entry of the service whose request is a PubSubType, run on the world by `run` (its
/// response dropped: a replay answers nobody).
template <class PubSubType, auto run>
constexpr RecordedService recorded(const char* name) {
  static_assert(kChangesWorld<PubSubType>, "only a service that changes the world is recorded");
  using Queued = ServiceRequest<PubSubType>;
  return {name, &Queued::read, [](Runner& runner) {
            runner.set_executor<Queued>([](const Queued& q, const Command&, World& world) {
              run(q.message(), world);
              return true;
            });
          }};
}

/// Only STOPPED changes the world: it puts it back as loaded.
void stop(const ss::SetSimulationState_Request_& q, World& world) {
  if (q.state().state() == si::SimulationState_Constants::STATE_STOPPED)
    world.reset(ResetScope::Everything);
}

/// The services whose requests change the world, as a session names them (their servers' names).
constexpr std::array<RecordedService, 6> kRecorded{{
    recorded<ss::SetEntityState_Request_PubSubType, set_entity_state>("set_entity_state"),
    recorded<ss::SpawnEntity_Request_PubSubType, spawn_entity>("spawn_entity"),
    recorded<ss::SpawnEntities_Request_PubSubType, spawn_entities>("spawn_entities"),
    recorded<ss::DeleteEntity_Request_PubSubType, delete_entity>("delete_entity"),
    recorded<ss::ResetSimulation_Request_PubSubType, reset_simulation>("reset_simulation"),
    recorded<ss::SetSimulationState_Request_PubSubType, stop>("set_simulation_state"),
}};
static_assert(kRecorded.size() == std::tuple_size_v<WorldChangingServices>,
              "a replay entry for every service that changes the world");

}  // namespace

void replay_on(Runner& runner) {
  for (const RecordedService& service : kRecorded) service.replay_on(runner);
}

std::shared_ptr<const Request> read_recorded(const WireRequest& recorded) {
  for (const RecordedService& service : kRecorded) {
    if (recorded.operation == service.name) return service.read(recorded);
  }
  return nullptr;
}

}  // namespace macsim::sim_interfaces
