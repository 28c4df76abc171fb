// The world's door table (world_internal.h): the door-switch structures' records, driven at
// each step (a pressed switch opens its door); and WorldDoors (world.h), its view: read,
// triggered and moved by the supervisor.
#include <algorithm>
#include <cmath>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_bounds.h"
#include "world_internal.h"

namespace macsim {

int WorldDoors::door_count() const { return static_cast<int>(doors_.doors().size()); }

std::optional<int> WorldDoors::find_door(const std::string& name) const {
  const auto& doors = doors_.doors();
  for (std::size_t i = 0; i < doors.size(); ++i) {
    if (doors[i]->spec.name == name) return static_cast<int>(i);
  }
  return std::nullopt;
}

Result<int> WorldDoors::get_door_by_name(const std::string& name) const {
  if (const auto door = find_door(name)) return {{}, *door};
  return {Status::error(ErrorCode::UnknownObject, "no door named '" + name + "' (there are " +
                                                      std::to_string(door_count()) + ")")};
}

Status WorldDoors::check_door(int door) const {
  if (door < 0 || door >= door_count()) {
    return Status::error(ErrorCode::UnknownObject, "no door with index " + std::to_string(door) +
                                                       " (there are " +
                                                       std::to_string(door_count()) + ")");
  }
  return {};
}

const std::string& WorldDoors::door_name(int door) const {
  return doors_.doors().at(door)->spec.name;
}

Result<DoorState> WorldDoors::door_state(int door) const {
  if (Status s = check_door(door); !s.ok()) return {s};
  return {{}, detail::DoorTable::state_of(*doors_.doors()[door])};
}

Result<DoorParts> WorldDoors::door_parts(int door) const {
  if (Status s = check_door(door); !s.ok()) return {s};
  return {{}, doors_.parts(door)};
}

Status WorldDoors::set_switch_triggered(int door, bool triggered) {
  if (Status s = check_door(door); !s.ok()) return s;
  doors_.doors()[door]->flags.virtual_trigger = triggered;
  return {};
}

Status WorldDoors::move_door_part(int door, bool leaf, const Eigen::Vector3d& position) {
  if (Status s = check_door(door); !s.ok()) return s;
  if (auto p = bounds::position_problem(position)) return detail::invalid_argument(*p);
  detail::DoorRecord& d = *doors_.doors()[door];
  const std::string moving_name = leaf ? d.spec.leaf : d.spec.switch_platform;
  const std::string fixed_name = leaf ? d.spec.frame : d.spec.switch_base;
  detail::JointRecord* joint = leaf ? d.door_joint : d.switch_joint;
  const detail::ObjectRecord* moving = objects_.find_named(moving_name);
  if (!moving || !joint) {
    return Status::error(ErrorCode::NotApplicable, "door '" + d.spec.name + "' has no switch");
  }
  const Eigen::Vector3d delta = position - detail::object_state(*moving).pose.position;
  // The moving part, its fixed part and their joint move together.
  joint->position = joint->spec.type == JointSpec::Type::Slider
                        ? dJointGetSliderPosition(joint->joint)
                        : dJointGetHingeAngle(joint->joint);
  dJointDestroy(joint->joint);
  joint->joint = nullptr;
  joint->spec.anchor += delta;
  Status status;
  for (const std::string* name : {&moving_name, &fixed_name}) {
    detail::ObjectRecord* found = objects_.find_named(*name);
    if (!found) continue;
    detail::ObjectRecord& o = *found;
    ObjectState state = detail::object_state(o);
    state.pose.position += delta;
    o.spec.pose.position += delta;
    const ObjectSpec spec = o.spec;
    physics_.destroy_object(o);
    o.spec = spec;
    physics_.build_object(o);
    if (o.body) {
      const Pose body = state.pose * Pose{o.com, Eigen::Quaterniond::Identity()};
      detail::set_body_state(
          o.body, {body.position, body.orientation, state.linear_velocity, state.angular_velocity});
    }
    for (const auto& hit : physics_.penetrations(o)) status.penetrated.push_back(hit);
  }
  physics_.build_joint(*joint);
  physics_.structure_changed();
  if (!status.penetrated.empty()) {
    physics_.emit(WorldEvent::Type::Penetration, d.spec.name,
                  "moved into " + status.penetrated.front());
  }
  return status;
}

Status WorldDoors::set_door_position(int door, const Eigen::Vector3d& position) {
  return move_door_part(door, true, position);
}

Status WorldDoors::set_switch_position(int door, const Eigen::Vector3d& position) {
  return move_door_part(door, false, position);
}

// ---- the records and the step ------------------------------------------------------------

namespace detail {

void DoorTable::add(DoorSpec spec, DoorFlags flags) {
  auto record = std::make_unique<detail::DoorRecord>();
  record->spec = std::move(spec);
  record->flags = flags;
  doors_.push_back(std::move(record));
}

void DoorTable::remove(int door) {
  doors_.erase(doors_.begin() + door);
  wire();
}

void DoorTable::wire() {
  for (const auto& object : objects_.objects()) object->door = -1;
  for (std::size_t d = 0; d < doors_.size(); ++d) {
    DoorRecord& door = *doors_[d];
    door.door_joint = objects_.joint_named(door.spec.door_joint);
    door.switch_joint =
        door.spec.switch_joint.empty() ? nullptr : objects_.joint_named(door.spec.switch_joint);
    const DoorSpec& s = door.spec;
    for (const std::string* part : {&s.leaf, &s.frame, &s.switch_platform, &s.switch_base}) {
      if (ObjectRecord* o = objects_.find_named(*part)) o->door = static_cast<int>(d);
    }
  }
}

DoorParts DoorTable::parts(int door) const {
  const DoorSpec& s = doors_.at(door)->spec;
  auto id = [this](const std::string& name) -> std::optional<ObjectId> {
    if (const ObjectRecord* o = objects_.find_named(name)) return o->id;
    return std::nullopt;
  };
  DoorParts parts;
  parts.leaf = id(s.leaf).value_or(0);
  parts.frame = id(s.frame).value_or(0);
  parts.platform = id(s.switch_platform);
  parts.base = id(s.switch_base);
  return parts;
}

void DoorTable::before_step() {
  for (auto& door : doors_) {
    bool pressed = false;
    if (door->switch_joint && door->switch_joint->joint) {
      const JointSpec& s = door->switch_joint->spec;
      const double pos = dJointGetSliderPosition(door->switch_joint->joint);
      pressed = pos <= s.lo + 0.1 * (s.hi - s.lo);  // pressed fully (within 10 % of travel)
    }
    const bool triggered = door->flags.virtual_trigger || pressed;
    if (triggered != door->flags.triggered) {
      door->flags.triggered = triggered;
      physics_.emit(
          triggered ? WorldEvent::Type::SwitchTriggered : WorldEvent::Type::SwitchReleased,
          door->spec.name, door->flags.virtual_trigger ? "virtual" : "pressed");
    }
    JointRecord* j = door->door_joint;
    if (!j || !j->joint) continue;
    const double speed = std::fabs(j->spec.velocity);
    const double velocity = triggered ? speed : -speed;  // open towards HI, close towards LO
    if (j->spec.type == JointSpec::Type::Slider) {
      dJointSetSliderParam(j->joint, dParamVel, velocity);
    } else {
      dJointSetHingeParam(j->joint, dParamVel, velocity);
    }
  }
}

void DoorTable::after_step() {
  for (auto& door : doors_) {
    const DoorGap before = door->flags.gap;
    door->flags.gap = state_of(*door).gap;
    if (door->flags.gap != before && door->flags.gap != DoorGap::Half) {
      physics_.emit(door->flags.gap == DoorGap::Open ? WorldEvent::Type::DoorOpened
                                                     : WorldEvent::Type::DoorClosed,
                    door->spec.name);
    }
  }
}

DoorState DoorTable::state_of(const DoorRecord& door) {
  DoorState state;
  state.virtually_triggered = door.flags.virtual_trigger;
  state.triggered = door.flags.triggered;
  if (door.switch_joint && door.switch_joint->joint) {
    const JointSpec& s = door.switch_joint->spec;
    const double pos = dJointGetSliderPosition(door.switch_joint->joint);
    state.switch_travel = std::clamp((s.hi - pos) / (s.hi - s.lo), 0.0, 1.0);
  }
  if (door.door_joint && door.door_joint->joint) {
    const JointSpec& s = door.door_joint->spec;
    const double pos = s.type == JointSpec::Type::Slider
                           ? dJointGetSliderPosition(door.door_joint->joint)
                           : dJointGetHingeAngle(door.door_joint->joint);
    state.opening = std::clamp((pos - s.lo) / (s.hi - s.lo), 0.0, 1.0);
  }
  state.gap = state.opening < 0.05   ? DoorGap::Closed
              : state.opening > 0.95 ? DoorGap::Open
                                     : DoorGap::Half;
  return state;
}

}  // namespace detail

}  // namespace macsim
