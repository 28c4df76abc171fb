#include "demo_controller.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <thread>

#include "macsim/affordances/perception.h"
#include "macsim/client/picture_client.h"
#include "macsim/dds/convert.h"

namespace kurt_demo {

namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;

constexpr double kCruise = 0.3;             // m/s
constexpr double kStandoff = 0.9;           // m from an object to look at it closely
constexpr double kPickupRadius = 0.485;     // m from the crane's pivot to the object
constexpr double kRotunitSpeed = M_PI;      // rad/s: a cloud every 2 s
constexpr double kParkSlew = M_PI / 2, kParkLift = 0.6;
constexpr double kRobotRadius = 0.33;       // m: the chassis and wheels, from base_link
constexpr double kHalfWidth = 0.25;         // m: half the corridor the robot drives in

using kurt_loop::wrap;

std::string fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* format, ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  return text;
}

/// The features the demonstrator computes of a can from where it stands: the cameras'.
const std::vector<std::string>& camera_features() {
  return *macsim::affordances::feature_group("camera");
}

}  // namespace

macsim::affordances::AffordanceModel load_lift_model(const std::string& dir) {
  const std::string file = dir + "/lift.yml";
  try {
    auto model = macsim::affordances::AffordanceModel::load(file);
    if (model.info().affordance != "lift")
      throw Failure{kUsage, file + " is a model of " + model.info().affordance + ", not lift"};
    if (std::find(model.info().labels.begin(), model.info().labels.end(), "liftable") ==
        model.info().labels.end())
      throw Failure{kUsage, file + " has no label 'liftable'"};
    std::string missing;
    for (const auto& f : model.info().features) {
      if (std::find(camera_features().begin(), camera_features().end(), f) ==
          camera_features().end())
        missing += (missing.empty() ? "" : ",") + f;
    }
    if (!missing.empty())
      throw Failure{kUsage, file + " takes " + missing +
                                ", which the demonstrator cannot compute from where it stands "
                                "(it sees the cans with its cameras; train with "
                                "affordance_learn --features hue)"};
    return model;
  } catch (const macsim::affordances::ModelError& e) {
    throw Failure{kUsage, e.what()};
  }
}

struct DemoController::Pictures {
  explicit Pictures(macsim::dds::Participant& p) : client(p) {}
  macsim::client::PictureClient client;
  bool available = true;
};

DemoController::DemoController(macsim::dds::Participant& participant, const DemoOptions& options)
    : RobotLoop(participant, options.loop), options_(options) {
  if (options_.pictures) pictures_ = std::make_unique<Pictures>(participant);
}

DemoController::~DemoController() = default;

// ---- the loop -----------------------------------------------------------------------------

void DemoController::say(const std::string& scene, const std::string& text) {
  std::printf("kurt_demo: [t=%6.1f s] %s: %s\n", elapsed(), scene.c_str(), text.c_str());
  std::fflush(stdout);
}

void DemoController::picture(const std::string& name) {
  if (!pictures_ || !pictures_->available) return;
  auto reply = pictures_->client.take(name, "Chase", 3s);
  if (!reply) {
    pictures_->available = false;
    say(name, "no picture: nothing serves pictures here (a real robot has no overview camera)");
  } else if (reply->code() != mm::ERR_OK) {
    pictures_->available = false;
    say(name, "no picture: " + reply->message());
  } else {
    say(name, "picture " + reply->file());
  }
}

// ---- motion -------------------------------------------------------------------------------

std::string DemoController::lower_onto(double lift, double height, bool until_held) {
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

void DemoController::park_crane() {
  crane_to(crane_.state() ? crane_.state()->slew() : 0.0, kParkLift, 0.0, 3.0);
  crane_to(kParkSlew, kParkLift, 0.0);
}

// ---- sensing ------------------------------------------------------------------------------

std::vector<std::pair<Sighting, Pose2>> DemoController::look(int frames) {
  linear_ = angular_ = 0;
  wait(0.3);  // let the chassis come to rest
  looking_ = true;
  struct Done {
    bool& looking;
    ~Done() { looking = false; }
  } done{looking_};
  std::vector<std::pair<Sighting, Pose2>> seen;
  double after = now_ - 1e-6;
  for (int taken = 0, tries = 0; taken < frames && tries < 40; ++tries) {
    if (auto frame = cameras_.latest(after)) {
      after = frame->stamp;
      ++taken;
      auto sightings = find_objects(*frame, geometry_);
      if (options_.lift_model) {
        // What the lift model says of each can: the trials' perception of the can's blob.
        for (auto& s : sightings) {
          if (s.kind != Kind::Can) continue;
          const cv::Rect around(s.box.x - 4, s.box.y - 4, s.box.width + 8, s.box.height + 8);
          macsim::affordances::Percept p;
          macsim::affordances::perceive_image(*frame, p, around);
          if (!p.seen) continue;
          try {
            const auto said = options_.lift_model->predict(macsim::affordances::named_features(
                p, macsim::affordances::Affordance::Lift));
            s.liftable = said.label == "liftable" ? said.confidence : 1.0 - said.confidence;
          } catch (const macsim::affordances::ModelError& e) {
            say("look", std::string("the lift model could not judge a can: ") + e.what());
          }
        }
      }
      for (const auto& s : sightings) seen.emplace_back(s, to_odom(s.x, s.y));
      if (!options_.debug_images.empty()) {
        cv::imwrite(fmt("%s/look_%03d.png", options_.debug_images.c_str(), debug_count_++),
                    draw_sightings(frame->left, sightings));
      }
      continue;
    }
    tick();
  }
  return seen;
}

void DemoController::record(const std::vector<std::pair<Sighting, Pose2>>& sightings) {
  for (const auto& [s, at] : sightings) {
    if (s.range > 3.5) continue;  // too far to place well
    if (s.kind == Kind::Switch) {
      if (!switch_) switch_ = Candidate{at.x, at.y, "yellow", 0, false, ""};
      auto& w = *switch_;
      w.x = (w.x * w.seen + at.x) / (w.seen + 1);
      w.y = (w.y * w.seen + at.y) / (w.seen + 1);
      ++w.seen;
      continue;
    }
    auto same = std::find_if(candidates_.begin(), candidates_.end(), [&](const Candidate& c) {
      return c.colour == s.colour && std::hypot(c.x - at.x, c.y - at.y) < 0.2;
    });
    if (same == candidates_.end()) {
      candidates_.push_back({at.x, at.y, s.colour, 0, false, ""});
      same = candidates_.end() - 1;
    } else if (same->tried) {
      continue;
    }
    same->x = (same->x * same->seen + at.x) / (same->seen + 1);
    same->y = (same->y * same->seen + at.y) / (same->seen + 1);
    ++same->seen;
    if (s.liftable >= 0) {
      same->liftable = (same->liftable * same->judged + s.liftable) / (same->judged + 1);
      ++same->judged;
    }
  }
}

void DemoController::map_here() {
  const auto cloud = take_cloud();
  obstacles_.add(cloud, geometry_, pose_.x, pose_.y, pose_.yaw);
}

Point DemoController::approach_point(Point target, double standoff, double reach) const {
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

void DemoController::travel_to(Point goal, double tolerance) {
  const Point here{pose_.x, pose_.y};
  if (!obstacles_.free(here, goal, kHalfWidth)) {
    // Around it: the first waypoint beside the straight way from which both legs are free.
    const double dx = goal.x - here.x, dy = goal.y - here.y, d = std::hypot(dx, dy);
    for (double side : {0.5, -0.5, 0.8, -0.8, 1.1, -1.1, 1.4, -1.4}) {
      for (double along : {0.5, 0.25, 0.75}) {
        const Point via{here.x + along * dx - side * dy / d, here.y + along * dy + side * dx / d};
        if (obstacles_.clearance(via, kRobotRadius) >= kRobotRadius &&
            obstacles_.free(here, via, kHalfWidth) && obstacles_.free(via, goal, kHalfWidth)) {
          drive_to(via.x, via.y, 0.08);
          drive_to(goal.x, goal.y, tolerance);
          return;
        }
      }
    }
  }
  drive_to(goal.x, goal.y, tolerance);
}

// ---- scenes -------------------------------------------------------------------------------

void DemoController::search(const std::string& scene, bool want_switch) {
  const double start_yaw = pose_.yaw;
  for (int k = 0; k < 9; ++k) {
    if (k > 0) turn_to(start_yaw + k * 2 * M_PI / 9);
    record(look(1));
    if (want_switch && switch_) break;
  }
  std::ostringstream what;
  what << candidates_.size() << " can candidate(s)";
  for (const auto& c : candidates_) {
    what << fmt(" [%s at %.2f,%.2f%s]", c.colour.c_str(), c.x, c.y, c.tried ? ", tried" : "");
  }
  if (switch_) what << fmt("; the switch at %.2f,%.2f", switch_->x, switch_->y);
  say(scene, "looked around: " + what.str());
}

std::optional<Point> DemoController::find_again(const Candidate& target, Kind kind) {
  auto matches = [&](const std::vector<std::pair<Sighting, Pose2>>& seen) {
    int found = 0;
    double sx = 0, sy = 0;
    for (const auto& [s, at] : seen) {
      if (s.kind == kind && (kind == Kind::Switch || s.colour == target.colour) &&
          std::hypot(at.x - target.x, at.y - target.y) < 0.45) {
        sx += at.x;
        sy += at.y;
        ++found;
      }
    }
    return found ? std::optional<Point>(Point{sx / found, sy / found}) : std::nullopt;
  };
  if (auto at = matches(look(3))) return at;
  // Not where expected: the odometry drifted. Look a little to each side, then from further
  // back (closer than about 0.8 m the floor in front is out of the cameras' view).
  const double ahead = pose_.yaw;
  for (double off : {0.45, -0.45}) {
    turn_to(ahead + off);
    if (auto at = matches(look(2))) return at;
  }
  turn_to(ahead);
  drive_straight(-0.4, 0.15);
  return matches(look(3));
}

bool DemoController::close_in(Candidate& target, Kind kind) {
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

bool DemoController::try_lift(Candidate& can) {
  can.tried = true;
  say("scene 2", fmt("going for the %s can at %.2f,%.2f (odometry frame)", can.colour.c_str(),
                     can.x, can.y));
  // Stand off where the way in is free, look again from close by, drive in to the crane's reach.
  if (!close_in(can, Kind::Can)) {
    can.outcome = "not seen again";
    say("scene 2", "the " + can.colour + " can is not where it was seen; next candidate");
    return false;
  }

  // Over it with the magnet, then down until the magnet holds it or rests on it.
  ++lift_attempts_;
  const Pose2 b = to_base(can.x, can.y);
  const double dx = b.x - geometry_.pivot_x, dy = b.y;
  const double slew = std::atan2(dy, dx);
  const double radius = std::clamp(std::hypot(dx, dy) / geometry_.boom_length, 0.0, 1.0);
  const double lift = std::clamp(-std::acos(radius), -0.24, 0.36);
  say("scene 2", fmt("can at %.3f m ahead, %.3f m left: slew %.2f rad, lift %.2f rad, magnet on, "
                     "lowering",
                     b.x, b.y, slew, lift));
  crane_to(slew, kParkLift, 0.0);
  crane_to(slew, lift, 0.0);
  magnet_ = true;
  // The can's top (0.135 m) is where the magnet meets it.
  const std::string held = lower_onto(lift, 0.135, true);
  if (held.empty()) {
    magnet_ = false;
    crane_to(slew, lift, 0.0);
    park_crane();
    can.outcome = "the magnet does not hold it (not magnetizable)";
    failed_colours_.push_back(can.colour);
    say("scene 2", "the magnet does not hold the " + can.colour + " can: not magnetizable? "
                   "Remembered; next candidate");
    return false;
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
    can.outcome = fmt("too heavy (the hoist stayed at %.2f m)", hoist);
    failed_colours_.push_back(can.colour);
    say("scene 2", fmt("the %s can did not come up (hoist at %.2f m, gripped at %.2f m): too "
                       "heavy; let go, remembered; next candidate",
                       can.colour.c_str(), hoist, at_grip ? at_grip->hoist() : 0.0));
    return false;
  }
  say("scene 2", "lifted the " + can.colour + " can (" + s->held_object() + ") off the floor");
  can.outcome = "lifted";
  obstacles_.clear({can.x, can.y}, 0.12);
  crane_to(kParkSlew, kParkLift, 0.0);
  picture("scene2_can_on_magnet");
  return true;
}

void DemoController::deliver() {
  if (!switch_) {
    say("scene 3", "the switch has not been seen yet; looking around");
    search("scene 3", true);
  }
  if (!switch_) throw Failure{kNoSwitch, "no door switch (a yellow floor platform) in sight"};
  say("scene 3", fmt("carrying the can to the switch at %.2f,%.2f", switch_->x, switch_->y));
  map_here();
  if (!close_in(*switch_, Kind::Switch)) {
    throw Failure{kNoSwitch, "the switch is not where it was seen"};
  }
  const Pose2 b = to_base(switch_->x, switch_->y);
  const double dx = b.x - geometry_.pivot_x, dy = b.y;
  const double slew = std::atan2(dy, dx);
  const double lift = std::clamp(
      -std::acos(std::clamp(std::hypot(dx, dy) / geometry_.boom_length, 0.0, 1.0)), -0.1, 0.36);
  say("scene 3", fmt("switch at %.3f m ahead, %.3f m left: lowering the can onto it", b.x, b.y));
  crane_to(slew, kParkLift, 0.0);
  crane_to(slew, lift, 0.0);
  // The can (0.135 m) meets the platform (0.07 m) under the magnet.
  lower_onto(lift, 0.07 + 0.135, false);
  magnet_ = false;
  wait(0.5);
  say("scene 3", "magnet off: the can stands on the switch");
  crane_to(slew, lift, 0.0, 2.5);
  park_crane();
}

void DemoController::go_through() {
  drive_straight(-0.4, 0.2);
  // The door opens when the switch sinks under the can: watch the wall for the opening.
  const double give_up = now_ + 25.0;
  std::optional<Passage> passage;
  int walls = 0;
  while (now_ < give_up) {
    const auto cloud = take_cloud();
    const auto points = slice(cloud, geometry_, 0.505, 0.615, 0.6, 6.0);
    passage = find_passage(points, 0.6);
    if (passage) break;
    walls += find_passage(points, 0.0) ? 1 : 0;
  }
  if (!passage) {
    throw Failure{kDoorClosed,
                  walls > 0 ? "the door stayed closed: the laser sees the wall without an opening "
                              "(the switch did not trigger?)"
                            : "the laser finds no wall with a door around the robot"};
  }
  const Pose2 centre = to_odom(passage->centre.x, passage->centre.y);
  const Pose2 across = to_odom(passage->normal.x, passage->normal.y);
  double nx = across.x - pose_.x, ny = across.y - pose_.y;
  say("scene 4", fmt("the door is open: the laser sees a %.2f m gap in the wall at %.2f,%.2f",
                     passage->width, centre.x, centre.y));
  picture("scene3_can_on_switch_door_open");
  // In front of the opening, square to the wall; then a closer look to centre on it.
  drive_to(centre.x - 0.9 * nx, centre.y - 0.9 * ny, 0.04);
  turn_to(std::atan2(ny, nx));
  const auto closer = find_passage(slice(take_cloud(), geometry_, 0.505, 0.615, 0.3, 4.0), 0.6);
  Pose2 c = centre;
  if (closer) {
    c = to_odom(closer->centre.x, closer->centre.y);
    const Pose2 n = to_odom(closer->normal.x, closer->normal.y);
    nx = n.x - pose_.x;
    ny = n.y - pose_.y;
    say("scene 4", fmt("closer look: a %.2f m gap centred at %.2f,%.2f", closer->width, c.x, c.y));
  }
  drive_to(c.x - 0.6 * nx, c.y - 0.6 * ny, 0.03, 0.15);
  turn_to(std::atan2(ny, nx));
  say("scene 4", "driving through");
  drive_to(c.x + 1.0 * nx, c.y + 1.0 * ny, 0.05, 0.25);
  linear_ = angular_ = 0;
  wait(0.3);
  // Through: the wall is behind the robot now.
  const Pose2 b = to_base(c.x, c.y);
  if (b.x > -0.5) {
    throw Failure{kNoPassage, fmt("did not get through the door (it is %.2f m ahead)", b.x)};
  }
  say("scene 4", fmt("through the door: %.2f m beyond it", -b.x));
  picture("scene4_robot_through");
}

void DemoController::run() {
  say("start", "looking for robot '" + options_.loop.robot + "'" + (simulation_ ? " (lock-step)" : ""));
  connect();
  start_ = now_;
  say("start", "found it; parking the crane, starting the laser's rotating unit");
  rotunit_ = kRotunitSpeed;
  park_crane();
  map_here();
  search("scene 1", false);
  if (candidates_.empty()) throw Failure{kNoCan, "no can in sight after a full turn"};
  picture("scene1_cans_found");
  if (options_.lift_model) {
    const auto& info = options_.lift_model->info();
    std::string said;
    for (const auto& c : candidates_) {
      said += c.judged ? fmt(" [%s at %.2f,%.2f: %s %.2f]", c.colour.c_str(), c.x, c.y,
                             c.liftable >= 0.5 ? "liftable" : "not_liftable",
                             c.liftable >= 0.5 ? c.liftable : 1.0 - c.liftable)
                       : fmt(" [%s at %.2f,%.2f: not judged]", c.colour.c_str(), c.x, c.y);
    }
    say("scene 2", fmt("the lift model (%s rows of %s, held-out accuracy %.1f %%) says:%s",
                       std::to_string(info.rows).c_str(), info.generator.c_str(),
                       100 * info.held_out_accuracy, said.c_str()));
  }
  // Scene 2: with a lift model, the cans it finds likeliest to come up first; then (and without
  // one) the nearest first, colours that failed last.
  bool lifted = false, looked_again = false;
  while (!lifted) {
    Candidate* next = nullptr;
    double best = 1e9;
    for (auto& c : candidates_) {
      if (c.tried) continue;
      const double failures =
          std::count(failed_colours_.begin(), failed_colours_.end(), c.colour);
      // A can the model never judged counts as even odds: after those it finds likely.
      const double unlikely =
          options_.lift_model ? 100.0 * (1.0 - (c.judged ? c.liftable : 0.5)) : 0.0;
      const double cost =
          unlikely + std::hypot(c.x - pose_.x, c.y - pose_.y) + 10.0 * failures;
      if (cost < best) {
        best = cost;
        next = &c;
      }
    }
    if (!next && !looked_again) {
      // Every candidate failed: maybe a can was hidden behind another; one more look around.
      looked_again = true;
      search("scene 2", false);
      continue;
    }
    if (!next) {
      std::string tried;
      for (const auto& c : candidates_) tried += " " + c.colour + ": " + c.outcome + ";";
      throw Failure{kNoLiftableCan, "no can could be lifted (" +
                                        std::to_string(candidates_.size()) + " tried:" + tried + ")"};
    }
    lifted = try_lift(*next);
  }
  deliver();
  go_through();
  linear_ = angular_ = 0;
  rotunit_ = 0;
  tick();
}

}  // namespace kurt_demo
