// What macsim_web sends the page, as JSON text frames (and JPEG images as binary frames), made
// from the wire types a client reads. No DDS here: unit-tested on its own.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>

#include "macsim/client/robot_devices.h"
#include "macsim/msg/macsim_msgs.h"
#include "macsim/msg/plan_msgs.h"

namespace macsim::web {

using Objects = std::map<uint32_t, macsim_msgs::msg::dds_::ObjectState_>;

/// The robot as the page draws it.
struct RobotView {
  bool known = false;                               ///< a ground-truth pose came
  std::array<double, 7> pose{0, 0, 0, 0, 0, 0, 1};  ///< base_link in the world: x y z qx qy qz qw
  double slew = 0, lift = 0, hoist = 0;             ///< the crane's joints (rad, rad, m)
  bool magnet = false;
  std::string held;  ///< the object on the magnet, if any
};

/// {"type":"scene", domain, robot, objects: [{id, name, kind, portable, components: [{shape,
/// size, position, orientation, color}], position, orientation}]}: everything to build the
/// page's scene.
std::string scene_message(const Objects& objects, int domain, const std::string& robot);

/// {"type":"update", time, rtf, objects: {id: [x y z qx qy qz qw]}, robot: {pose, crane,
/// magnet, held}}: what moved, at the page's rate.
std::string update_message(const Objects& objects, double sim_time, double rtf,
                           const RobotView& robot);

/// {"type":"scan", stamp, frame, angle_min, angle_increment, ranges (m, 3 decimals; null: no
/// echo)}.
std::string scan_message(const sensor_msgs::msg::dds_::LaserScan_& scan);

/// {"type":"cloud", stamp, points: [x y z ...] in base_link, m, 3 decimals}, every k-th point
/// so that at most `max_points` are sent.
std::string cloud_message(const client::Cloud& cloud, std::size_t max_points);

/// Where the robot's odometry frame lies in the world: x, y (m) and yaw (rad), from a ground-truth
/// pose and an odometry pose of the same instant.
std::array<double, 3> odom_in_world(const geometry_msgs::msg::dds_::Pose_& truth,
                                    const geometry_msgs::msg::dds_::Pose_& odom);

/// {"type":"plan", goal, round, current, outcome, steps: [{action, predicted, probability,
/// perceived, status ("to do", "under way", "as predicted", "not as predicted")}], things: [{name,
/// label, confidence, position: [x y] in the world}]}: a controller's plan as it acts, its things
/// moved from the odometry frame into the world by `odom` (x, y, yaw).
std::string plan_message(const plan_msgs::msg::dds_::Plan_& plan, const std::array<double, 3>& odom);

/// A binary frame: one byte naming the eye ('L' or 'R'), then the image as JPEG.
std::string image_frame(char eye, const cv::Mat& bgr, int quality);

/// The answer to a text frame from the page: {"type":"hello"} gets {"type":"hello", domain,
/// robot}; anything else (bad JSON, an unknown type) an {"type":"error", message}.
std::string answer(const std::string& text, int domain, const std::string& robot);

}  // namespace macsim::web
