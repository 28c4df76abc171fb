#include "sim_bridge.h"

#include <cfloat>
#include <cmath>

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"

namespace macsim {

namespace gm = geometry_msgs::msg::dds_;
namespace nm = nav_msgs::msg::dds_;

struct SimBridge::RobotTopics {
  std::string name;
  uint64_t published_frames = 0;
  std::unique_ptr<dds::Writer<nm::Odometry_PubSubType>> odom;
  std::unique_ptr<dds::Writer<nm::Odometry_PubSubType>> ground_truth;
  std::unique_ptr<dds::Reader<gm::Twist_PubSubType>> cmd_vel;
};

namespace {

/// Odometry as the real driver publishes it (kurt_base: frames, covariance).
nm::Odometry_ odometry_message(const PlanarOdometry& odom, double stamp) {
  nm::Odometry_ msg;
  msg.header().stamp(dds::to_time(stamp));
  msg.header().frame_id("odom_combined");
  msg.child_frame_id("base_footprint");
  msg.pose().pose().position().x(odom.x);
  msg.pose().pose().position().y(odom.y);
  msg.pose().pose().orientation(dds::yaw_quaternion(odom.yaw));
  msg.twist().twist().linear().x(odom.linear);
  msg.twist().twist().angular().z(odom.angular);
  dds::set_driver_covariance(msg, odom.linear, odom.angular);
  return msg;
}

/// Ground truth of base_footprint in the world frame; twist in the robot frame (as ROS does).
nm::Odometry_ ground_truth_message(const KurtRobot& robot, double stamp) {
  const Pose pose = robot.base_footprint_pose();
  const Eigen::Vector3d v = pose.orientation.conjugate() * robot.linear_velocity();
  const Eigen::Vector3d w = pose.orientation.conjugate() * robot.angular_velocity();
  nm::Odometry_ msg;
  msg.header().stamp(dds::to_time(stamp));
  msg.header().frame_id("world");
  msg.child_frame_id("base_footprint");
  msg.pose().pose().position(dds::point(pose.position.x(), pose.position.y(), pose.position.z()));
  const auto& q = pose.orientation;
  msg.pose().pose().orientation(dds::quaternion(q.x(), q.y(), q.z(), q.w()));
  msg.twist().twist().linear(dds::vector3(v.x(), v.y(), v.z()));
  msg.twist().twist().angular(dds::vector3(w.x(), w.y(), w.z()));
  return msg;
}

}  // namespace

SimBridge::SimBridge(dds::Participant& participant, Simulation& simulation)
    : simulation_(simulation) {
  clock_ = std::make_unique<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
      participant, dds::topics::kClock, dds::QosFamily::Sensor);
  for (const auto& robot : simulation.world().robots()) {
    auto topics = std::make_unique<RobotTopics>();
    topics->name = robot->name();
    topics->odom = std::make_unique<dds::Writer<nm::Odometry_PubSubType>>(
        participant, dds::topics::odom(robot->name()), dds::QosFamily::Sensor);
    topics->ground_truth = std::make_unique<dds::Writer<nm::Odometry_PubSubType>>(
        participant, dds::topics::ground_truth(robot->name()), dds::QosFamily::Sensor);
    CommandQueue& queue = simulation.commands();
    const std::string name = robot->name();
    // Runs on Fast DDS's thread: copy the numbers, queue the command, touch nothing else.
    topics->cmd_vel = std::make_unique<dds::Reader<gm::Twist_PubSubType>>(
        participant, dds::topics::cmd_vel(name), dds::QosFamily::Command,
        [&queue, name](const gm::Twist_& twist) {
          const double linear = twist.linear().x();
          const double angular = twist.angular().z();
          if (!std::isfinite(linear) || !std::isfinite(angular)) return;  // never into ODE
          queue.push([name, linear, angular](World& world) {
            if (KurtRobot* r = world.robot(name)) r->command_twist(linear, angular, world.time());
          });
        });
    robots_.push_back(std::move(topics));
  }
}

SimBridge::~SimBridge() = default;

void SimBridge::publish() {
  World& world = simulation_.world();
  const double now = world.time();
  if (now + 1e-9 >= next_clock_time_) {
    rosgraph_msgs::msg::dds_::Clock_ clock;
    clock.clock(dds::to_time(now));
    clock_->write(clock);
    next_clock_time_ += 0.01;
  }
  for (auto& topics : robots_) {
    KurtRobot* robot = world.robot(topics->name);
    if (!robot || robot->odometry_frames() == topics->published_frames) continue;
    topics->published_frames = robot->odometry_frames();
    topics->odom->write(odometry_message(robot->odometry(), now));
    topics->ground_truth->write(ground_truth_message(*robot, now));
  }
}

std::vector<std::string> SimBridge::topic_names() const {
  std::vector<std::string> names{dds::topics::kClock + " (rosgraph_msgs/Clock, out)"};
  for (const auto& topics : robots_) {
    names.push_back(dds::topics::cmd_vel(topics->name) + " (geometry_msgs/Twist, in)");
    names.push_back(dds::topics::odom(topics->name) + " (nav_msgs/Odometry, out)");
    names.push_back(dds::topics::ground_truth(topics->name) + " (nav_msgs/Odometry, out)");
  }
  return names;
}

}  // namespace macsim
