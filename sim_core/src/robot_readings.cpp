#include "robot_readings.h"

#include <ode/ode.h>

#include <cmath>

#include "ode_support.h"

namespace macsim::detail {

robot::Mount robot_mount(const std::string& parent, const std::string& child,
                         const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  return {parent, child, {p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

void add_stereo_frames(const StereoMount& cameras, robot::Frames& frames) {
  const Eigen::Quaterniond optical(0.5, -0.5, 0.5, -0.5);  // w, x, y, z
  for (const auto& [side, pose] :
       {std::pair{"left", cameras.left}, std::pair{"right", cameras.right}}) {
    const std::string camera = std::string(side) + "_camera";
    frames.mounts.push_back(robot_mount("base_link", camera, pose.position, pose.orientation));
    frames.mounts.push_back(
        robot_mount(camera, camera + "_optical_frame", Eigen::Vector3d::Zero(), optical));
  }
}

robot::Odometry odometry_reading(const PlanarOdometry& o, double left_wheel, double right_wheel) {
  return {o.x,
          o.y,
          o.yaw,
          o.linear,
          o.angular,
          std::remainder(left_wheel, 2 * M_PI),
          std::remainder(right_wheel, 2 * M_PI)};
}

robot::GroundTruth ground_truth_reading(const RobotModel& robot) {
  const Pose pose = robot.base_footprint_pose();
  const Eigen::Vector3d v = pose.orientation.conjugate() * robot.linear_velocity();
  const Eigen::Vector3d w = pose.orientation.conjugate() * robot.angular_velocity();
  const auto& q = pose.orientation;
  return {{pose.position.x(), pose.position.y(), pose.position.z()},
          {q.x(), q.y(), q.z(), q.w()},
          {v.x(), v.y(), v.z()},
          {w.x(), w.y(), w.z()}};
}

ShapeView shape_view(dGeomID g, const Color& color) {
  ShapeView v;
  dQuaternion q;
  dGeomGetQuaternion(g, q);
  v.pose = {vec(dGeomGetPosition(g)), from_ode(q)};
  v.color = color;
  switch (dGeomGetClass(g)) {
    case dBoxClass: {
      dVector3 sides;
      dGeomBoxGetLengths(g, sides);
      v.shape = Shape::Box;
      v.size = vec(sides);
      break;
    }
    case dSphereClass:
      v.shape = Shape::Sphere;
      v.size = {dGeomSphereGetRadius(g), 0.0, 0.0};
      break;
    default: {
      dReal radius, length;
      dGeomCylinderGetParams(g, &radius, &length);
      v.shape = Shape::Cylinder;
      v.size = {radius, 0.0, length};
    }
  }
  return v;
}

robot::Scan scan_reading(const LaserScan& s, const std::string& frame, double scan_time) {
  return {frame, s.angle_min, s.angle_increment, s.range_min, s.range_max, scan_time, s.ranges};
}

}  // namespace macsim::detail
