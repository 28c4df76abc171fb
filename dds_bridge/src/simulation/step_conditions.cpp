#include "simulation/step_conditions.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
// A request may make the reply carry at most this many sample values (512 KiB).
constexpr double kMaxSampleValues = 65536;

bool robot_reading(int32_t what) { return what >= mm::STEP_READ_ODOMETRY_X && what <= mm::STEP_READ_CRANE_HOLDING; }
bool object_reading(int32_t what) {
  return what >= mm::STEP_READ_OBJECT_X && what <= mm::STEP_READ_OBJECT_TILT_RATE;
}

}  // namespace

std::variant<StepConditions, std::string> StepConditions::compile(
    const mm::SimulationRequest_& q, const World& world, const LatestReadings& readings) {
  StepConditions out;
  out.readings_ = readings;
  // A reading named by field `field`: known, of a robot or an object that exists.
  auto reading = [&](const mm::StepCondition_& c, const std::string& field,
                     Reading& r) -> std::string {
    r = {c.reading(), c.robot(), c.object_id()};
    if (c.reading() < mm::STEP_READ_SIM_TIME || c.reading() > mm::STEP_READ_OBJECT_TILT_RATE)
      return field + ".reading " + std::to_string(c.reading()) + " is no STEP_READ_* value";
    if (robot_reading(c.reading()) && (!readings || !readings(c.robot())))
      return field + ".robot: no robot '" + c.robot() + "' here";
    if (object_reading(c.reading()) && !world.objects().object_state(c.object_id()).ok())
      return field + ".object_id: no object " + std::to_string(c.object_id());
    return "";
  };
  for (std::size_t i = 0; i < q.until().size(); ++i) {
    const auto& c = q.until()[i];
    const std::string field = "until[" + std::to_string(i) + "]";
    Condition condition;
    if (auto error = reading(c, field, condition.reading); !error.empty()) return error;
    if (c.test() < mm::STEP_TEST_ABOVE || c.test() > mm::STEP_TEST_STALLED)
      return field + ".test " + std::to_string(c.test()) + " is no STEP_TEST_* value";
    if (!std::isfinite(c.value()) || !std::isfinite(c.tolerance()) || c.tolerance() < 0)
      return field + ": value and tolerance must be finite, tolerance not negative";
    if (c.test() == mm::STEP_TEST_STALLED && !(c.value() > 0))
      return field + ".value: a stall lasts a positive number of seconds";
    if (c.group() < 0) return field + ".group must not be negative";
    condition.test = c.test();
    condition.value = c.value();
    condition.tolerance = c.tolerance();
    condition.group = c.group();
    out.until_.push_back(condition);
  }
  for (std::size_t i = 0; i < q.samples().size(); ++i) {
    Reading r;
    if (auto error = reading(q.samples()[i], "samples[" + std::to_string(i) + "]", r);
        !error.empty())
      return error;
    out.recorded_.push_back(r);
  }
  const double every = std::max<double>(q.check_every(), 1);
  if (!out.recorded_.empty() &&
      std::ceil(static_cast<double>(q.steps()) / every) * static_cast<double>(out.recorded_.size()) >
          kMaxSampleValues) {
    return "samples: " + std::to_string(q.samples().size()) + " readings at every check of " +
           std::to_string(q.steps()) + " steps would pass " +
           std::to_string(static_cast<long>(kMaxSampleValues)) + " values";
  }
  // Groups in order of their numbers (check() takes each as a run of conditions).
  std::stable_sort(out.until_.begin(), out.until_.end(),
                   [](const Condition& a, const Condition& b) { return a.group < b.group; });
  // A stall counts from the request's start.
  for (auto& c : out.until_) {
    if (c.test != mm::STEP_TEST_STALLED) continue;
    c.best = out.read(c.reading, world);
    c.best_at = world.time();
    c.started = std::isfinite(c.best);
  }
  return out;
}

double StepConditions::read(const Reading& r, const World& world) const {
  if (r.what == mm::STEP_READ_SIM_TIME) return world.time();
  if (object_reading(r.what)) {
    const auto state = world.objects().object_state(r.object);
    if (!state.ok()) return kNone;  // gone meanwhile
    const auto& p = state.value.pose.position;
    switch (r.what) {
      case mm::STEP_READ_OBJECT_X: return p.x();
      case mm::STEP_READ_OBJECT_Y: return p.y();
      case mm::STEP_READ_OBJECT_Z: return p.z();
      default: return std::hypot(state.value.angular_velocity.x(), state.value.angular_velocity.y());
    }
  }
  const robot::Readings* latest = readings_ ? readings_(r.robot) : nullptr;
  // Stamped after now: read before a reset or a world load took the time back; not there yet.
  if (!latest || latest->stamp > world.time() + 1e-9) return kNone;
  const auto& o = latest->odometry;
  const auto& g = latest->ground_truth;
  const auto& c = latest->crane;
  switch (r.what) {
    case mm::STEP_READ_ODOMETRY_X: return o ? o->x : kNone;
    case mm::STEP_READ_ODOMETRY_Y: return o ? o->y : kNone;
    case mm::STEP_READ_ODOMETRY_YAW: return o ? o->yaw : kNone;
    case mm::STEP_READ_TRUTH_X: return g ? g->position[0] : kNone;
    case mm::STEP_READ_TRUTH_Y: return g ? g->position[1] : kNone;
    case mm::STEP_READ_TRUTH_Z: return g ? g->position[2] : kNone;
    case mm::STEP_READ_CRANE_SLEW: return c ? c->slew : kNone;
    case mm::STEP_READ_CRANE_LIFT: return c ? c->lift : kNone;
    case mm::STEP_READ_CRANE_HOIST: return c ? c->hoist : kNone;
    case mm::STEP_READ_CRANE_HOLDING: return c ? (c->held_object.empty() ? 0.0 : 1.0) : kNone;
    default: return kNone;
  }
}

void StepConditions::trace(const World& world) {
  // splitmix64's finaliser over the running trace and the new hash: order matters.
  uint64_t z = trace_ ^ (world.state_hash() + 0x9E3779B97F4A7C15ull + (trace_ << 6) + (trace_ >> 2));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  trace_ = z ^ (z >> 31);
}

bool StepConditions::check(const World& world) {
  for (const auto& r : recorded_) samples_.push_back(read(r, world));
  const double now = world.time();
  // A group holds when every one of its conditions holds (a reading not there holds nothing);
  // the conditions are sorted by group, so a group is a run of them. Every condition is tested
  // (a stall keeps its best), the first group that holds ends the request.
  bool group_holds = true;
  for (std::size_t i = 0; i < until_.size(); ++i) {
    Condition& c = until_[i];
    const double v = read(c.reading, world);
    bool holds = false;
    switch (c.test) {
      case mm::STEP_TEST_ABOVE: holds = v > c.value; break;
      case mm::STEP_TEST_BELOW: holds = v < c.value; break;
      case mm::STEP_TEST_NEAR: holds = std::fabs(v - c.value) < c.tolerance; break;
      default:  // STALLED
        if (!c.started && std::isfinite(v)) c.best = v, c.best_at = now, c.started = true;
        if (c.started && v > c.best + c.tolerance) c.best = v, c.best_at = now;
        holds = c.started && now - c.best_at > c.value;
    }
    group_holds = group_holds && holds;
    const bool group_ends = i + 1 == until_.size() || until_[i + 1].group != c.group;
    if (group_ends) {
      if (group_holds && ended_by_ < 0) ended_by_ = c.group;
      group_holds = true;
    }
  }
  return ended_by_ >= 0;
}

}  // namespace macsim
