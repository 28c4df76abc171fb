#include "simulated_kurt.h"

#include <cmath>
#include <stdexcept>

namespace macsim {

namespace {
robot::Capabilities capabilities_of(const KurtConfig& config) {
  robot::Capabilities c;
  c.ground_truth = true;
  c.ranges = config.range_sensors;
  c.imu = true;
  c.rotunit = config.laser == LaserMount::Rotating;
  c.laser = config.laser != LaserMount::None;
  c.laser_rotating = config.laser == LaserMount::Rotating;
  c.points = config.laser == LaserMount::Rotating;
  c.crane = config.crane;
  c.magnet = config.crane;
  return c;
}
robot::Mount mount(const std::string& parent, const std::string& child, const Eigen::Vector3d& p,
                   const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  return {parent, child, {p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

robot::Frames frames_of(const KurtConfig& config) {
  robot::Frames f;
  const double link_height = config.body.wheel_axle_below_base_link + config.drive.wheel_radius();
  f.mounts.push_back(mount("base_footprint", "base_link", {0, 0, link_height}));
  if (config.range_sensors) {
    for (const RangeSensorSpec& s : kurt_range_sensors()) {
      f.mounts.push_back(
          mount("base_link", s.frame, {s.x, s.y, 0},
                Eigen::Quaterniond(Eigen::AngleAxisd(s.yaw, Eigen::Vector3d::UnitZ()))));
    }
  }
  if (config.cameras) {
    // An optical frame looks along z with x right and y down (REP-103).
    const Eigen::Quaterniond optical(0.5, -0.5, 0.5, -0.5);  // w, x, y, z
    for (const auto& [side, pose] :
         {std::pair{"left", config.cameras->left}, std::pair{"right", config.cameras->right}}) {
      const std::string camera = std::string(side) + "_camera";
      f.mounts.push_back(mount("base_link", camera, pose.position, pose.orientation));
      f.mounts.push_back(
          mount(camera, camera + "_optical_frame", Eigen::Vector3d::Zero(), optical));
    }
  }
  if (config.laser == LaserMount::Fixed) {
    f.mounts.push_back(mount("base_link", "laser", laser_origin(config.laser)));
  } else if (config.laser == LaserMount::Rotating) {
    // The scan plane is vertical (the frame's xy plane turned up about x); the rotunit turns
    // it about base_link's z axis.
    f.laser = mount("base_link", "laser360", laser_origin(config.laser),
                    Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())));
  }
  if (config.crane) {
    const CraneParams& c = config.crane_params;
    f.crane_pivot = mount("base_link", "crane_turret", {c.pivot_x, 0, c.pivot_height});
    f.boom_length = c.boom_length;
  }
  return f;
}

}  // namespace

SimulatedKurt::SimulatedKurt(Runner& runner, std::string name)
    : runner_(runner), name_(std::move(name)) {
  KurtRobot* r = robot();
  if (!r) throw std::invalid_argument("no robot named '" + name_ + "' in the world");
  capabilities_ = capabilities_of(r->config());
  frame_tree_ = frames_of(r->config());
  generation_ = runner.generation();
}

void SimulatedKurt::command_twist(double linear, double angular) {
  if (KurtRobot* r = robot()) r->command_twist(linear, angular, runner_.world().time());
}

void SimulatedKurt::command_wheel_speeds(double left, double right) {
  if (KurtRobot* r = robot()) r->command_wheel_speeds({left, right}, runner_.world().time());
}

void SimulatedKurt::command_rotunit(double speed) {
  if (KurtRobot* r = robot()) r->command_rotunit(speed);
}

void SimulatedKurt::command_crane(double slew, double lift, double hoist) {
  if (KurtRobot* r = robot()) r->command_crane({slew, lift, hoist});
}

void SimulatedKurt::command_magnet(bool on) {
  if (KurtRobot* r = robot()) r->command_magnet(on);
}

robot::Readings SimulatedKurt::read() {
  robot::Readings out;
  KurtRobot* r = robot();
  if (!r) return out;
  const double now = runner_.world().time();
  out.stamp = now;
  if (now < last_time_ || runner_.generation() != generation_) {
    // A reset or a new world: its first readings are new, whatever their counters say.
    generation_ = runner_.generation();
    frames_ = scans_ = clouds_ = UINT64_MAX;
  }
  last_time_ = now;
  if (r->odometry_frames() != frames_) {  // every encoder frame
    frames_ = r->odometry_frames();
    const PlanarOdometry o = r->odometry();
    out.odometry = robot::Odometry{o.x,
                                   o.y,
                                   o.yaw,
                                   o.linear,
                                   o.angular,
                                   std::remainder(r->wheel_angle(0), 2 * M_PI),
                                   std::remainder(r->wheel_angle(1), 2 * M_PI)};
    const Pose pose = r->base_footprint_pose();
    const Eigen::Vector3d v = pose.orientation.conjugate() * r->linear_velocity();
    const Eigen::Vector3d w = pose.orientation.conjugate() * r->angular_velocity();
    const auto& q = pose.orientation;
    out.ground_truth = robot::GroundTruth{{pose.position.x(), pose.position.y(), pose.position.z()},
                                          {q.x(), q.y(), q.z(), q.w()},
                                          {v.x(), v.y(), v.z()},
                                          {w.x(), w.y(), w.z()}};
    const ImuReading& imu = r->imu();
    out.imu = robot::Imu{imu.roll, imu.pitch, imu.yaw, imu.yaw_variance, imu.yaw_rate};
    if (capabilities_.ranges) {
      for (const RangeReading& each : r->ranges()) {
        out.ranges.push_back({each.sensor->frame, each.sensor->sonar, each.range});
      }
    }
    if (capabilities_.crane) {
      const CraneState c = r->crane_state();
      out.crane = robot::Crane{c.slew, c.lift, c.hoist, c.magnet_on, c.held_object};
    }
  }
  if (r->laser_scans() != scans_) {  // every sweep
    scans_ = r->laser_scans();
    const LaserScan& s = r->laser_scan();
    out.scan = robot::Scan{capabilities_.laser_rotating ? "laser360" : "laser",
                           s.angle_min,
                           s.angle_increment,
                           s.range_min,
                           s.range_max,
                           1.0 / r->config().laser_rate,
                           s.ranges};
    if (capabilities_.rotunit) out.rotunit = robot::Rotunit{r->rotunit_angle(), r->rotunit_speed()};
  }
  if (r->point_clouds() != clouds_) {  // every revolution
    clouds_ = r->point_clouds();
    const PointCloud& cloud = r->point_cloud();
    robot::Cloud c;
    c.xyz.reserve(cloud.points.size() * 3);
    for (const auto& p : cloud.points) c.xyz.insert(c.xyz.end(), {p.x(), p.y(), p.z()});
    out.cloud = std::move(c);
  }
  return out;
}

}  // namespace macsim
