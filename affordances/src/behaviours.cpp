#include "macsim/affordances/behaviours.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "macsim/affordances/laser_odometry.h"
#include "macsim/affordances/perception.h"
#include "macsim/affordances/traverse.h"
#include "macsim/images/image_files.h"

namespace macsim::affordances {

namespace {

constexpr double kStandoff = 0.9;        // m from an object to look at it closely
constexpr double kPickupRadius = 0.485;  // m from the crane's pivot to the object
constexpr double kRotunitSpeed = M_PI;   // rad/s: a cloud every 2 s
constexpr double kParkSlew = M_PI / 2, kParkLift = 0.6;
constexpr double kRobotRadius = 0.33;  // m: the chassis and wheels, from base_link
constexpr double kHalfWidth = 0.25;    // m: half the corridor the robot drives in
constexpr double kCanTop = 0.135;      // m: where the magnet meets a can
constexpr double kPlatformTop = 0.07;  // m: the switch's platform above the floor
constexpr double kBesideOnPlatform = 0.04;  // m: things put down from the platform's middle, to each side
constexpr double kBumper = 0.21;             // m: base_link to the front bumper
constexpr double kBoxHalf = 0.1;             // m: half a pushable box's side
constexpr double kPushStandoff = 1.0;        // m: from a box's middle to stand behind it
constexpr double kStaleSwitch = 0.6;         // m: a switch seen this far from its estimate replaces it
constexpr double kDoorWatch = 1.5;           // m: in front of a door seen from afar, where the wall is watched
constexpr double kOnPlatformSeen = 0.45;     // m: a sighting this close to the switch of what was put there is that
constexpr double kSameThing = 0.3;           // m: a sighting this close to a thing of its colour and kind is that thing
constexpr double kPushLeg = 0.9;             // m: the longest push before the box is looked at again
constexpr int kPushLegs = 6;                 // pushes per push behaviour at most
constexpr double kLastPush = 0.25;           // m: the longest push once the box is close to the plate
constexpr double kDoorSettle = 3.0;          // s: a door the robot's weight opened has closed again after this
constexpr double kPlateHidden = 0.5;         // m: a box closer than this to the plate hides part of it
constexpr double kOnSwitch = 0.18;           // m: a box's middle this close to the plate's is on it (0.5 m wide)
constexpr double kTrialSlack = 0.1;          // m: a thing's near side this close to a trial's is judged from there
constexpr int kMostJudged = 6;               // things judged by the traverse model per travel at most
constexpr double kWayBorder = 1.5;           // m: the floor plan reaches this far beyond here and the goal
constexpr double kWaypoint = 0.4;            // m: between the waypoints of a way round
constexpr double kSlipSaid = 0.1;            // m: a laser odometry correction this large is said
constexpr double kStuck = 0.4;               // m: a slip this large was the tracks spinning against something
constexpr double kStuckAhead = 0.35;         // m: from base_link to what it stood against
constexpr double kStuckRadius = 0.15;        // m: around that, what blocks from then on
constexpr double kSwitchMargin = 0.15;       // m: kept off a raised platform's yellow: its base, and the slip
constexpr double kPlateWidth = 0.3;          // m: a switch platform whose width was not measured
constexpr double kMovedSinceCloud = 0.05;    // m: a look around from further than this from the last cloud takes one

std::string fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* format, ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  return text;
}

/// A thing first seen at `at` (odometry frame), not yet counted as a sighting.
SeenThing seen_thing(const std::string& name, const std::string& colour, Kind kind, const Pose2& at) {
  SeenThing t;
  t.name = name;
  t.colour = colour;
  t.kind = kind;
  t.x = at.x;
  t.y = at.y;
  return t;
}

}  // namespace

bool flush_switch(const Scene& scene) {
  if (!scene.switch_platform) return false;
  const auto width = scene.switch_platform->features.find("width_m");
  return width != scene.switch_platform->features.end() && width->second > kFlushPlateWidth;
}

double switch_keep_off(const Scene& scene) {
  if (!scene.switch_platform || flush_switch(scene)) return 0;
  const auto width = scene.switch_platform->features.find("width_m");
  return (width != scene.switch_platform->features.end() ? width->second : kPlateWidth) / 2 + kSwitchMargin;
}

const std::vector<std::string>& thing_features() {
  static const std::vector<std::string> names{"hue", "width_m"};
  return names;
}

std::string debug_images_problem(const std::string& dir) {
  if (dir.empty() || std::filesystem::is_directory(dir)) return {};
  return "--debug-images " + dir + " is no folder";
}

std::string robot_place(const Scene& scene) {
  // At a thing it lost sight of, the robot is at a place of its own again: the start of a plan.
  const bool at_lost = std::any_of(scene.things.begin(), scene.things.end(),
                                   [&](const SeenThing& t) { return t.lost && t.name == scene.at; });
  return at_lost ? "start" : scene.at;
}

Behaviours::Behaviours(macsim::dds::Participant& participant, const BehaviourOptions& options)
    : RobotLoop(participant, options.loop), options_(options) {
  if (options.pictures) pictures_ = std::make_unique<macsim::client::PictureClient>(participant);
}

std::optional<std::string> Behaviours::overview_picture(const std::string& name) {
  if (!pictures_) return std::nullopt;
  const auto reply = pictures_->take(name, "Chase", std::chrono::seconds(3));
  if (!reply || reply->code() != macsim_msgs::msg::dds_::ERR_OK) {
    say(name, reply ? "no picture: " + reply->message()
                    : "no picture: nothing serves pictures here (a real robot has no overview camera)");
    pictures_.reset();
    return std::nullopt;
  }
  say(name, "picture " + reply->file());
  return reply->file();
}

Behaviours::~Behaviours() = default;

void Behaviours::say(const std::string& stage, const std::string& text) {
  if (!options_.verbose) return;
  std::printf("%s: [t=%6.1f s] %s: %s\n", options_.program.c_str(), elapsed(), stage.c_str(),
              text.c_str());
  std::fflush(stdout);
}

void Behaviours::emit(const std::string& event) {
  if (on_event) on_event(event);
}

SeenThing* Behaviours::thing(const std::string& name) {
  const auto it = std::find_if(scene_.things.begin(), scene_.things.end(),
                               [&](const SeenThing& t) { return t.name == name; });
  return it == scene_.things.end() ? nullptr : &*it;
}

BehaviourReport Behaviours::report(const std::string& behaviour, const std::string& argument) const {
  BehaviourReport r;
  r.behaviour = behaviour;
  r.argument = argument;
  r.before = scene_;
  r.before.robot = pose_;
  return r;
}

BehaviourReport& Behaviours::finish(BehaviourReport& r, Setback setback, const std::string& reason) {
  scene_.robot = pose_;
  r.after = scene_;
  r.setback = setback;
  r.reason = reason;
  return r;
}

void Behaviours::start() {
  say("start", "looking for robot '" + options_.loop.robot + "'" + (simulation_ ? " (lock-step)" : ""));
  connect();
  start_ = now_;
  say("start", "found it; parking the crane, starting the laser's rotating unit");
  rotunit_ = kRotunitSpeed;
  park_crane();
  map_here();
  scene_.robot = pose_;
}

void Behaviours::halt() {
  linear_ = angular_ = 0;
  rotunit_ = 0;
  tick();
}

// ---- motion -------------------------------------------------------------------------------

std::string Behaviours::lower_onto(double lift, double height, bool until_held) {
  // Quickly to a few centimetres above, then slowly (2 cm/s): a magnet that grips at speed
  // jerks the load hard enough to lose it.
  const double tip = geometry_.base_height + geometry_.pivot_z + geometry_.boom_length * std::sin(lift);
  const double contact = (tip - geometry_.magnet_below_tip - height) / std::cos(lift);
  crane_to(slew_, lift, std::max(0.0, contact - 0.04), 3.0);
  double still_since = now_;
  const double give_up = now_ + 8.0;
  while (now_ < give_up) {
    hoist_ = std::min(geometry_.max_hoist, hoist_ + 0.001);
    tick();
    const auto s = crane_.state();
    if (!s) continue;
    if (until_held && !s->held_object().empty()) {
      hoist_ = s->hoist();
      return s->held_object();
    }
    // Resting on something (held or not), or at the end of the hoist.
    if (hoist_ - s->hoist() < 0.006) {
      still_since = now_;
    } else if (now_ - still_since > 0.3) {
      break;
    }
  }
  hoist_ = crane_.state() ? crane_.state()->hoist() : hoist_;
  return {};
}

void Behaviours::park_crane() {
  crane_to(crane_.state() ? crane_.state()->slew() : 0.0, kParkLift, 0.0, 3.0);
  crane_to(kParkSlew, kParkLift, 0.0);
}

// ---- sensing ------------------------------------------------------------------------------

void Behaviours::for_frames(int frames, const std::function<void(const macsim::client::StereoFrame&)>& use) {
  linear_ = angular_ = 0;
  wait(0.3);  // let the chassis come to rest
  looking_ = true;
  struct Done {
    bool& looking;
    ~Done() { looking = false; }
  } done{looking_};
  double after = now_ - 1e-6;
  for (int taken = 0, tries = 0; taken < frames && tries < 40; ++tries) {
    if (auto frame = cameras_.latest(after)) {
      after = frame->stamp;
      ++taken;
      use(*frame);
      continue;
    }
    tick();
  }
}

std::optional<Point> Behaviours::look_at_flush_plate() {
  int found = 0;
  double sx = 0, sy = 0;
  for_frames(3, [&](const macsim::client::StereoFrame& frame) {
    if (const auto plate = find_flush_plate(frame, geometry_)) {
      const Pose2 at = to_odom(plate->x, plate->y);
      sx += at.x;
      sy += at.y;
      ++found;
    }
  });
  return found ? std::optional<Point>(Point{sx / found, sy / found}) : std::nullopt;
}

std::vector<std::pair<Sighting, Pose2>> Behaviours::look(int frames) {
  std::vector<std::pair<Sighting, Pose2>> seen;
  for_frames(frames, [&](const macsim::client::StereoFrame& frame) {
    auto sightings = find_objects(frame, geometry_);
    if (frame.focal > 0) view_half_angle_ = std::atan2(frame.left.cols / 2.0, frame.focal);
    // Each can as the trials perceive an object's blob: its features, and what the lift
    // model says of it.
    for (auto& s : sightings) {
      if (s.kind == Kind::Switch) continue;
      const cv::Rect around(s.box.x - 4, s.box.y - 4, s.box.width + 8, s.box.height + 8);
      Percept p;
      perceive_image(frame, p, around);
      if (!p.seen) continue;
      const auto all = named_features(p, Affordance::Lift);
      for (const auto& name : thing_features()) s.features[name] = all.at(name);
      if (options_.lift_model && s.kind == Kind::Can) {
        try {
          const auto said = options_.lift_model->predict(all);
          s.liftable = said.label == "liftable" ? said.confidence : 1.0 - said.confidence;
        } catch (const ModelError& e) {
          say("look", std::string("the lift model could not judge a can: ") + e.what());
        }
      }
    }
    for (const auto& s : sightings) seen.emplace_back(s, to_odom(s.x, s.y));
    if (!options_.debug_images.empty()) {
      images::write_image(fmt("%s/look_%03d.png", options_.debug_images.c_str(), debug_count_++),
                  draw_sightings(frame.left, sightings));
    }
  });
  return seen;
}

void Behaviours::forget_unseen(const std::vector<std::pair<Sighting, Pose2>>& seen) {
  constexpr double kNear = 1.0, kFar = 3.0, kSame = 0.45;  // m
  for (auto& t : scene_.things) {
    if (t.lost || t.name == scene_.holding ||
        std::find(scene_.on_switch.begin(), scene_.on_switch.end(), t.name) != scene_.on_switch.end())
      continue;
    const double range = std::hypot(t.x - pose_.x, t.y - pose_.y);
    const double bearing = std::remainder(std::atan2(t.y - pose_.y, t.x - pose_.x) - pose_.yaw, 2 * M_PI);
    if (range < kNear || range > kFar || std::fabs(bearing) > 0.7 * view_half_angle_) continue;
    const bool there = std::any_of(seen.begin(), seen.end(), [&](const auto& s) {
      return s.first.kind == t.kind && s.first.colour == t.colour && std::hypot(s.second.x - t.x, s.second.y - t.y) < kSame;
    });
    if (!there) {
      t.lost = true;
      t.outcome = "not seen again where it was";
    }
  }
}

void Behaviours::record(const std::vector<std::pair<Sighting, Pose2>>& sightings) {
  for (const auto& [s, at] : sightings) {
    if (s.range > 3.5) continue;  // too far to place well
    if (s.kind == Kind::Switch) {
      if (!scene_.switch_platform) scene_.switch_platform = seen_thing("switch", "yellow", Kind::Switch, at);
      auto& w = *scene_.switch_platform;
      // Far from where it was: the odometry moved on (the tracks slipped); this look is what counts.
      if (w.seen > 0 && std::hypot(w.x - at.x, w.y - at.y) > kStaleSwitch) w.seen = 0;
      w.x = (w.x * w.seen + at.x) / (w.seen + 1);
      w.y = (w.y * w.seen + at.y) / (w.seen + 1);
      w.above_floor = (w.above_floor * w.seen + s.above_floor) / (w.seen + 1);
      w.features["width_m"] = (w.features["width_m"] * w.seen + s.width) / (w.seen + 1);
      ++w.seen;
      continue;
    }
    // On the switch's platform (or seen off it by as much as a look from across the room may
    // be): what was put there.
    if (scene_.switch_platform &&
        std::hypot(at.x - scene_.switch_platform->x, at.y - scene_.switch_platform->y) < kOnPlatformSeen &&
        std::any_of(scene_.on_switch.begin(), scene_.on_switch.end(), [&](const std::string& name) {
          const SeenThing* put = thing(name);
          return put && put->colour == s.colour && put->kind == s.kind;
        }))
      continue;
    auto same = std::find_if(scene_.things.begin(), scene_.things.end(), [&](const SeenThing& c) {
      return c.colour == s.colour && c.kind == s.kind && std::hypot(c.x - at.x, c.y - at.y) < kSameThing;
    });
    if (same == scene_.things.end()) {
      const auto of_colour = std::count_if(scene_.things.begin(), scene_.things.end(),
                                           [&](const SeenThing& c) { return c.colour == s.colour; });
      scene_.things.push_back(seen_thing(s.colour + "_" + std::to_string(of_colour + 1), s.colour, s.kind, at));
      same = scene_.things.end() - 1;
    } else if (same->tried) {
      continue;
    }
    same->x = (same->x * same->seen + at.x) / (same->seen + 1);
    same->y = (same->y * same->seen + at.y) / (same->seen + 1);
    ++same->seen;
    same->lost = false;
    if (!s.features.empty()) same->features = s.features;
    if (s.liftable >= 0) {
      same->liftable = (same->liftable * same->judged + s.liftable) / (same->judged + 1);
      ++same->judged;
    }
  }
}

macsim::client::Cloud Behaviours::located_cloud() {
  const auto cloud = take_cloud();
  auto still = static_structure(cloud, pose_);
  std::optional<std::array<double, 2>> shift;
  if (!static_map_.points().empty()) {
    // Its tracks may have slipped since the last cloud by any part of what the wheels made, up
    // to all of it (stuck): where it would stand had they slipped by each fifth, and a hand to
    // either side.
    std::vector<std::array<double, 2>> guesses;
    const double bx = cloud_pose_.x - pose_.x, by = cloud_pose_.y - pose_.y;
    const double made = std::hypot(bx, by);
    if (made > 0.05) {
      for (int fifth = 1; fifth <= 5; ++fifth)
        for (double side : {0.0, -0.15, 0.15})
          guesses.push_back({fifth * bx / 5 - side * by / made, fifth * by / 5 + side * bx / made});
    }
    shift = align(static_map_.points(), still, guesses);
  }
  if (shift) {
    pose_.x += (*shift)[0];
    pose_.y += (*shift)[1];
    const double slip = std::hypot((*shift)[0], (*shift)[1]);
    if (slip > kSlipSaid)
      say(stage_, fmt("the laser puts it %.2f,%.2f m off where the wheels say (they slipped)",
                      (*shift)[0], (*shift)[1]));
    if (slip > kStuck && !pushing_) {
      // Its tracks spun against what stands before it: that blocks from now on, whatever the
      // traverse model said of it.
      const Point against{pose_.x + kStuckAhead * std::cos(pose_.yaw),
                          pose_.y + kStuckAhead * std::sin(pose_.yaw)};
      obstacles_.block(against, kStuckRadius);
      say(stage_, fmt("stuck against something at %.2f,%.2f: it blocks from now on", against.x, against.y));
    }
    still = static_structure(cloud, pose_);
  }
  // The first cloud makes the map; a cloud laid onto it adds what it saw anew.
  if (shift || static_map_.points().empty()) static_map_.add(still);
  cloud_pose_ = pose_;
  return cloud;
}

void Behaviours::map_here() {
  const auto cloud = located_cloud();
  obstacles_.add(cloud, geometry_, pose_.x, pose_.y, pose_.yaw);
  keep_off_the_switch();
}

bool Behaviours::on_raised_switch(Point at) const {
  const double radius = switch_keep_off(scene_);
  return radius > 0 && std::hypot(at.x - scene_.switch_platform->x, at.y - scene_.switch_platform->y) <= radius;
}

void Behaviours::keep_off_the_switch() {
  // A raised platform lies below what the laser takes for an obstacle.
  if (const double radius = switch_keep_off(scene_); radius > 0)
    obstacles_.block({scene_.switch_platform->x, scene_.switch_platform->y}, radius);
}

Point Behaviours::approach_point(Point target, double standoff, double reach) const {
  const double direct = std::atan2(target.y - pose_.y, target.x - pose_.x);
  for (int k = 0; k < 24; ++k) {
    // 0, +15, -15, +30, -30, ... degrees off the direct way in
    const double off = (k + 1) / 2 * (k % 2 ? 1 : -1) * M_PI / 12;
    const double a = direct + off, ux = std::cos(a), uy = std::sin(a);
    const Point stand{target.x - standoff * ux, target.y - standoff * uy};
    const Point near{target.x - reach * ux, target.y - reach * uy};
    if (obstacles_.clearance(stand, kRobotRadius) >= kRobotRadius &&
        obstacles_.free(stand, near, kHalfWidth, target, 0.15)) {
      return stand;
    }
  }
  const double d = std::hypot(target.x - pose_.x, target.y - pose_.y);
  return {target.x - standoff * (target.x - pose_.x) / d, target.y - standoff * (target.y - pose_.y) / d};
}

std::optional<Point> Behaviours::detour(Point goal) const {
  const Point here{pose_.x, pose_.y};
  const double dx = goal.x - here.x, dy = goal.y - here.y, d = std::max(std::hypot(dx, dy), 1e-9);
  for (double side : {0.5, -0.5, 0.8, -0.8, 1.1, -1.1, 1.4, -1.4}) {
    for (double along : {0.5, 0.25, 0.75}) {
      const Point via{here.x + along * dx - side * dy / d, here.y + along * dy + side * dx / d};
      if (obstacles_.clearance(via, kRobotRadius) >= kRobotRadius &&
          obstacles_.free(here, via, kHalfWidth) && obstacles_.free(via, goal, kHalfWidth))
        return via;
    }
  }
  return std::nullopt;
}

bool Behaviours::judge_in_way(Point goal) {
  const auto block = obstacles_.first_blocked({pose_.x, pose_.y}, goal, kHalfWidth);
  if (!block || judged_.count(cell_of({block->x, block->y}))) return false;
  if (on_raised_switch(*block)) return false;  // kept off, whatever stands there
  // The thing of a cloud that holds the blocked cell (or the one nearest `at`, its middle seen
  // from further off).
  const auto thing_at = [](const std::vector<Thing>& things, Point2 at, double within) {
    const Thing* found = nullptr;
    for (const auto& t : things)
      for (const auto& c : t.cells) {
        const double d = std::hypot(c[0] - at[0], c[1] - at[1]);
        if (d < within) within = d, found = &t;
      }
    return found;
  };
  auto cloud = located_cloud();  // all round the robot
  auto things = things_in(cloud, pose_);
  const Thing* thing = thing_at(things, {block->x, block->y}, 0.15);
  // Stand before it as a traverse trial stood: facing its middle, its near side kTrialNear ahead.
  if (thing && thing->height != Height::Towering) {
    const double near = near_side(cloud, pose_, *thing);
    if (std::fabs(near - kTrialNear) > kTrialSlack) {
      const Point2 centre = thing->centre;
      turn_to(std::atan2(centre[1] - pose_.y, centre[0] - pose_.x));
      drive_straight(near - kTrialNear, 0.15);
      turn_to(std::atan2(centre[1] - pose_.y, centre[0] - pose_.x));
      cloud = located_cloud();
      things = things_in(cloud, pose_);
      thing = thing_at(things, centre, 0.3);
    }
  }
  if (!thing) {  // gone (a ball rolled off), or where the map has it the odometry drifted
    obstacles_.clear(*block, 0.15);
    say(stage_, fmt("nothing stands at %.2f,%.2f now", block->x, block->y));
    return true;
  }
  const double p = thing->height == Height::Towering
                       ? 0.0
                       : p_traversable(*options_.traverse_model, cloud, pose_, things, *thing);
  // What the cameras took for a thing of the scene is kept clear of, whatever the model says.
  bool known = false;
  const auto near_known = [&](const SeenThing& t) {
    for (const auto& c : thing->cells) known |= std::hypot(c[0] - t.x, c[1] - t.y) < kSameThing;
  };
  for (const auto& t : scene_.things) near_known(t);
  if (scene_.switch_platform) near_known(*scene_.switch_platform);
  const bool over = p >= 0.5 && !known;
  for (const auto& c : thing->cells) {
    judged_.insert(cell_of(c));
    if (over) obstacles_.let_pass({c[0], c[1]});
  }
  judged_.insert(cell_of({block->x, block->y}));
  if (over) obstacles_.let_pass(*block);
  say(stage_, fmt("judged what stands at %.2f,%.2f (%.2f m across): P(traversable) %.2f, %s",
                  thing->centre[0], thing->centre[1], thing->across, p,
                  over ? "over it" : known ? "a thing of the scene: around it" : "around it"));
  return true;
}

std::vector<Point> Behaviours::way_round(Point goal) const {
  const Point here{pose_.x, pose_.y};
  FloorPlan floor({here.x, here.y}, {goal.x, goal.y}, kWayBorder);
  for (const Point& c : obstacles_.obstacles_near(here, goal, kWayBorder + kHalfWidth))
    floor.block({c.x, c.y}, kHalfWidth);
  const auto cells = floor.path(kRobotRadius);  // it may leave what it stands against
  // Waypoints every kWaypoint m along the cells' way, and its end.
  std::vector<Point> way;
  double since = 0;
  for (std::size_t k = 1; k < cells.size(); ++k) {
    since += std::hypot(cells[k][0] - cells[k - 1][0], cells[k][1] - cells[k - 1][1]);
    if (since >= kWaypoint || k + 1 == cells.size()) {
      way.push_back({cells[k][0], cells[k][1]});
      since = 0;
    }
  }
  return way;
}

void Behaviours::travel_to(Point goal, double tolerance) {
  for (int judged = 0;; ++judged) {
    if (obstacles_.free({pose_.x, pose_.y}, goal, kHalfWidth)) break;
    if (const auto via = detour(goal)) {
      drive_to(via->x, via->y, 0.08);
      break;
    }
    if (options_.traverse_model && judged < kMostJudged && judge_in_way(goal)) continue;
    // No way with one turn in it: the shortest over the floor the laser saw free.
    if (const auto way = way_round(goal); !way.empty()) {
      say(stage_, fmt("a way of %zu legs round what the laser sees", way.size()));
      for (const Point& p : way) drive_to(p.x, p.y, 0.1);
      break;
    }
    say(stage_, fmt("no way to %.2f,%.2f judged passable: driving on", goal.x, goal.y));
    break;
  }
  drive_to(goal.x, goal.y, tolerance);
}

std::optional<Point> Behaviours::find_again(const SeenThing& target, Kind kind, double radius, Sighting* last) {
  auto matches = [&](const std::vector<std::pair<Sighting, Pose2>>& seen) {
    int found = 0;
    double sx = 0, sy = 0;
    for (const auto& [s, at] : seen) {
      if (s.kind == kind && (kind == Kind::Switch || s.colour == target.colour) &&
          std::hypot(at.x - target.x, at.y - target.y) < radius) {
        sx += at.x;
        sy += at.y;
        ++found;
        if (last) *last = s;
      }
    }
    return found ? std::optional<Point>(Point{sx / found, sy / found}) : std::nullopt;
  };
  if (auto at = matches(look(3))) return at;
  // Not where expected: the odometry drifted. Look a little to each side, then from further
  // back (closer than about 0.8 m the floor in front is out of the cameras' view; where the
  // tracks slipped on the way in, it may stand closer still, so it backs off twice).
  const double ahead = pose_.yaw;
  for (double off : {0.45, -0.45}) {
    turn_to(ahead + off);
    if (auto at = matches(look(2))) return at;
  }
  turn_to(ahead);
  for (int back = 0; back < 2; ++back) {
    drive_straight(-0.4, 0.15);
    if (auto at = matches(look(3))) return at;
  }
  return std::nullopt;
}

bool Behaviours::close_in(SeenThing& target, Kind kind) {
  const double reach = geometry_.pivot_x + kPickupRadius;
  for (int attempt = 0; attempt < 3; ++attempt) {
    travel_to(approach_point({target.x, target.y}, kStandoff, reach), 0.05);
    turn_to(std::atan2(target.y - pose_.y, target.x - pose_.x));
    if (attempt == 0) map_here();
    const auto at = find_again(target, kind);
    if (!at) return false;
    target.x = at->x;
    target.y = at->y;
    const double distance = std::hypot(target.x - pose_.x, target.y - pose_.y);
    if (std::fabs(distance - kStandoff) < 0.25) break;  // else walk up to it again
  }
  turn_to(std::atan2(target.y - pose_.y, target.x - pose_.x));
  drive_straight(std::hypot(target.x - pose_.x, target.y - pose_.y) - reach, 0.15);
  return true;
}

// ---- behaviours ---------------------------------------------------------------------------

BehaviourReport Behaviours::look_around(bool until_switch) {
  BehaviourReport r = report("look_around", "");
  // Where it looks from by the laser first: what it sees is placed by its pose, which the tracks'
  // slip since the last cloud has put off.
  if (std::hypot(pose_.x - cloud_pose_.x, pose_.y - cloud_pose_.y) > kMovedSinceCloud) map_here();
  looked_from_.push_back({pose_.x, pose_.y});
  const double start_yaw = pose_.yaw;
  for (int k = 0; k < 9; ++k) {
    if (k > 0) turn_to(start_yaw + k * 2 * M_PI / 9);
    const auto seen = look(1);
    forget_unseen(seen);
    record(seen);
    if (until_switch && scene_.switch_platform) break;
  }
  std::ostringstream what;
  for (const Kind kind : {Kind::Can, Kind::Box}) {
    const auto count = std::count_if(scene_.things.begin(), scene_.things.end(),
                                     [&](const SeenThing& c) { return c.kind == kind; });
    if (kind == Kind::Box && count == 0) continue;
    what << (kind == Kind::Can ? "" : "; ") << count << (kind == Kind::Can ? " can candidate(s)" : " box(es)");
    for (const auto& c : scene_.things) {
      if (c.kind == kind)
        what << fmt(" [%s at %.2f,%.2f%s%s]", c.colour.c_str(), c.x, c.y, c.tried ? ", tried" : "",
                    c.lost ? ", lost" : "");
    }
  }
  keep_off_the_switch();
  if (scene_.switch_platform)
    what << fmt("; the switch at %.2f,%.2f (%.2f m wide)", scene_.switch_platform->x, scene_.switch_platform->y,
                scene_.switch_platform->features["width_m"]);
  say(stage_, "looked around: " + what.str());
  return finish(r);
}

BehaviourReport Behaviours::look_from_elsewhere() {
  BehaviourReport r = report("look_around", "elsewhere");
  map_here();
  const Point here{pose_.x, pose_.y};
  std::optional<Point> best;
  double furthest = 0;  // m from every place looked from
  for (int k = 0; k < 16; ++k) {
    const double a = k * M_PI / 8;
    for (const double d : {2.0, 1.5, 1.0, 0.6}) {  // the longest free way in this direction
      const Point to{here.x + d * std::cos(a), here.y + d * std::sin(a)};
      // (What lies within the robot's own footprint is not in its way: it stands there.)
      if (obstacles_.clearance(to, kRobotRadius + 0.05) < kRobotRadius + 0.05 ||
          !obstacles_.free(here, to, kHalfWidth, here, kRobotRadius))
        continue;
      double apart = 1e9;
      for (const Point& q : looked_from_) apart = std::min(apart, std::hypot(to.x - q.x, to.y - q.y));
      if (apart > furthest) {
        furthest = apart;
        best = to;
      }
      break;
    }
  }
  if (best) {
    say(stage_, fmt("looking around from elsewhere: %.2f,%.2f", best->x, best->y));
    drive_to(best->x, best->y, 0.1);
  } else {
    say(stage_, "the laser sees no free floor to look from: looking around from here");
  }
  look_around(false);
  return finish(r);
}

BehaviourReport Behaviours::go_to(const std::string& name) {
  BehaviourReport r = report("go_to", name);
  SeenThing* target = thing(name);
  if (!target) return finish(r, Setback::NotSeen, name + " was never seen");
  const std::string what = "the " + target->colour + (target->kind == Kind::Box ? " box" : " can");
  say(stage_, fmt("going for %s at %.2f,%.2f (odometry frame)", what.c_str(), target->x, target->y));
  // Stand off where the way in is free, look again from close by, drive in to the crane's reach.
  if (!close_in(*target, target->kind)) {
    target->outcome = "not seen again";
    target->lost = true;
    say(stage_, what + " is not where it was seen; next candidate");
    return finish(r, Setback::NotSeen, what + " is not where it was seen");
  }
  scene_.at = name;
  return finish(r);
}

BehaviourReport Behaviours::lift(const std::string& name) {
  BehaviourReport r = report("lift", name);
  SeenThing* can = thing(name);
  if (!can) return finish(r, Setback::NotSeen, name + " was never seen");
  // Over it with the magnet, then down until the magnet holds it or rests on it.
  ++lift_attempts_;
  can->tried = true;
  const Pose2 b = to_base(can->x, can->y);
  const double dx = b.x - geometry_.pivot_x, dy = b.y;
  const double slew = std::atan2(dy, dx);
  const double radius = std::clamp(std::hypot(dx, dy) / geometry_.boom_length, 0.0, 1.0);
  const double lift = std::clamp(-std::acos(radius), -0.24, 0.36);
  say(stage_, fmt("can at %.3f m ahead, %.3f m left: slew %.2f rad, lift %.2f rad, magnet on, "
                  "lowering",
                  b.x, b.y, slew, lift));
  crane_to(slew, kParkLift, 0.0);
  crane_to(slew, lift, 0.0);
  magnet_ = true;
  const std::string held = lower_onto(lift, kCanTop, true);
  if (held.empty()) {
    magnet_ = false;
    crane_to(slew, lift, 0.0);
    park_crane();
    can->outcome = "the magnet does not hold it (not magnetizable)";
    say(stage_, "the magnet does not hold the " + can->colour + " can: not magnetizable? "
                "Remembered; next candidate");
    return finish(r, Setback::NotHeld, can->outcome);
  }
  // Up: the load came up if the hoist could pull it in.
  const auto at_grip = crane_.state();
  crane_to(slew, lift, 0.0, 3.0);
  crane_to(slew, kParkLift, 0.0, 3.0);
  const auto s = crane_.state();
  if (!s || s->held_object().empty() || s->hoist() > 0.03) {
    const double hoist = s ? s->hoist() : 0;
    magnet_ = false;
    crane_to(slew, lift_, 0.0, 2.0);
    park_crane();
    can->outcome = fmt("too heavy (the hoist stayed at %.2f m)", hoist);
    say(stage_, fmt("the %s can did not come up (hoist at %.2f m, gripped at %.2f m): too "
                    "heavy; let go, remembered; next candidate",
                    can->colour.c_str(), hoist, at_grip ? at_grip->hoist() : 0.0));
    return finish(r, Setback::TooHeavy, can->outcome);
  }
  say(stage_, "lifted the " + can->colour + " can (" + s->held_object() + ") off the floor");
  can->outcome = "lifted";
  scene_.holding = name;
  // Where the crane holds it: the magnet's face above the floor, less the can.
  scene_.held_height = geometry_.base_height + geometry_.pivot_z +
                       geometry_.boom_length * std::sin(s->lift()) - geometry_.magnet_below_tip -
                       s->hoist() - kCanTop;
  obstacles_.clear({can->x, can->y}, 0.12);
  crane_to(kParkSlew, kParkLift, 0.0);
  emit("lifted");
  return finish(r);
}

BehaviourReport Behaviours::go_to_switch() {
  BehaviourReport r = report("go_to", "switch");
  if (!scene_.switch_platform) {
    say(stage_, "the switch has not been seen yet; looking around");
    look_around(true);
  }
  if (!scene_.switch_platform)
    return finish(r, Setback::NoSwitch, "no door switch (a yellow floor platform) in sight");
  say(stage_, fmt("carrying the can to the switch at %.2f,%.2f", scene_.switch_platform->x,
                  scene_.switch_platform->y));
  map_here();
  if (!close_in(*scene_.switch_platform, Kind::Switch) && !close_in_by_what_is_on_it()) {
    // Seen from far (or the odometry drifted): look for it again from here, once.
    say(stage_, "the switch is not where it was seen; looking around for it");
    scene_.switch_platform.reset();
    look_around(true);
    if (!scene_.switch_platform || !close_in(*scene_.switch_platform, Kind::Switch))
      return finish(r, Setback::NoSwitch, "the switch is not where it was seen");
  }
  scene_.at = "switch";
  return finish(r);
}

bool Behaviours::close_in_by_what_is_on_it() {
  if (scene_.on_switch.empty()) return false;
  const SeenThing* put = thing(scene_.on_switch.front());  // put beside the platform's middle
  if (!put) return false;
  SeenThing marker = *put;
  say(stage_, fmt("the switch is hidden behind what stands on it: going by the %s %s there",
                  marker.colour.c_str(), marker.kind == Kind::Box ? "box" : "can"));
  if (!close_in(marker, marker.kind)) return false;
  scene_.switch_platform->x = marker.x + middle_from_first_.x;
  scene_.switch_platform->y = marker.y + middle_from_first_.y;
  return true;
}

BehaviourReport Behaviours::put_down() {
  BehaviourReport r = report("put_down", scene_.holding);
  if (!scene_.switch_platform) return finish(r, Setback::NoSwitch, "no switch was seen");
  const Pose2 b = to_base(scene_.switch_platform->x, scene_.switch_platform->y);
  // The first thing right of the platform's middle, the next left of it: two cans side by side
  // keep 0.05 m off its edges, where one in the middle and one beside it kept 0.02 m and the
  // second, lowered a few centimetres off, fell.
  const std::size_t there = scene_.on_switch.size();
  const double side = there % 2 ? kBesideOnPlatform : -kBesideOnPlatform;
  const double dx = b.x - geometry_.pivot_x, dy = b.y + side;
  const double slew = std::atan2(dy, dx);
  const double lift = std::clamp(
      -std::acos(std::clamp(std::hypot(dx, dy) / geometry_.boom_length, 0.0, 1.0)), -0.1, 0.36);
  say(stage_, fmt("switch at %.3f m ahead, %.3f m left: lowering the can onto it, %.2f m %s of its middle%s", b.x,
                  b.y, std::fabs(side), side > 0 ? "left" : "right", there ? ", beside what stands there" : ""));
  crane_to(slew, kParkLift, 0.0);
  crane_to(slew, lift, 0.0);
  // The can meets the platform under the magnet.
  lower_onto(lift, kPlatformTop + kCanTop, false);
  magnet_ = false;
  wait(0.5);
  say(stage_, "magnet off: the can stands on the switch");
  crane_to(slew, lift, 0.0, 2.5);
  park_crane();
  if (!scene_.holding.empty()) {
    scene_.on_switch.push_back(scene_.holding);
    // Seen there from now on: a sighting on the platform is the thing put down.
    if (SeenThing* put = thing(scene_.holding)) {
      const Pose2 at = to_odom(b.x, b.y + side);
      put->x = at.x;
      put->y = at.y;
      if (there == 0) middle_from_first_ = {scene_.switch_platform->x - at.x, scene_.switch_platform->y - at.y};
    }
  }
  scene_.holding.clear();
  scene_.held_height = 0;
  return finish(r);
}

BehaviourReport Behaviours::push(const std::string& name) {
  BehaviourReport r = report("push", name);
  // Pushing, the tracks spin against the box by design: no slip marks what it stands against.
  pushing_ = true;
  const std::shared_ptr<void> done_pushing(nullptr, [this](void*) { pushing_ = false; });
  SeenThing* box = thing(name);
  if (!box) return finish(r, Setback::NotSeen, name + " was never seen");
  if (!scene_.switch_platform) {
    say(stage_, "the switch has not been seen yet; looking around");
    look_around(true);
  }
  if (!scene_.switch_platform)
    return finish(r, Setback::NoSwitch, "no door switch (a yellow floor plate) in sight");
  Point onto{scene_.switch_platform->x, scene_.switch_platform->y};
  say(stage_, fmt("pushing the %s box at %.2f,%.2f onto the switch at %.2f,%.2f", box->colour.c_str(), box->x,
                  box->y, onto.x, onto.y));
  // In legs: behind it on the line from the switch, a closer look to aim at its middle, a push
  // to 25 cm short of the switch (or onto it when that close), back off and look where it went.
  map_here();
  Point from{box->x, box->y};
  double left = std::hypot(onto.x - from.x, onto.y - from.y);
  bool on_plate = false;
  // A shut door that opens says the box presses the switch, however the plate looks behind it.
  const bool door_shut = perceive_door() && !scene_.door;
  const bool flush = flush_switch(scene_);
  // Which way to push: to the plate, or (when the estimates put the box on it but the picture
  // does not) on along the way the robot looks at it.
  const auto way = [&] {
    const double d = std::hypot(onto.x - from.x, onto.y - from.y);
    if (d > 0.1) return Point{(onto.x - from.x) / d, (onto.y - from.y) / d};
    const double a = std::hypot(from.x - pose_.x, from.y - pose_.y);
    return Point{(from.x - pose_.x) / a, (from.y - pose_.y) / a};
  };
  for (int leg = 0; leg < kPushLegs && !on_plate; ++leg) {
    Point u = way();
    travel_to({from.x - kPushStandoff * u.x, from.y - kPushStandoff * u.y}, 0.05);
    turn_to(std::atan2(u.y, u.x));
    Sighting behind;
    auto at = find_again(*box, Kind::Box, 0.45, &behind);
    if (!at) {
      // Going round it, the robot may have nudged it on, or stand too close to see it whole:
      // from further back, a wider look.
      drive_straight(-0.5, 0.2);
      at = find_again(*box, Kind::Box, 0.8, &behind);
    }
    if (!at) {
      box->lost = true;
      box->outcome = "not seen again";
      return finish(r, Setback::NotSeen, "the " + box->colour + " box is not where it was seen");
    }
    from = *at;
    // The plate from here too: the box's way to it judged in one look, whatever the odometry.
    if (flush) {
      if (const auto plate = look_at_flush_plate()) {
        say(stage_, fmt("the plate's outline puts its middle at %.2f,%.2f", plate->x, plate->y));
        onto = *plate;
      }
    }
    left = std::hypot(onto.x - from.x, onto.y - from.y);
    // Seen from behind, the plate shows in front of a box that stands on it: one picture judges
    // the last centimetres better than two estimated positions do.
    if (behind.on_plate) {
      on_plate = true;
      break;
    }
    const Point ahead = way();
    if (ahead.x * u.x + ahead.y * u.y < 0) break;  // past where the plate was seen: no turning back
    u = ahead;
    turn_to(std::atan2(u.y, u.x));
    // A long push lets the box turn and slide off the line: at most kPushLeg, then aimed again.
    // Close to the plate, short pushes: the plate's middle is judged behind the box.
    const double along =
        left > 0.45 ? std::min(left - 0.25, kPushLeg) : std::clamp(left, 0.08, kLastPush);
    const Pose2 b = to_base(from.x, from.y);
    say(stage_, fmt("behind it: the box %.2f m ahead, %.2f m from the switch; pushing it %.2f m", b.x, left, along));
    drive_straight(b.x - kBumper - kBoxHalf + along, 0.15);
    drive_straight(-0.8, 0.2);  // far enough for the cameras to see it whole
    // Where it stands by the laser: the tracks slip when the box catches, and the box went on by
    // as much less.
    const Pose2 wheels = pose_;
    map_here();
    const double slipped = std::max(0.0, -((pose_.x - wheels.x) * u.x + (pose_.y - wheels.y) * u.y));
    if (slipped > kSlipSaid) say(stage_, fmt("the tracks slipped %.2f m of the push", slipped));
    if (door_shut && door_stays_open()) {
      say(stage_, "the door opened: the box presses the switch");
      on_plate = true;
      break;
    }
    // Looked for where it should be now (the box may have turned the robot aside).
    SeenThing pushed = *box;
    const double went = std::max(0.0, along - slipped);
    pushed.x = from.x + went * u.x;
    pushed.y = from.y + went * u.y;
    turn_to(std::atan2(pushed.y - pose_.y, pushed.x - pose_.x));
    Sighting sighted;
    const auto there = find_again(pushed, Kind::Box, 0.7, &sighted);  // the tracks slipped
    if (!there) {
      box->x = pushed.x;
      box->y = pushed.y;
      box->outcome = "not seen after the push";
      return finish(r, Setback::NotPushed, "the " + box->colour + " box was not seen after the push");
    }
    obstacles_.clear(from, 0.2);  // where the box stood is free now
    from = *there;
    box->x = from.x;
    box->y = from.y;
    // The plate again too: pushing, the tracks slip and the odometry runs ahead of the robot,
    // so what was seen before the push lies off now.
    // A flush plate's outline shows round a box in front of its middle; a raised platform's
    // blob is judged off its middle when the box hides part of it.
    auto plate = flush ? look_at_flush_plate() : std::nullopt;
    if (!plate && std::hypot(onto.x - from.x, onto.y - from.y) > kPlateHidden)
      plate = find_again(*scene_.switch_platform, Kind::Switch, 1.0);
    if (plate) {
      onto = *plate;
      scene_.switch_platform->x = plate->x;
      scene_.switch_platform->y = plate->y;
    }
    left = std::hypot(onto.x - from.x, onto.y - from.y);
    on_plate = sighted.on_plate;
  }
  if (on_plate) left = 0;
  box->x = from.x;
  box->y = from.y;
  if (left > kOnSwitch) {
    box->outcome = "did not reach the switch";
    say(stage_, fmt("the box ended at %.2f,%.2f, %.2f m from the switch", from.x, from.y, left));
    return finish(r, Setback::NotPushed, fmt("the box ended %.2f m from the switch", left));
  }
  say(stage_, "the box stands on the switch");
  box->outcome = "on the switch";
  scene_.on_switch.push_back(name);
  scene_.at = "switch";
  return finish(r);
}

bool Behaviours::perceive_door() {
  // From across the room the partition's band (only it reaches 0.5 m) holds few points: a dozen
  // on its line make it a wall here, where the watch before driving through wants 40.
  constexpr int kFewestWallPoints = 12;
  const auto points = slice(located_cloud(), geometry_, 0.505, 0.615, 0.3, 6.0);
  if (const auto passage = find_passage(points, 0.6, kFewestWallPoints)) {
    const Pose2 centre = to_odom(passage->centre.x, passage->centre.y);
    const Pose2 across = to_odom(passage->normal.x, passage->normal.y);
    scene_.door = SeenDoor{centre.x, centre.y, across.x - pose_.x, across.y - pose_.y, passage->width};
    return true;
  }
  if (!find_passage(points, 0.0, kFewestWallPoints)) return false;
  scene_.door.reset();
  return true;
}

bool Behaviours::door_stays_open() {
  // Twice, a while apart: the robot's own weight on a plate opens the door while it stands there
  // (and a single cloud can show a gap that is not there).
  if (!perceive_door() || !scene_.door) return false;
  wait(kDoorSettle);
  return perceive_door() && scene_.door;
}

BehaviourReport Behaviours::go_to_door() {
  BehaviourReport r = report("go_to", "door");
  if (scene_.door && std::hypot(scene_.door->x - pose_.x, scene_.door->y - pose_.y) > kDoorWatch + 0.5) {
    // Seen from across the room, the wall holds too few points to watch: closer first.
    const SeenDoor& d = *scene_.door;
    say(stage_, fmt("going toward the door seen at %.2f,%.2f", d.x, d.y));
    travel_to({d.x - kDoorWatch * d.nx, d.y - kDoorWatch * d.ny}, 0.1);
    turn_to(std::atan2(d.ny, d.nx));
  } else {
    drive_straight(-0.4, 0.2);
  }
  // The door opens when the switch sinks under the can: watch the wall for the opening.
  const double give_up = now_ + 25.0;
  std::optional<Passage> passage;
  int walls = 0;
  while (now_ < give_up) {
    const auto cloud = located_cloud();
    const auto points = slice(cloud, geometry_, 0.505, 0.615, 0.6, 6.0);
    passage = find_passage(points, 0.6);
    if (passage) break;
    walls += find_passage(points, 0.0) ? 1 : 0;
  }
  if (!passage) {
    scene_.door.reset();
    return walls > 0 ? finish(r, Setback::DoorClosed,
                              "the door stayed closed: the laser sees the wall without an opening "
                              "(the switch did not trigger?)")
                     : finish(r, Setback::NoDoor, "the laser finds no wall with a door around the robot");
  }
  const Pose2 centre = to_odom(passage->centre.x, passage->centre.y);
  const Pose2 across = to_odom(passage->normal.x, passage->normal.y);
  const double nx = across.x - pose_.x, ny = across.y - pose_.y;
  scene_.door = SeenDoor{centre.x, centre.y, nx, ny, passage->width};
  say(stage_, fmt("the door is open: the laser sees a %.2f m gap in the wall at %.2f,%.2f",
                  passage->width, centre.x, centre.y));
  emit("gap_seen");
  // In front of the opening, square to the wall.
  drive_to(centre.x - 0.9 * nx, centre.y - 0.9 * ny, 0.04);
  turn_to(std::atan2(ny, nx));
  scene_.at = "door";
  return finish(r);
}

BehaviourReport Behaviours::drive_through() {
  BehaviourReport r = report("drive_through", "door");
  if (scene_.at != "door" || !scene_.door) {
    const BehaviourReport there = go_to_door();
    if (!there.done()) return finish(r, there.setback, there.reason);
  }
  // A closer look to centre on the gap.
  double nx = scene_.door->nx, ny = scene_.door->ny;
  const auto closer = find_passage(slice(located_cloud(), geometry_, 0.505, 0.615, 0.3, 4.0), 0.6);
  Pose2 c{scene_.door->x, scene_.door->y, 0};
  if (closer) {
    c = to_odom(closer->centre.x, closer->centre.y);
    const Pose2 n = to_odom(closer->normal.x, closer->normal.y);
    nx = n.x - pose_.x;
    ny = n.y - pose_.y;
    say(stage_, fmt("closer look: a %.2f m gap centred at %.2f,%.2f", closer->width, c.x, c.y));
  }
  drive_to(c.x - 0.6 * nx, c.y - 0.6 * ny, 0.03, 0.15);
  turn_to(std::atan2(ny, nx));
  say(stage_, "driving through");
  drive_to(c.x + 1.0 * nx, c.y + 1.0 * ny, 0.05, 0.25);
  linear_ = angular_ = 0;
  wait(0.3);
  // Through: the wall is behind the robot now.
  const Pose2 b = to_base(c.x, c.y);
  if (b.x > -0.5)
    return finish(r, Setback::NotThrough, fmt("did not get through the door (it is %.2f m ahead)", b.x));
  scene_.beyond_door = true;
  say(stage_, fmt("through the door: %.2f m beyond it", -b.x));
  emit("through");
  return finish(r);
}

}  // namespace macsim::affordances
