// World::overlaps(): objects and robots that start inside each other, found by one collision
// pass of ODE's space (its sweep and prune), and the lines that report them.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "world_internal.h"

namespace macsim {

namespace {

constexpr int kMaxContacts = 8;

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
  dContactGeom contacts[kMaxContacts];
  const int n = dCollide(a, b, kMaxContacts, contacts, sizeof(dContactGeom));
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
  for (std::size_t i = 0; i < objects_.size(); ++i) search.object_rank[&objects_[i]->tag] = i;
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    for (dBodyID body : robots_[r]->bodies()) {
      search.robot_of[body] = {robots_[r].get(), objects_.size() + r};
    }
  }
  search.ground_rank = objects_.size() + robots_.size();
  for (const auto& joint : joints_) {
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
    lines.push_back("warning: ... and " + std::string(report.truncated ? "at least " : "") +
                    std::to_string(report.pairs.size() - shown) +
                    " more pairs of objects inside each other" +
                    (report.truncated ? " (the search stops at " +
                                            std::to_string(kMaxOverlapPairs) + " pairs)"
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
    text += (i == 0 ? ": '" : "; '") + o.first + "' and '" + o.second + "' " +
            depth_text(o.depth) + " deep";
  }
  if (count > named && named > 0) text += "; ...";
  return text;
}

OverlapReport admit_overlaps(const World& world, bool refuse,
                             const std::function<void(const std::string&)>& warn) {
  OverlapReport report = world.overlaps();
  if (warn) {
    for (const auto& line : overlap_warnings(report)) warn(line);
  }
  if (refuse && !report.empty()) {
    const SourceLocation& at = report.pairs.front().source;
    throw WorldFileError(at.file.empty() ? world.spec().file : at.file, at.line,
                         "refused: " + overlap_error(report));
  }
  return report;
}

}  // namespace macsim
