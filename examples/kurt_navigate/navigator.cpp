#include "navigator.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace kurt_navigate {

namespace {

using macsim::affordances::wrap;
using macsim::affordances::length;
using macsim::affordances::near_side;
using macsim::affordances::p_traversable;
using macsim::affordances::things_in;

constexpr double kSpeed = 0.4;    // m/s, the traverse trials' speed
constexpr double kStretch = 1.0;  // m of the way driven before looking again
// Clear of what it cannot pass: half the robot's width over its tracks (0.22 m) and a margin;
// closer than kMargin costs more.
constexpr double kClearance = 0.3, kMargin = 0.5;
// With no way over what it judged passable, it tries what it judged at least this likely to be,
// each cell of it costing this many times bare floor.
constexpr double kDoubted = 0.25, kDoubtedCost = 8.0;
constexpr double kLookahead = 0.35;  // m: the point of the way it steers for
// The traverse trials' obstacle: its near side 0.62-0.75 m ahead.
using macsim::affordances::kTrialNear;
// A thing is judged from where its near side lies kJudgeNearest-kJudgeNear m away (a trial's
// lay 0.62-0.75 m ahead), alone in the cloud turned to face it; the look nearest kTrialNear
// wins. The robot stops where its way comes within kApproach of a thing not judged yet; standing
// there already (within kJudgeRange of it), it goes to stand with the near side kTrialNear
// ahead (give or take kNearSlack / 2).
constexpr double kNearSlack = 0.07, kApproach = 0.8, kJudgeRange = 1.1;
constexpr double kJudgeNearest = 0.5, kJudgeNear = 0.9;
// The traverse trials' look: the boom up and swung aside (out of the cloud), the scanner
// turning once a second.
constexpr double kAsideSlew = -0.75, kBoomUp = 0.6;
constexpr double kRotunitSpeed = 2 * M_PI;

}  // namespace

Navigator::Navigator(macsim::dds::Participant& participant, const NavigateOptions& options)
    : RobotLoop(participant, options.loop), options_(options) {}

void Navigator::say(const std::string& text) {
  std::printf("kurt_navigate: [t=%6.1f s] %s\n", elapsed(), text.c_str());
  std::fflush(stdout);
}

void Navigator::after_tick() { sightings_.pass(pose_); }

macsim::client::Cloud Navigator::level(macsim::client::Cloud cloud) const {
  const auto imu = imu_.latest();
  if (!imu) return cloud;
  const auto& o = imu->orientation();
  const Eigen::Quaterniond q(o.w(), o.x(), o.y(), o.z());
  // The robot's tilt alone: its orientation with the heading (of its x axis) taken out.
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const Eigen::Matrix3f tilt =
      (Eigen::AngleAxisd(-std::atan2(r(1, 0), r(0, 0)), Eigen::Vector3d::UnitZ()) * r)
          .cast<float>();
  for (auto& p : cloud.points) {
    const Eigen::Vector3f v = tilt * Eigen::Vector3f(p[0], p[1], p[2]);
    p = {v.x(), v.y(), v.z()};
  }
  return cloud;
}

Navigator::Way Navigator::plan(const macsim::client::Cloud& cloud) {
  const Point2 goal{options_.goal_x, options_.goal_y};
  auto things = things_in(cloud, pose_);
  std::string judged;
  for (auto& thing : things) {
    thing.judged = true;  // the baseline: nothing is passable
    if (options_.policy != Policy::Model || thing.height == Height::Towering) continue;
    bool pressed = false;  // it stalled against this before
    for (const auto& at : pressed_)
      for (const auto& c : thing.cells) pressed |= std::hypot(c[0] - at[0], c[1] - at[1]) < 0.2;
    char text[80];
    if (pressed) {
      thing.passable = false;
      continue;
    }
    const double near = near_side(cloud, pose_, thing);
    if (near >= kJudgeNearest && near <= kJudgeNear) {
      // Near, as a trial's obstacle stood: the model is asked about it alone, in the frame that
      // faces it; the verdict of the look nearest a trial's stance is kept.
      const double p = p_traversable(*options_.traverse_model, cloud, pose_, things, thing);
      const double off_trial = std::fabs(near - kTrialNear);
      std::size_t taken = 0;  // cells this look judged first or from nearer a trial's stance
      for (const auto& c : thing.cells) {
        auto [v, fresh] = verdicts_.try_emplace(cell_of(c), Verdict{p, off_trial});
        const bool take = fresh || off_trial < v->second.off_trial;
        if (take) v->second = Verdict{p, off_trial};
        taken += take;
      }
      if (2 * taken > thing.cells.size()) {  // a new verdict on the most of it
        std::snprintf(text, sizeof text, " (%.2f,%.2f %.2fm %.2f at %.2fm)", thing.centre[0],
                      thing.centre[1], thing.across, p, near);
        judged += text;
      }
    }
    // As the best look judged the cells it covers, else not known yet.
    double sum = 0;
    int n = 0;
    for (const auto& c : thing.cells) {
      const auto v = verdicts_.find(cell_of(c));
      if (v != verdicts_.end()) sum += v->second.p_traversable, ++n;
    }
    thing.judged = n > 0;
    thing.p_traversable = n > 0 ? sum / n : 0;
    thing.passable = thing.judged && thing.p_traversable >= 0.5;
  }
  if (options_.policy == Policy::Model && !judged.empty())
    say("judged (where, across, P(traversable), near side):" + judged);
  if (options_.verbose) {
    std::string all;
    for (const auto& thing : things) {
      char p[8] = "-";  // not judged yet
      if (thing.height == Height::Towering)
        std::snprintf(p, sizeof p, "wall");
      else if (thing.judged)
        std::snprintf(p, sizeof p, "%.2f", thing.p_traversable);
      char t[96];
      std::snprintf(t, sizeof t, " (%.2f,%.2f %.2fm %.2fm %s)", thing.centre[0], thing.centre[1],
                    thing.across, thing.distance, p);
      all += t;
    }
    say("things (where, across, distance, P(traversable)):" + all);
  }
  Way way;
  // Clear by the margin if it can; closer to what it cannot pass if it must.
  for (double clearance : {kClearance, kClearance - 0.05}) {
    FloorPlan floor({pose_.x, pose_.y}, goal);
    for (const auto& thing : things) floor.add(thing, clearance, kMargin);
    for (const auto& at : pressed_) floor.block(at, 0.12);
    way.points = floor.path();
    if (!way.points.empty()) break;
  }
  // No way over what it judged passable: it tries what it doubted least, and then anything it
  // has not stalled against, at a price, before it gives up (a stall marks what it cannot pass).
  for (double doubt : {kDoubted, 0.0}) {
    if (!way.points.empty() || options_.policy != Policy::Model) break;
    FloorPlan floor({pose_.x, pose_.y}, goal);
    for (auto thing : things) {
      const bool tried = thing.judged && !thing.passable && thing.height != Height::Towering &&
                         thing.p_traversable >= doubt;
      thing.passable |= tried;
      floor.add(thing, kClearance - 0.05, kMargin, tried ? kDoubtedCost : 2.0);
    }
    for (const auto& at : pressed_) floor.block(at, 0.12);
    way.points = floor.path();
    if (!way.points.empty()) {
      char text[96];
      std::snprintf(text, sizeof text,
                    "no way over what it judged passable: trying what it judged P >= %.2f", doubt);
      say(text);
    }
  }
  // It stops to look where the way comes near what it has not judged yet, as a trial looked;
  // standing there already, it turns to face it.
  way.stretch = std::min(kStretch, length(way.points));
  double run = 0;
  for (std::size_t k = 0; k < way.points.size() && run < way.stretch; ++k) {
    const auto& p = way.points[k];
    if (k > 0) run += std::hypot(p[0] - way.points[k - 1][0], p[1] - way.points[k - 1][1]);
    const Thing* ahead = nullptr;
    for (const auto& thing : things) {
      if (thing.judged) continue;
      for (const auto& c : thing.cells)
        if (std::hypot(c[0] - p[0], c[1] - p[1]) < kApproach) ahead = &thing;
      if (ahead) break;
    }
    if (!ahead) continue;
    way.stretch = run;
    if (run < 0.1 && ahead->distance <= kJudgeRange)
      way.judge = Stand{ahead->centre, near_side(cloud, pose_, *ahead)};
    else
      way.stretch = std::max(run, 0.1);
    break;
  }
  return way;
}

void Navigator::stand_before(const Stand& stand) {
  turn_to(std::atan2(stand.centre[1] - pose_.y, stand.centre[0] - pose_.x));
  if (std::fabs(stand.near - kTrialNear) > kNearSlack / 2)
    drive_straight(stand.near - kTrialNear, 0.2, 1.0);
  turn_to(std::atan2(stand.centre[1] - pose_.y, stand.centre[0] - pose_.x));
}

void Navigator::back_off(Outcome& out, const std::string& why) {
  ++out.stalls;
  // What it stood against blocks from now on.
  const Point2 against{pose_.x + 0.35 * std::cos(pose_.yaw), pose_.y + 0.35 * std::sin(pose_.yaw)};
  // Stalled there before (wedged on something, its tracks slipping): it backs off further.
  int before = 0;
  for (const auto& at : pressed_)
    before += std::hypot(at[0] - against[0], at[1] - against[1]) < 0.3;
  pressed_.push_back(against);
  say("stalled (" + why + "): pressed against something it cannot pass; backing off");
  drive_straight(-0.3 * std::min(before + 1, 3), 0.2, 1.0);
}

bool Navigator::follow(const std::vector<Point2>& way, double stretch) {
  double travelled = 0, best = 0, best_at = now_;
  macsim::affordances::Pose2 last = pose_;
  std::size_t along = 0;  // the way's point nearest the robot
  // A stretch takes a few times what driving it straight would; a track slipping on what it is
  // wedged on makes headway by the wheels but none by the ground.
  const double give_up = now_ + 3 * stretch / kSpeed + 5.0;
  bool stalled = false;
  while (now_ < give_up) {
    for (std::size_t k = along; k < way.size() && k < along + 20; ++k) {
      if (std::hypot(way[k][0] - pose_.x, way[k][1] - pose_.y) <
          std::hypot(way[along][0] - pose_.x, way[along][1] - pose_.y))
        along = k;
    }
    std::size_t target = along;
    while (target + 1 < way.size() &&
           std::hypot(way[target][0] - pose_.x, way[target][1] - pose_.y) < kLookahead)
      ++target;
    const double to_end = std::hypot(way.back()[0] - pose_.x, way.back()[1] - pose_.y);
    if (travelled >= stretch || to_end < 0.05) break;
    const double bearing = std::atan2(way[target][1] - pose_.y, way[target][0] - pose_.x);
    const double error = wrap(bearing - pose_.yaw);
    if (std::fabs(error) > 0.6) {  // turn on the spot first
      turn_to(bearing);
      best_at = now_;
      last = pose_;
      continue;
    }
    linear_ = std::clamp(1.2 * to_end + 0.05, 0.05, kSpeed) * (1 - 0.6 * std::fabs(error));
    angular_ = std::clamp(2.5 * error, -0.8, 0.8);
    tick();
    travelled += std::hypot(pose_.x - last.x, pose_.y - last.y);
    last = pose_;
    if (travelled > best + 0.02) {
      best = travelled;
      best_at = now_;
    } else if (now_ - best_at > 1.0) {
      stalled = true;
      break;
    }
  }
  linear_ = angular_ = 0;
  tick();
  return !stalled;
}

Outcome Navigator::run() {
  Outcome out;
  try {
    drive(out);
  } catch (const macsim::affordances::LoopError& e) {
    constexpr Exit kCodes[] = {kNoRobot, kTimeout, kNoCloud};
    out.code = kCodes[static_cast<int>(e.stop)];
    out.reason = e.what();
  }
  out.things = sightings_.count(0.22);
  return out;
}

void Navigator::drive(Outcome& out) {
  say("looking for robot '" + options_.loop.robot + "'" + (simulation_ ? " (lock-step)" : ""));
  connect();
  start_ = now_;
  char text[160];
  std::snprintf(text, sizeof text, "found it; goal at %.2f,%.2f (odometry frame), policy %s",
                options_.goal_x, options_.goal_y,
                options_.policy == Policy::Model ? "model" : "avoid");
  say(text);
  rotunit_ = kRotunitSpeed;
  crane_to(kAsideSlew, kBoomUp, 0.0);
  StaticMap map;                  // what stands still, odometry frame
  macsim::affordances::Pose2 stretch_from;  // where the last stretch began...
  double asked = 0;               // ...and the m its wheels made on it (0: none to judge)
  int faced = 0;                  // turns in a row to face a thing to judge
  while (true) {
    const auto cloud = level(take_cloud());
    // Where what stands still says it is: a track slipping against something counts as
    // distance in the wheels' odometry, not in the laser's.
    auto still = static_structure(cloud, pose_);
    // Its tracks may have slipped on the last stretch, by any part of it up to the whole (stuck):
    // where it would stand had they slipped by each fifth, and a hand to either side.
    std::vector<std::array<double, 2>> guesses;
    if (asked > 0) {
      const double bx = stretch_from.x - pose_.x, by = stretch_from.y - pose_.y;
      const double norm = std::max(std::hypot(bx, by), 1e-9);
      for (int fifth = 1; fifth <= 5; ++fifth)
        for (double side : {0.0, -0.15, 0.15})
          guesses.push_back({fifth * bx / 5 - side * by / norm, fifth * by / 5 + side * bx / norm});
    }
    const auto shift = map.points().empty() ? std::nullopt : align(map.points(), still, guesses);
    if (options_.verbose) {
      char t[160];
      std::snprintf(t, sizeof t,
                    "laser odometry: wheels at %.2f,%.2f; %zu points on %zu of the map: %s",
                    pose_.x, pose_.y, still.size(), map.points().size(),
                    shift ? "" : "no fit, the wheels' word kept");
      if (shift)
        std::snprintf(t + std::strlen(t), sizeof t - std::strlen(t), "moved by %.3f,%.3f",
                      (*shift)[0], (*shift)[1]);
      say(t);
    }
    if (shift) {
      pose_.x += (*shift)[0];
      pose_.y += (*shift)[1];
      still = static_structure(cloud, pose_);
    }
    // The first look makes the map; a look it could be aligned with adds what it saw anew.
    if (shift || map.points().empty()) map.add(still);
    sightings_.add(cloud, pose_);
    if (asked > 0.1) {
      const double moved = std::hypot(pose_.x - stretch_from.x, pose_.y - stretch_from.y);
      if (moved < 0.3 * asked) {
        std::snprintf(text, sizeof text, "%.2f m of %.2f (by the laser)", moved, asked);
        back_off(out, text);
        asked = 0;
        continue;  // and looks again from there
      }
    }
    const double to_goal = std::hypot(options_.goal_x - pose_.x, options_.goal_y - pose_.y);
    if (to_goal < options_.tolerance) break;
    const auto way = plan(cloud);
    if (way.judge && faced < 3) {  // to judge what stands in its way
      ++faced;
      stand_before(*way.judge);
      asked = 0;
      continue;
    }
    faced = 0;
    if (way.points.empty()) {
      out.code = kNoWay;
      out.reason = "no way judged passable from here";
      break;
    }
    std::snprintf(text, sizeof text, "at %.2f,%.2f, %.2f m from the goal: a way of %.2f m", pose_.x,
                  pose_.y, to_goal, length(way.points));
    say(text);
    ++out.stretches;
    stretch_from = pose_;
    const bool went = follow(way.points, way.stretch);
    asked = std::hypot(pose_.x - stretch_from.x, pose_.y - stretch_from.y);
    if (!went) {
      back_off(out, "no headway by the wheels");
      asked = 0;
    }
  }
  linear_ = angular_ = 0;
  rotunit_ = 0;
  tick();
}

}  // namespace kurt_navigate
