#include "supervisor/supervisor_codec.h"

#include "macsim/dds/convert.h"

namespace macsim::codec {

// Each sim_core enum that travels, tied to its wire value: a reordered enum fails to compile.
static_assert(static_cast<int>(ErrorCode::Ok) == mm::ERR_OK);
static_assert(static_cast<int>(ErrorCode::UnknownObject) == mm::ERR_UNKNOWN_OBJECT);
static_assert(static_cast<int>(ErrorCode::WrongGeometry) == mm::ERR_WRONG_GEOMETRY);
static_assert(static_cast<int>(ErrorCode::InvalidArgument) == mm::ERR_INVALID_ARGUMENT);
static_assert(static_cast<int>(ErrorCode::NotApplicable) == mm::ERR_NOT_APPLICABLE);
static_assert(static_cast<int>(ErrorCode::Penetration) == mm::ERR_PENETRATION);
static_assert(static_cast<int>(ErrorCode::BadTexture) == mm::ERR_BAD_TEXTURE);
static_assert(static_cast<int>(ErrorCode::BadFile) == mm::ERR_BAD_FILE);
static_assert(static_cast<int>(ErrorCode::LimitReached) == mm::ERR_LIMIT_REACHED);
static_assert(static_cast<int>(Shape::Box) == mm::SHAPE_BOX);
static_assert(static_cast<int>(Shape::Cylinder) == mm::SHAPE_CYLINDER);
static_assert(static_cast<int>(Shape::Sphere) == mm::SHAPE_SPHERE);
static_assert(static_cast<int>(ObjectKind::Object) == mm::KIND_OBJECT);
static_assert(static_cast<int>(ObjectKind::Wall) == mm::KIND_WALL);
static_assert(static_cast<int>(ObjectKind::Ramp) == mm::KIND_RAMP);
static_assert(static_cast<int>(ObjectKind::SwitchBase) == mm::KIND_SWITCH_BASE);
static_assert(static_cast<int>(ObjectKind::SwitchPlatform) == mm::KIND_SWITCH_PLATFORM);
static_assert(static_cast<int>(ObjectKind::DoorFrame) == mm::KIND_DOOR_FRAME);
static_assert(static_cast<int>(ObjectKind::DoorLeaf) == mm::KIND_DOOR_LEAF);
static_assert(static_cast<int>(DoorGap::Closed) == mm::GAP_CLOSED);
static_assert(static_cast<int>(DoorGap::Half) == mm::GAP_HALF);
static_assert(static_cast<int>(DoorGap::Open) == mm::GAP_OPEN);
static_assert(static_cast<int>(ResetScope::Poses) == mm::RESET_POSES);
static_assert(static_cast<int>(ResetScope::PosesAndTime) == mm::RESET_POSES_AND_TIME);
static_assert(static_cast<int>(ResetScope::Everything) == mm::RESET_EVERYTHING);

gm::Pose_ pose_message(const Pose& p) {
  gm::Pose_ m;
  m.position(dds::point(p.position.x(), p.position.y(), p.position.z()));
  m.orientation(
      dds::quaternion(p.orientation.x(), p.orientation.y(), p.orientation.z(), p.orientation.w()));
  return m;
}

Eigen::Vector3d vector_of(const gm::Vector3_& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d vector_of(const gm::Point_& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Quaterniond quaternion_of(const gm::Quaternion_& q) { return {q.w(), q.x(), q.y(), q.z()}; }

Pose pose_of(const gm::Pose_& m) {
  return {vector_of(m.position()), quaternion_of(m.orientation())};
}

mm::Object_ object_message(const World& world, ObjectId id) {
  mm::Object_ o;
  const ObjectSpec* spec = world.objects().object(id);
  if (!spec) return o;
  const ObjectState state = world.objects().object_state(id).value;
  o.id(id);
  o.name(spec->name);
  o.kind(static_cast<int32_t>(spec->kind));
  o.portable(spec->portable);
  for (const auto& c : spec->components) {
    mm::Component_ m;
    m.shape(static_cast<int32_t>(c.shape));
    m.size({c.size.x(), c.size.y(), c.size.z()});
    m.pose(pose_message(c.pose));
    m.color(c.color);
    m.texture(c.texture);
    o.components().push_back(m);
  }
  o.pose(pose_message(state.pose));
  const auto& v = state.linear_velocity;
  const auto& w = state.angular_velocity;
  o.velocity().linear(dds::vector3(v.x(), v.y(), v.z()));
  o.velocity().angular(dds::vector3(w.x(), w.y(), w.z()));
  o.density(spec->density);
  o.mass(spec->portable ? world.objects().object_mass(id).value : 0.0);
  o.material(spec->material);
  o.magnetizable(spec->magnetizable);
  o.frozen(spec->frozen);
  o.user_data(spec->user_data);
  o.user_color(spec->user_color);
  o.user_shape(spec->user_shape);
  if (spec->ramp) o.ramp({spec->ramp->width, spec->ramp->height, spec->ramp->angle});
  return o;
}

std::optional<ObjectSpec> spec_of(const mm::Object_& o, std::string& error) {
  ObjectSpec spec;
  spec.name = o.name();
  spec.portable = o.portable();
  spec.pose = pose_of(o.pose());
  spec.density = o.density() > 0 ? o.density() : 100.0;
  if (!o.material().empty()) spec.material = o.material();
  spec.magnetizable = o.magnetizable();
  spec.frozen = o.frozen();
  spec.user_data = o.user_data();
  spec.user_color = o.user_color();
  spec.user_shape = o.user_shape();
  for (const auto& m : o.components()) {
    if (m.shape() < mm::SHAPE_BOX || m.shape() > mm::SHAPE_SPHERE) {
      error = "unknown shape code " + std::to_string(m.shape()) +
              " (SHAPE_BOX, SHAPE_CYLINDER or SHAPE_SPHERE)";
      return std::nullopt;
    }
    ComponentSpec c;
    c.shape = static_cast<Shape>(m.shape());
    c.size = {m.size()[0], m.size()[1], m.size()[2]};
    c.pose = pose_of(m.pose());
    c.color = m.color();
    c.texture = m.texture();
    spec.components.push_back(c);
  }
  if (o.kind() == mm::KIND_RAMP) {
    spec.ramp = RampGeometry{o.ramp()[0], o.ramp()[1], o.ramp()[2]};
  } else if (o.kind() != mm::KIND_OBJECT) {
    error = "only objects (KIND_OBJECT) and ramps (KIND_RAMP) can be created; got kind " +
            std::to_string(o.kind());
    return std::nullopt;
  }
  if (o.mass() > 0 && spec.volume() > 0) spec.density = o.mass() / spec.volume();
  return spec;
}

mm::Door_ door_message(const World& world, int door) {
  mm::Door_ d;
  const DoorState s = world.doors().door_state(door).value;
  d.name(world.doors().door_name(door));
  d.triggered(s.triggered);
  d.virtually_triggered(s.virtually_triggered);
  d.gap(static_cast<int32_t>(s.gap));
  d.opening(s.opening);
  d.switch_travel(s.switch_travel);
  return d;
}

const char* event_name(WorldEvent::Type type) {
  switch (type) {
    case WorldEvent::Type::SwitchTriggered:
      return "switch_triggered";
    case WorldEvent::Type::SwitchReleased:
      return "switch_released";
    case WorldEvent::Type::DoorOpened:
      return "door_opened";
    case WorldEvent::Type::DoorClosed:
      return "door_closed";
    case WorldEvent::Type::Penetration:
      return "penetration";
    case WorldEvent::Type::Instability:
      return "instability";
    case WorldEvent::Type::ObjectAttached:
      return "attached";
    case WorldEvent::Type::ObjectReleased:
      return "released";
  }
  return "?";
}

int32_t error_code(ErrorCode code) { return static_cast<int32_t>(code); }

std::vector<Sender> senders(const std::vector<mm::SampleIdentity_>& commands_sent) {
  std::vector<Sender> out;
  out.reserve(commands_sent.size());
  for (const auto& sent : commands_sent)
    out.push_back(Sender{sent.writer_guid(), sent.sequence_number()});
  return out;
}

}  // namespace macsim::codec
