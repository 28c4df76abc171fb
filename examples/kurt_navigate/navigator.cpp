#include "navigator.h"

#include <cmath>
#include <cstdio>

namespace kurt_navigate {

namespace {

using kurt_loop::wrap;

constexpr double kSpeed = 0.4;          // m/s, the traverse trials' speed
constexpr double kStretch = 0.8;        // m driven before looking again
constexpr double kHalfWidth = 0.25;     // m: half the robot's width (0.22) and a margin
// The traverse trials' obstacle: its near side 0.62-0.75 m ahead, at most 0.6 m deep.
constexpr double kTrialNear = 0.68, kThingDepth = 0.6;
constexpr double kWayStep = M_PI / 12;  // the ways judged: every 15 degrees...
constexpr int kWaysEachSide = 8;        // ...up to 120 degrees either side of the goal's bearing
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

std::optional<Navigator::Choice> Navigator::choose(const macsim::client::Cloud& cloud) {
  const double goal_bearing = std::atan2(options_.goal_y - pose_.y, options_.goal_x - pose_.x);
  const double to_goal = std::hypot(options_.goal_x - pose_.x, options_.goal_y - pose_.y);
  std::optional<Choice> best, likeliest;
  std::string judged;
  for (int k = 0; k <= 2 * kWaysEachSide; ++k) {
    // 0, +15, -15, +30, ... degrees off the goal's bearing: the first passable is the nearest.
    const int off = (k + 1) / 2 * (k % 2 ? 1 : -1);
    const double heading = wrap(goal_bearing + off * kWayStep);
    // Where a stretch stalled before, the same way is not taken again.
    bool stalled_here = false;
    for (const auto& [where, taken] : stalled_) {
      stalled_here |= std::hypot(where.x - pose_.x, where.y - pose_.y) < 0.4 &&
                      std::fabs(wrap(taken - heading)) < 0.3;
    }
    if (stalled_here) continue;
    const auto way = along(cloud, wrap(heading - pose_.yaw));
    Choice c{heading, 0, false};
    // Free for a stretch and a margin: passable by either policy.
    const double free = free_length(way, kHalfWidth, 2.0);
    const bool clear = free >= std::min(kStretch, to_goal) + 0.3;
    if (options_.policy == Policy::Model) {
      // Something in the way: the model is asked about it as a trial saw its obstacle, its near
      // side 0.68 m ahead and the floor beyond (what stands further is left out).
      c.score = 1.0;
      if (!clear) {
        auto seen = way;
        const double shift = kTrialNear - free;
        std::erase_if(seen.points, [&](const auto& q) { return q[0] > free + kThingDepth; });
        for (auto& q : seen.points) q[0] = static_cast<float>(q[0] + shift);
        const auto said = options_.traverse_model->predict(way_features(seen));
        c.score = said.label == "traversable" ? said.confidence : 1 - said.confidence;
      }
      c.passable = c.score >= 0.5;
    } else {
      c.score = free;
      c.passable = clear;
    }
    char text[48];
    std::snprintf(text, sizeof text, " %+.0f:%.2f", off * kWayStep * 180 / M_PI, c.score);
    judged += text;
    if (c.passable && !best) best = c;
    if (!likeliest || c.score > likeliest->score) likeliest = c;
  }
  say("ways off the goal's bearing (deg: " +
      std::string(options_.policy == Policy::Model ? "P(traversable)" : "free m") + "):" + judged);
  if (best) return best;
  // None judged passable: the model's likeliest is taken at its word; the baseline takes the
  // longest free way when it leaves room for a short stretch.
  if (likeliest && (options_.policy == Policy::Model || likeliest->score >= 0.6)) return likeliest;
  return std::nullopt;
}

Outcome Navigator::run() {
  Outcome out;
  try {
    drive(out);
  } catch (const kurt_loop::LoopError& e) {
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
  std::vector<Point2> walls;  // the tall structure of the last look, odometry frame
  std::optional<std::pair<kurt_loop::Pose2, double>> stretch;  // from where, which way
  double asked = 0;
  while (true) {
    const auto cloud = take_cloud();
    // Where the walls say it is: a track slipping against something counts as distance in the
    // wheels' odometry, not in the laser's.
    auto tall = tall_structure(cloud, pose_);
    // It may not have moved at all since the last look (stuck, its wheels slipping).
    std::vector<std::array<double, 2>> guesses;
    if (stretch) guesses.push_back({stretch->first.x - pose_.x, stretch->first.y - pose_.y});
    const auto shift = walls.empty() ? std::nullopt : align(walls, tall, guesses);
    if (shift) {
      pose_.x += (*shift)[0];
      pose_.y += (*shift)[1];
      tall = tall_structure(cloud, pose_);
    }
    walls = std::move(tall);
    sightings_.add(cloud, pose_);
    if (stretch) {
      const double moved = std::hypot(pose_.x - stretch->first.x, pose_.y - stretch->first.y);
      if (moved < 0.3 * asked) {
        ++out.stalls;
        stalled_.push_back(*stretch);
        std::snprintf(text, sizeof text,
                      "stalled: %.2f m of %.2f (by the laser): pressed against something it "
                      "cannot pass; backing off",
                      moved, asked);
        say(text);
        drive_straight(-0.3, 0.2, 1.0);
      }
    }
    const double to_goal = std::hypot(options_.goal_x - pose_.x, options_.goal_y - pose_.y);
    if (to_goal < options_.tolerance) break;
    const auto choice = choose(cloud);
    if (!choice) {
      out.code = kNoWay;
      out.reason = "no way judged passable from here";
      break;
    }
    std::snprintf(text, sizeof text,
                  "at %.2f,%.2f, %.2f m from the goal: heading %.0f deg (%s %.2f)", pose_.x,
                  pose_.y, to_goal, choice->heading * 180 / M_PI,
                  options_.policy == Policy::Model ? "P(traversable)" : "free m", choice->score);
    say(text);
    turn_to(choice->heading);
    ++out.stretches;
    // A stretch, shorter near the goal: stalled when its wheels made no 2 cm in a second (or,
    // at the next look, when the laser says it did not get 30 % of the way).
    asked = std::min(kStretch, to_goal);
    stretch = {pose_, choice->heading};
    if (!drive_straight(asked, kSpeed, 1.0)) {
      ++out.stalls;
      stalled_.push_back(*stretch);
      stretch.reset();
      say("stalled: pressed against something it cannot pass; backing off");
      drive_straight(-0.3, 0.2, 1.0);
    }
  }
  linear_ = angular_ = 0;
  rotunit_ = 0;
  tick();
}

}  // namespace kurt_navigate
