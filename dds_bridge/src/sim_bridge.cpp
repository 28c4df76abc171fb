#include "sim_bridge.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>

#include "macsim/dds/convert.h"
#include "macsim/dds/kurt_messages.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/rosgraph_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/render/camera_rig.h"
#include "robot_commands.h"

namespace macsim {

namespace gm = geometry_msgs::msg::dds_;
namespace nm = nav_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;
namespace km = kurt_msgs::msg::dds_;
using dds::QosFamily;

struct SimBridge::Clock {
  dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> writer;
};

struct SimBridge::RobotTopics {
  RobotTopics(dds::Participant& p, const std::string& robot, bool rotating_laser)
      : name(robot),
        odom(p, dds::topics::odom(robot), QosFamily::Sensor),
        ground_truth(p, dds::topics::ground_truth(robot), QosFamily::Sensor),
        joint_states(p, dds::topics::joint_states(robot), QosFamily::Sensor),
        range(p, dds::topics::range(robot), QosFamily::Sensor),
        imu(p, dds::topics::imu(robot), QosFamily::Sensor),
        scan(p, dds::topics::scan(robot, rotating_laser), QosFamily::Sensor),
        points(p, dds::topics::points(robot), QosFamily::Sensor),
        crane_state(p, dds::topics::crane_state(robot), QosFamily::Sensor) {}

  std::string name;
  uint64_t frames = 0, scans = 0, clouds = 0;
  uint64_t stereo_skipped = 0;  // camera instants skipped while a renderer was still busy
  double next_camera_time = 0.0;
  dds::Writer<nm::Odometry_PubSubType> odom, ground_truth;
  dds::Writer<sm::JointState_PubSubType> joint_states;
  dds::Writer<sm::Range_PubSubType> range;
  dds::Writer<sm::Imu_PubSubType> imu;
  dds::Writer<sm::LaserScan_PubSubType> scan;
  dds::Writer<sm::PointCloud2_PubSubType> points;
  dds::Writer<km::CraneState_PubSubType> crane_state;
  std::unique_ptr<dds::Writer<sm::Image_PubSubType>> left_image, right_image;
  std::unique_ptr<dds::Writer<sm::CameraInfo_PubSubType>> left_info, right_info;
  // Readers last: they are destroyed first, so no callback outlives what it queues into.
  std::unique_ptr<dds::Reader<gm::Twist_PubSubType>> cmd_vel, rot_vel;
  std::unique_ptr<dds::Reader<km::WheelSpeeds_PubSubType>> wheel_speeds;
  std::unique_ptr<dds::Reader<km::CraneCommand_PubSubType>> crane_command;
  std::unique_ptr<dds::Reader<km::MagnetCommand_PubSubType>> magnet;
  std::vector<std::unique_ptr<render::CameraRig>> cameras;  // one per eye, rendering in parallel
};

namespace {

/// Ground truth of base_footprint in the world frame; twist in the robot frame (as ROS does).
nm::Odometry_ ground_truth_message(const KurtRobot& robot, double stamp) {
  const Pose pose = robot.base_footprint_pose();
  const Eigen::Vector3d v = pose.orientation.conjugate() * robot.linear_velocity();
  const Eigen::Vector3d w = pose.orientation.conjugate() * robot.angular_velocity();
  nm::Odometry_ msg;
  msg.header(dds::header(stamp, "world"));
  msg.child_frame_id("base_footprint");
  msg.pose().pose().position(dds::point(pose.position.x(), pose.position.y(), pose.position.z()));
  const auto& q = pose.orientation;
  msg.pose().pose().orientation(dds::quaternion(q.x(), q.y(), q.z(), q.w()));
  msg.twist().twist().linear(dds::vector3(v.x(), v.y(), v.z()));
  msg.twist().twist().angular(dds::vector3(w.x(), w.y(), w.z()));
  return msg;
}

sm::LaserScan_ scan_message(const LaserScan& scan, const std::string& frame, double rate) {
  sm::LaserScan_ msg;
  msg.header(dds::header(scan.stamp, frame));
  msg.angle_min(static_cast<float>(scan.angle_min));
  msg.angle_max(
      static_cast<float>(scan.angle_min + scan.angle_increment * (scan.ranges.size() - 1)));
  msg.angle_increment(static_cast<float>(scan.angle_increment));
  msg.scan_time(static_cast<float>(1.0 / rate));
  msg.time_increment(
      static_cast<float>(1.0 / rate / 2 / scan.ranges.size()));  // half a turn of the mirror
  msg.range_min(static_cast<float>(scan.range_min));
  msg.range_max(static_cast<float>(scan.range_max));
  msg.ranges(scan.ranges);
  return msg;
}

sm::PointCloud2_ cloud_message(const PointCloud& cloud) {
  sm::PointCloud2_ msg;
  msg.header(dds::header(cloud.stamp, "base_link"));
  uint32_t offset = 0;
  for (const char* axis : {"x", "y", "z"}) {
    sm::PointField_ field;
    field.name(axis);
    field.offset(offset);
    field.datatype(7);  // FLOAT32
    field.count(1);
    msg.fields().push_back(field);
    offset += 4;
  }
  msg.height(1);
  msg.width(static_cast<uint32_t>(cloud.points.size()));
  msg.point_step(12);
  msg.row_step(12 * msg.width());
  msg.is_bigendian(false);
  msg.is_dense(true);
  msg.data().resize(cloud.points.size() * 12);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    std::memcpy(msg.data().data() + 12 * i, cloud.points[i].data(), 12);
  }
  return msg;
}

sm::Image_ image_message(const cv::Mat& bgr, double stamp, const std::string& frame) {
  sm::Image_ msg;
  msg.header(dds::header(stamp, frame));
  msg.height(bgr.rows);
  msg.width(bgr.cols);
  msg.encoding("bgr8");
  msg.step(bgr.cols * 3);
  msg.data().assign(bgr.data, bgr.data + bgr.total() * 3);
  return msg;
}

/// Pinhole calibration; the right camera's projection carries the baseline.
sm::CameraInfo_ camera_info(const render::CameraIntrinsics& in, double stamp,
                            const std::string& frame, double baseline) {
  sm::CameraInfo_ msg;
  msg.header(dds::header(stamp, frame));
  msg.height(in.height);
  msg.width(in.width);
  msg.distortion_model("plumb_bob");
  msg.d({0, 0, 0, 0, 0});
  const double f = in.focal(), cx = in.width / 2.0, cy = in.height / 2.0;
  msg.k({f, 0, cx, 0, f, cy, 0, 0, 1});
  msg.r({1, 0, 0, 0, 1, 0, 0, 0, 1});
  msg.p({f, 0, cx, -f * baseline, 0, f, cy, 0, 0, 0, 1, 0});
  return msg;
}

}  // namespace

SimBridge::SimBridge(dds::Participant& participant, Runner& runner, const BridgeOptions& options)
    : runner_(runner),
      options_(options),
      clock_(new Clock{{participant, dds::topics::kClock, QosFamily::Sensor}}) {
  for (const auto& robot : runner.world().robots()) {
    const std::string name = robot->name();
    auto topics = std::make_unique<RobotTopics>(participant, name,
                                                robot->config().laser == LaserMount::Rotating);
    // Reader callbacks run on Fast DDS's threads: copy the numbers, queue a command, nothing else.
    auto queue = [&runner](std::optional<Command> command) {
      if (command) runner.push(std::move(*command));
    };
    topics->cmd_vel = std::make_unique<dds::Reader<gm::Twist_PubSubType>>(
        participant, dds::topics::cmd_vel(name), QosFamily::Command,
        [queue, name](const gm::Twist_& t) {
          queue(robot_commands::twist(name, t.linear().x(), t.angular().z()));
        });
    topics->wheel_speeds = std::make_unique<dds::Reader<km::WheelSpeeds_PubSubType>>(
        participant, dds::topics::wheel_speeds(name), QosFamily::Command,
        [queue, name](const km::WheelSpeeds_& w) {
          queue(robot_commands::wheel_speeds(name, {w.left(), w.right()}));
        });
    topics->rot_vel = std::make_unique<dds::Reader<gm::Twist_PubSubType>>(
        participant, dds::topics::rot_vel(name), QosFamily::Command,
        [queue, name](const gm::Twist_& t) { queue(robot_commands::rotunit(name, t.angular().z())); });
    topics->crane_command = std::make_unique<dds::Reader<km::CraneCommand_PubSubType>>(
        participant, dds::topics::crane_command(name), QosFamily::Command,
        [queue, name](const km::CraneCommand_& c) {
          queue(robot_commands::crane(name, {c.slew(), c.lift(), c.hoist()}));
        });
    topics->magnet = std::make_unique<dds::Reader<km::MagnetCommand_PubSubType>>(
        participant, dds::topics::crane_magnet(name), QosFamily::Command,
        [queue, name](const km::MagnetCommand_& m) { queue(robot_commands::magnet(name, m.on())); });
    if (options_.cameras) {
      auto* t = topics.get();
      t->left_image = std::make_unique<dds::Writer<sm::Image_PubSubType>>(
          participant, dds::topics::image(name, "left"), QosFamily::Sensor);
      t->right_image = std::make_unique<dds::Writer<sm::Image_PubSubType>>(
          participant, dds::topics::image(name, "right"), QosFamily::Sensor);
      t->left_info = std::make_unique<dds::Writer<sm::CameraInfo_PubSubType>>(
          participant, dds::topics::camera_info(name, "left"), QosFamily::Sensor);
      t->right_info = std::make_unique<dds::Writer<sm::CameraInfo_PubSubType>>(
          participant, dds::topics::camera_info(name, "right"), QosFamily::Sensor);
      const render::CameraIntrinsics in = options_.camera;
      const double baseline =
          (render::left_camera_mount().position - render::right_camera_mount().position).norm();
      // Runs on the render thread: writers are thread-safe, the world is never touched.
      auto publish = [t, in, baseline](const render::CameraImage& f) {
        // Each image goes out as soon as it is rendered, with its camera info.
        if (f.eye == render::Eye::Left) {
          t->left_image->write(image_message(f.image, f.stamp, "left_camera_optical_frame"));
          t->left_info->write(camera_info(in, f.stamp, "left_camera_optical_frame", 0.0));
        } else {
          t->right_image->write(image_message(f.image, f.stamp, "right_camera_optical_frame"));
          t->right_info->write(camera_info(in, f.stamp, "right_camera_optical_frame", baseline));
        }
      };
      for (const render::Eye eye : {render::Eye::Left, render::Eye::Right}) {
        t->cameras.push_back(
            std::make_unique<render::CameraRig>(name, in, publish, std::vector<render::Eye>{eye}));
      }
    }
    robots_.push_back(std::move(topics));
  }
}

SimBridge::~SimBridge() = default;

void SimBridge::poll_commands() {
  for (auto& t : robots_) {
    t->cmd_vel->poll();
    t->wheel_speeds->poll();
    t->rot_vel->poll();
    t->crane_command->poll();
    t->magnet->poll();
  }
}

void SimBridge::publish() {
  World& world = runner_.world();
  const double now = world.time();
  if (now < last_time_ || runner_.generation() != generation_) {
    // A reset or a new world: start the schedules again.
    generation_ = runner_.generation();
    next_clock_time_ = now;
    for (auto& t : robots_) {
      t->next_camera_time = now;
      t->frames = t->scans = t->clouds = UINT64_MAX;
    }
  }
  last_time_ = now;
  if (now + 1e-9 >= next_clock_time_) {
    rosgraph_msgs::msg::dds_::Clock_ clock;
    clock.clock(dds::to_time(now));
    clock_->writer.write(clock);
    next_clock_time_ += 0.01;
  }
  for (auto& topics : robots_) {
    if (KurtRobot* robot = world.robot(topics->name)) publish_robot(*topics, *robot, now);
  }
}

void SimBridge::publish_robot(RobotTopics& t, KurtRobot& robot, double now) {
  if (robot.odometry_frames() != t.frames) {  // every 10 ms encoder frame
    t.frames = robot.odometry_frames();
    const PlanarOdometry odom = robot.odometry();
    t.odom.write(dds::kurt_odometry(odom.x, odom.y, odom.yaw, odom.linear, odom.angular, now));
    t.ground_truth.write(ground_truth_message(robot, now));
    t.joint_states.write(dds::kurt_wheel_joints(std::remainder(robot.wheel_angle(0), 2 * M_PI),
                                                std::remainder(robot.wheel_angle(1), 2 * M_PI),
                                                now));
    const ImuReading imu = robot.imu();
    t.imu.write(dds::kurt_imu(imu.roll, imu.pitch, imu.yaw, imu.yaw_variance, imu.yaw_rate, now));
    for (const RangeReading& r : robot.ranges()) {
      if (!robot.config().range_sensors) break;
      t.range.write(dds::kurt_range(r.sensor->frame, r.sensor->sonar, r.range, now));
    }
    const CraneState crane = robot.crane_state();
    km::CraneState_ state;
    state.header(dds::header(now, "base_link"));
    state.slew(crane.slew);
    state.lift(crane.lift);
    state.hoist(crane.hoist);
    state.magnet_on(crane.magnet_on);
    state.held_object(crane.held_object);
    t.crane_state.write(state);
  }
  if (robot.laser_scans() != t.scans) {
    t.scans = robot.laser_scans();
    const bool rotating = robot.config().laser == LaserMount::Rotating;
    t.scan.write(scan_message(robot.laser_scan(), rotating ? "laser360" : "laser",
                              robot.config().laser_rate));
    if (rotating) {  // the driver publishes the rotunit in joint_states messages of its own
      t.joint_states.write(
          dds::kurt_rotunit_joint(robot.rotunit_angle(), robot.rotunit_speed(), now));
    }
  }
  if (robot.point_clouds() != t.clouds) {
    t.clouds = robot.point_clouds();
    t.points.write(cloud_message(robot.point_cloud()));
  }
  if (!t.cameras.empty() && now + 1e-9 >= t.next_camera_time) {
    t.next_camera_time += 1.0 / options_.camera_rate;
    // Both eyes render the same scene or neither does: a stereo pair never mixes two instants.
    const bool ready = std::all_of(t.cameras.begin(), t.cameras.end(),
                                   [](const auto& rig) { return rig->idle(); });
    if (ready) {
      const render::Scene scene = render::capture_scene(runner_.world());
      for (auto& rig : t.cameras) rig->submit(scene);
    } else {
      ++t.stereo_skipped;
    }
  }
}

void SimBridge::wait_for_cameras() {
  for (auto& t : robots_) {
    for (auto& rig : t->cameras) rig->wait_idle();
  }
}

std::string SimBridge::camera_summary() const {
  std::string summary;
  for (const auto& t : robots_) {
    if (t->cameras.empty()) continue;
    summary += "macsim: " + t->name + "'s cameras: " + std::to_string(t->cameras[0]->rendered()) +
               " stereo pairs rendered, " + std::to_string(t->stereo_skipped) +
               " skipped (a renderer was busy)\n";
  }
  return summary;
}

std::vector<std::string> SimBridge::topic_names() const {
  std::vector<std::string> names{dds::topics::kClock + " (rosgraph_msgs/Clock, out)"};
  for (const auto& t : robots_) {
    const auto& n = t->name;
    for (const auto& [topic, what] : std::vector<std::pair<std::string, std::string>>{
             {dds::topics::cmd_vel(n), "geometry_msgs/Twist, in"},
             {dds::topics::wheel_speeds(n), "kurt_msgs/WheelSpeeds, in"},
             {dds::topics::rot_vel(n), "geometry_msgs/Twist, in"},
             {dds::topics::crane_command(n), "kurt_msgs/CraneCommand, in"},
             {dds::topics::crane_magnet(n), "kurt_msgs/MagnetCommand, in"},
             {dds::topics::odom(n), "nav_msgs/Odometry, out"},
             {dds::topics::ground_truth(n), "nav_msgs/Odometry, out"},
             {dds::topics::joint_states(n), "sensor_msgs/JointState, out"},
             {dds::topics::range(n), "sensor_msgs/Range, out"},
             {dds::topics::imu(n), "sensor_msgs/Imu, out"},
             {t->scan.topic_name(), "sensor_msgs/LaserScan, out"},
             {dds::topics::points(n), "sensor_msgs/PointCloud2, out"},
             {dds::topics::crane_state(n), "kurt_msgs/CraneState, out"}}) {
      names.push_back(topic + " (" + what + ")");
    }
    if (!t->cameras.empty()) {
      for (const char* side : {"left", "right"}) {
        names.push_back(dds::topics::image(n, side) + " (sensor_msgs/Image, out)");
        names.push_back(dds::topics::camera_info(n, side) + " (sensor_msgs/CameraInfo, out)");
      }
    }
  }
  return names;
}

}  // namespace macsim
