// World::overlaps(): objects and robots that start inside each other, found by one collision
// pass of ODE's space (its sweep and prune), and the lines that report them.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "world_internal.h"

namespace macsim {

namespace {

/// Who a geom belongs to: an object, a robot or the ground; `rank` orders the names of a pair
/// (objects in list order, then robots, then the ground).
struct Owner {
  const void* key = nullptr;
  std::size_t rank = 0;
  const ObjectSpec* object = nullptr;
  const RobotModel* robot = nullptr;
  bool movable = false;
};

struct PairHash {
  std::size_t operator()(const std::pair<const void*, const void*>& p) const {
    return std::hash<const void*>()(p.first) * 31 + std::hash<const void*>()(p.second);
  }
};

struct Found {
  Owner first, second;
  double depth = 0.0;
};

struct OverlapSearch {
  double tolerance = kOverlapTolerance;
  const detail::GeomTag* ground = nullptr;
  std::size_t ground_rank = 0;
  std::unordered_map<const detail::GeomTag*, std::size_t> object_rank;  // by the object's tag
  std::unordered_map<dBodyID, std::pair<const RobotModel*, std::size_t>> robot_of;
  std::set<std::pair<std::string, std::string>> joined;  // object names joined by a joint
  std::unordered_map<std::pair<const void*, const void*>, std::size_t, PairHash> index;
  std::vector<Found> found;
  bool truncated = false;

  std::optional<Owner> owner(dGeomID g, const detail::GeomTag* tag) const {
    Owner o;
    dBodyID body = dGeomGetBody(g);
    o.movable = body && !dBodyIsKinematic(body);
    if (tag == ground) {
      o.key = tag;
      o.rank = ground_rank;
      return o;
    }
    if (tag->object) {
      const auto rank = object_rank.find(tag);
      if (rank == object_rank.end()) return std::nullopt;
      o.key = tag;
      o.rank = rank->second;
      o.object = tag->object;
      return o;
    }
    const auto robot = robot_of.find(body);
    if (robot == robot_of.end()) return std::nullopt;  // not a part of this world's objects
    o.key = robot->second.first;
    o.rank = robot->second.second;
    o.robot = robot->second.first;
    return o;
  }

  bool joined_on_purpose(const Owner& a, const Owner& b) const {
    if (!a.object || !b.object) return false;
    return joined.count({a.object->name, b.object->name}) > 0 ||
           joined.count({b.object->name, a.object->name}) > 0;
  }
};

/// How far `a` and `b` are inside each other: the deepest contact ODE gives, or how deep the
/// centre of one lies inside the other (ODE misses some concentric overlaps).
double depth_between(dGeomID a, dGeomID b) {
  dContactGeom contacts[detail::kMaxContacts];
  const int n = dCollide(a, b, detail::kMaxContacts, contacts, sizeof(dContactGeom));
  double depth = 0.0;
  for (int i = 0; i < n; ++i) depth = std::max(depth, double(contacts[i].depth));
  if (dGeomGetClass(b) != dPlaneClass) {
    depth = std::max(depth, detail::point_depth(a, dGeomGetPosition(b)));
  }
  if (dGeomGetClass(a) != dPlaneClass) {
    depth = std::max(depth, detail::point_depth(b, dGeomGetPosition(a)));
  }
  return depth;
}

void overlap_callback(void* data, dGeomID a, dGeomID b) {
  auto* q = static_cast<OverlapSearch*>(data);
  const auto* ta = static_cast<const detail::GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const detail::GeomTag*>(dGeomGetData(b));
  // One object, one door-switch structure or one robot never collides with itself.
  if (!ta || !tb || ta->group == tb->group || q->truncated) return;
  const dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;  // joined
  const auto oa = q->owner(a, ta), ob = q->owner(b, tb);
  if (!oa || !ob) return;
  if (!oa->movable && !ob->movable) return;  // nothing here pushes the other away
  if (q->joined_on_purpose(*oa, *ob)) return;
  const bool ground_a = ta == q->ground, ground_b = tb == q->ground;
  if ((ground_a && ob->object && ob->object->kind == ObjectKind::Ramp) ||
      (ground_b && oa->object && oa->object->kind == ObjectKind::Ramp)) {
    return;  // a ramp is a box embedded in the ground
  }
  const double depth = depth_between(a, b);
  if (!(depth > q->tolerance)) return;
  const bool a_first = oa->rank <= ob->rank;
  const Owner& first = a_first ? *oa : *ob;
  const Owner& second = a_first ? *ob : *oa;
  const auto [at, fresh] = q->index.try_emplace({first.key, second.key}, q->found.size());
  if (!fresh) {
    q->found[at->second].depth = std::max(q->found[at->second].depth, depth);
    return;
  }
  if (q->found.size() >= kMaxOverlapPairs) {
    q->index.erase(at);
    q->truncated = true;
    return;
  }
  q->found.push_back({first, second, depth});
}

std::string name_of(const Owner& o) {
  if (o.object) return o.object->name;
  if (o.robot) return o.robot->name();
  return "ground";
}

std::string depth_text(double depth) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f m", depth);
  return text;
}

}  // namespace

OverlapReport World::overlaps(double tolerance) const {
  OverlapSearch search;
  search.tolerance = tolerance;
  search.ground = ground_tag_.get();
  const auto& objects = table_->objects();
  for (std::size_t i = 0; i < objects.size(); ++i) search.object_rank[&objects[i]->tag] = i;
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    for (dBodyID body : robots_[r]->bodies()) {
      search.robot_of[body] = {robots_[r].get(), objects.size() + r};
    }
  }
  search.ground_rank = objects.size() + robots_.size();
  for (const auto& joint : table_->joints()) {
    if (!joint->spec.body2.empty()) search.joined.insert({joint->spec.body1, joint->spec.body2});
  }
  detail::ensure_ode_ready();
  dSpaceCollide(space_, &search, &overlap_callback);

  std::sort(search.found.begin(), search.found.end(), [](const Found& a, const Found& b) {
    if (a.depth != b.depth) return a.depth > b.depth;
    return std::pair(a.first.rank, a.second.rank) < std::pair(b.first.rank, b.second.rank);
  });
  OverlapReport report;
  report.truncated = search.truncated;
  report.pairs.reserve(search.found.size());
  for (const Found& f : search.found) {
    SourceLocation source;
    if (f.first.object) source = f.first.object->source;
    if (f.first.robot) source = f.first.robot->spec().source;
    report.pairs.push_back({name_of(f.first), name_of(f.second), f.depth, source});
  }
  return report;
}

std::vector<std::string> overlap_warnings(const OverlapReport& report, std::size_t max_lines) {
  std::vector<std::string> lines;
  const std::size_t shown = std::min(max_lines, report.pairs.size());
  for (std::size_t i = 0; i < shown; ++i) {
    const Overlap& o = report.pairs[i];
    const std::string where =
        o.source.file.empty() ? "" : o.source.file + ":" + std::to_string(o.source.line) + ": ";
    lines.push_back(where + "warning: '" + o.first + "' and '" + o.second +
                    "' start inside each other, " + depth_text(o.depth) + " deep");
  }
  if (shown < report.pairs.size() || report.truncated) {
    lines.push_back(
        "warning: ... and " + std::string(report.truncated ? "at least " : "") +
        std::to_string(report.pairs.size() - shown) + " more pairs of objects inside each other" +
        (report.truncated ? " (the search stops at " + std::to_string(kMaxOverlapPairs) + " pairs)"
                          : ""));
  }
  return lines;
}

std::string overlap_error(const OverlapReport& report, std::size_t named) {
  const std::size_t count = report.pairs.size();
  std::string text = (report.truncated ? "at least " : "") + std::to_string(count) +
                     (count == 1 ? " pair" : " pairs") + " of objects start inside each other";
  for (std::size_t i = 0; i < std::min(named, count); ++i) {
    const Overlap& o = report.pairs[i];
    text += (i == 0 ? ": '" : "; '") + o.first + "' and '" + o.second + "' " + depth_text(o.depth) +
            " deep";
  }
  if (count > named && named > 0) text += "; ...";
  return text;
}

OverlapReport admit_overlaps(const World& world, bool refuse) {
  OverlapReport report = world.overlaps();
  for (const auto& line : overlap_warnings(report)) log_message(LogLevel::Warning, line);
  if (refuse && !report.empty()) {
    const SourceLocation& at = report.pairs.front().source;
    throw WorldFileError(at.file.empty() ? world.spec().file : at.file, at.line,
                         "refused: " + overlap_error(report));
  }
  return report;
}

}  // namespace macsim

namespace macsim {

namespace {

/// Something that can be moved as a whole on the floor: a free portable object or a robot.
struct Unit {
  std::string name;
  Eigen::Vector3d* position = nullptr;  // in the spec
  SourceLocation source;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // centre of its footprint
  double radius = 0.0;
  bool robot = false;
  bool tangled = false;
  std::string partner;  // one thing it started inside, for the message
  double depth = 0.0;
};

constexpr double kGap = 0.01;                       // m left between parted footprints
constexpr std::size_t kMaxTangled = 2000;           // parting compares every tangled unit with all
constexpr double kGoldenAngle = 2.399963229728653;  // rad

/// The footprint of a robot as built: the circle about its base that holds all its shapes.
double robot_radius(const RobotModel& robot, const Eigen::Vector2d& at) {
  double radius = 0.0;
  for (const ShapeView& s : robot.shapes()) {
    const double half = s.shape == Shape::Box ? 0.5 * s.size.head<2>().norm() : s.size.x();
    radius = std::max(radius, (s.pose.position.head<2>() - at).norm() + half);
  }
  return radius;
}

std::vector<Unit> units_of(WorldSpec& spec, const World& probe) {
  std::set<std::string> jointed;
  for (const auto& j : spec.joints) {
    jointed.insert(j.body1);
    jointed.insert(j.body2);
  }
  std::vector<Unit> units;
  for (auto& o : spec.objects) {
    if (!o.portable || o.frozen || o.kind != ObjectKind::Object || jointed.count(o.name)) continue;
    Unit unit;
    unit.name = o.name;
    unit.position = &o.pose.position;
    unit.source = o.source;
    unit.at = o.pose.position.head<2>();
    unit.radius = footprint_radius(o);
    units.push_back(unit);
  }
  for (auto& r : spec.robots) {
    const RobotModel* built = nullptr;
    for (const auto& robot : probe.robots()) {
      if (robot->name() == r.name) built = robot.get();
    }
    if (!built) continue;
    Unit unit;
    unit.name = r.name;
    unit.position = &r.pose.position;
    unit.source = r.source;
    unit.at = r.pose.position.head<2>();
    unit.radius = robot_radius(*built, unit.at);
    unit.robot = true;
    units.push_back(unit);
  }
  return units;
}

/// Marks the units deeply inside another unit; false if none is.
bool mark_tangled(std::vector<Unit>& units, const OverlapReport& report) {
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < units.size(); ++i) index[units[i].name] = i;
  bool any = false;
  for (const Overlap& o : report.pairs) {
    const auto a = index.find(o.first), b = index.find(o.second);
    if (a == index.end() || b == index.end()) continue;
    Unit& ua = units[a->second];
    Unit& ub = units[b->second];
    if (o.depth <= 0.25 * std::min(ua.radius, ub.radius)) continue;  // the physics' to part
    for (auto [self, other] : {std::pair{&ua, &ub}, std::pair{&ub, &ua}}) {
      if (!self->tangled || o.depth > self->depth) {
        self->partner = other->name;
        self->depth = o.depth;
      }
      self->tangled = true;
    }
    any = true;
  }
  return any;
}

/// Spreads each heap of tangled units of one kind (objects, robots) standing at one point on a
/// sunflower spiral about it.
void spread_heaps(std::vector<Unit>& units) {
  std::vector<std::size_t> heap_of(units.size()), members(units.size(), 0), leaders;
  for (std::size_t i = 0; i < units.size(); ++i) {
    heap_of[i] = i;
    if (!units[i].tangled) continue;
    for (const std::size_t j : leaders) {
      if (units[j].robot == units[i].robot && (units[j].at - units[i].at).norm() < 1e-3) {
        heap_of[i] = j;
        break;
      }
    }
    if (heap_of[i] == i) leaders.push_back(i);
  }
  std::vector<double> widest(units.size(), 0.0);
  for (std::size_t i = 0; i < units.size(); ++i)
    widest[heap_of[i]] = std::max(widest[heap_of[i]], units[i].radius);
  for (std::size_t i = 0; i < units.size(); ++i) {
    const std::size_t heap = heap_of[i];
    if (heap == i) continue;
    const double k = static_cast<double>(++members[heap]);
    const double spacing = (2.0 * widest[heap] + kGap) / 1.5;  // neighbours ~1.77 x apart
    units[i].at = units[heap].at +
                  spacing * std::sqrt(k) *
                      Eigen::Vector2d(std::cos(k * kGoldenAngle), std::sin(k * kGoldenAngle));
  }
}

/// Units filed by square cells on the floor no narrower than two footprints and a gap, so a
/// unit's footprint can meet only those in its cell and the eight around it.
class FloorCells {
 public:
  explicit FloorCells(double cell) : cell_(cell) {}
  void add(std::size_t unit, const Eigen::Vector2d& at) { cells_[key(at, 0, 0)].push_back(unit); }
  /// Calls `visit(unit)` for the units filed in the nine cells about `at`.
  template <class Visit>
  void around(const Eigen::Vector2d& at, Visit visit) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const auto cell = cells_.find(key(at, dx, dy));
        if (cell == cells_.end()) continue;
        for (const std::size_t unit : cell->second) visit(unit);
      }
  }

 private:
  std::uint64_t key(const Eigen::Vector2d& at, int dx, int dy) const {
    const auto x = static_cast<std::int64_t>(std::floor(at.x() / cell_)) + dx;
    const auto y = static_cast<std::int64_t>(std::floor(at.y() / cell_)) + dy;
    return (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint32_t>(y);
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

/// Pushes tangled units apart until no footprints meet: both of a pair alike, except that an
/// object gives way to a robot and a tangled unit to one that is not (which stays). Each round
/// looks only at the units near each tangled one; it stops after 200 rounds if they cannot all
/// be placed (no room among the untangled ones), leaving the rest to the physics.
void push_apart(std::vector<Unit>& units) {
  double widest = 0.0;
  for (const Unit& u : units) widest = std::max(widest, u.radius);
  const double cell = 2.0 * widest + kGap;
  FloorCells untangled(cell);
  std::vector<std::size_t> tangled;
  for (std::size_t i = 0; i < units.size(); ++i) {
    if (units[i].tangled) {
      tangled.push_back(i);
    } else {
      untangled.add(i, units[i].at);
    }
  }
  auto push = [&units](std::size_t i, std::size_t j) {
    Eigen::Vector2d d = units[j].at - units[i].at;
    const double need = units[i].radius + units[j].radius + kGap;
    const double distance = d.norm();
    if (distance >= need) return false;
    if (distance < 1e-9) {
      const double a = kGoldenAngle * static_cast<double>(i + j);
      d = Eigen::Vector2d(std::cos(a), std::sin(a));
    } else {
      d /= distance;
    }
    const double by = need - distance + 1e-6;
    const bool i_stays = units[i].robot && !units[j].robot && units[j].tangled;
    const bool j_stays = !units[j].tangled || (units[j].robot && !units[i].robot);
    if (i_stays) {
      units[j].at += by * d;
    } else if (j_stays) {
      units[i].at -= by * d;
    } else {
      units[i].at -= 0.5 * by * d;
      units[j].at += 0.5 * by * d;
    }
    return true;
  };
  for (int round = 0; round < 200; ++round) {
    FloorCells moving(cell);  // where the tangled ones stand at the round's start
    for (const std::size_t i : tangled) moving.add(i, units[i].at);
    bool pushed = false;
    for (const std::size_t i : tangled) {
      const Eigen::Vector2d at = units[i].at;
      moving.around(at, [&](std::size_t j) {
        if (j > i) pushed = push(i, j) || pushed;  // tangled pairs once
      });
      untangled.around(at, [&](std::size_t j) { pushed = push(i, j) || pushed; });
    }
    if (!pushed) return;  // a round that moved nothing saw every pair where it stands
  }
}

}  // namespace

std::vector<std::string> part_overlaps(WorldSpec& spec, std::size_t max_lines) {
  std::vector<std::string> lines;
  std::vector<Unit> moved;                // as last placed, in the order first moved
  std::vector<Eigen::Vector2d> first_at;  // where each of them stood in the file
  for (int pass = 0; pass < 3; ++pass) {  // what a truncated report left out comes next pass
    const World probe(spec);
    const OverlapReport report = probe.overlaps();
    if (report.empty()) break;
    std::vector<Unit> units = units_of(spec, probe);
    if (!mark_tangled(units, report)) break;
    const auto tangled = static_cast<std::size_t>(
        std::count_if(units.begin(), units.end(), [](const Unit& u) { return u.tangled; }));
    if (tangled > kMaxTangled) {
      lines.push_back("warning: " + std::to_string(tangled) +
                      " objects and robots start deeply inside each other; more than " +
                      std::to_string(kMaxTangled) + " are left for the physics to part");
      break;
    }
    const std::vector<Unit> before = units;
    spread_heaps(units);
    push_apart(units);
    for (std::size_t i = 0; i < units.size(); ++i) {
      if (!units[i].tangled) continue;
      units[i].position->head<2>() += units[i].at - before[i].at;
      auto known = std::find_if(moved.begin(), moved.end(),
                                [&](const Unit& u) { return u.name == units[i].name; });
      if (known == moved.end()) {
        moved.push_back(units[i]);
        first_at.push_back(before[i].at);
      } else {
        known->at = units[i].at;
      }
    }
  }
  for (std::size_t i = moved.size(); i-- > 0;) {  // the centre of a heap may stay put
    if ((moved[i].at - first_at[i]).norm() < 5e-4) {
      moved.erase(moved.begin() + static_cast<long>(i));
      first_at.erase(first_at.begin() + static_cast<long>(i));
    }
  }
  const std::size_t shown = std::min(max_lines, moved.size());
  for (std::size_t i = 0; i < shown; ++i) {
    const Unit& unit = moved[i];
    const std::string where =
        unit.source.file.empty() ? ""
                                 : unit.source.file + ":" + std::to_string(unit.source.line) + ": ";
    char depth[48], distance[48];
    std::snprintf(depth, sizeof depth, "%.3f m deep inside '", unit.depth);
    std::snprintf(distance, sizeof distance, "': moved %.3f m apart",
                  (unit.at - first_at[i]).norm());
    lines.push_back(where + "warning: '" + unit.name + "' started " + depth + unit.partner +
                    distance);
  }
  if (shown < moved.size()) {
    lines.push_back("warning: ... and " + std::to_string(moved.size() - shown) +
                    " more objects or robots moved apart");
  }
  return lines;
}

}  // namespace macsim
