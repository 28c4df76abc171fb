#include "macsim/robot/robot_node.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <stdexcept>

#include "macsim/dds/convert.h"
#include "macsim/dds/kurt_messages.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/msg/std_msgsPubSubTypes.h"
#include "macsim/msg/tf2_msgsPubSubTypes.h"

namespace macsim::robot {

namespace gm = geometry_msgs::msg::dds_;
namespace km = kurt_msgs::msg::dds_;
namespace nm = nav_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;
namespace tf = tf2_msgs::msg::dds_;
namespace sd = std_msgs::msg::dds_;
using dds::QosFamily;

namespace {

/// One transform of a TF message, frames already prefixed.
gm::TransformStamped_ transform(double stamp, const std::string& parent, const std::string& child,
                                const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  gm::TransformStamped_ t;
  t.header(dds::header(stamp, parent));
  t.child_frame_id(child);
  t.transform().translation(dds::vector3(p.x(), p.y(), p.z()));
  t.transform().rotation(dds::quaternion(q.x(), q.y(), q.z(), q.w()));
  return t;
}

Eigen::Vector3d position_of(const Mount& m) {
  return {m.position[0], m.position[1], m.position[2]};
}
Eigen::Quaterniond orientation_of(const Mount& m) {
  return Eigen::Quaterniond(m.orientation[3], m.orientation[0], m.orientation[1], m.orientation[2])
      .normalized();
}

/// The prefix put before a frame id (an empty id stays empty).
std::string framed(const std::string& prefix, const std::string& frame) {
  return frame.empty() ? frame : prefix + frame;
}
template <class Message>
Message& in_frames(Message& msg, const std::string& prefix) {
  msg.header().frame_id(framed(prefix, msg.header().frame_id()));
  return msg;
}

bool finite(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

template <class T>
std::unique_ptr<dds::Writer<T>> writer_if(bool has, dds::Participant& p, const std::string& topic,
                                          QosFamily family) {
  return has ? std::make_unique<dds::Writer<T>>(p, topic, family) : nullptr;
}

/// Ground truth of base_footprint in the world frame; twist in the robot frame (as ROS does).
nm::Odometry_ ground_truth_message(const GroundTruth& g, double stamp) {
  nm::Odometry_ msg;
  msg.header(dds::header(stamp, "world"));
  msg.child_frame_id("base_footprint");
  msg.pose().pose().position(dds::point(g.position[0], g.position[1], g.position[2]));
  msg.pose().pose().orientation(
      dds::quaternion(g.orientation[0], g.orientation[1], g.orientation[2], g.orientation[3]));
  msg.twist().twist().linear(dds::vector3(g.linear[0], g.linear[1], g.linear[2]));
  msg.twist().twist().angular(dds::vector3(g.angular[0], g.angular[1], g.angular[2]));
  return msg;
}

sm::LaserScan_ scan_message(const Scan& scan, double stamp) {
  sm::LaserScan_ msg;
  msg.header(dds::header(stamp, scan.frame));
  const std::size_t n = scan.ranges.size();
  msg.angle_min(static_cast<float>(scan.angle_min));
  msg.angle_max(static_cast<float>(scan.angle_min + scan.angle_increment * (n > 0 ? n - 1 : 0)));
  msg.angle_increment(static_cast<float>(scan.angle_increment));
  msg.scan_time(static_cast<float>(scan.scan_time));
  // The mirror sweeps the beams in half a turn.
  msg.time_increment(n > 0 ? static_cast<float>(scan.scan_time / 2 / n) : 0.0f);
  msg.range_min(static_cast<float>(scan.range_min));
  msg.range_max(static_cast<float>(scan.range_max));
  msg.ranges(scan.ranges);
  return msg;
}

sm::PointCloud2_ cloud_message(const Cloud& cloud, double stamp) {
  sm::PointCloud2_ msg;
  msg.header(dds::header(stamp, "base_link"));
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
  const auto points = static_cast<uint32_t>(cloud.xyz.size() / 3);
  msg.height(1);
  msg.width(points);
  msg.point_step(12);
  msg.row_step(12 * points);
  msg.is_bigendian(false);
  msg.is_dense(true);
  msg.data().resize(std::size_t{points} * 12);
  if (points > 0) std::memcpy(msg.data().data(), cloud.xyz.data(), msg.data().size());
  return msg;
}

km::CraneState_ crane_message(const Crane& crane, double stamp) {
  km::CraneState_ msg;
  msg.header(dds::header(stamp, "base_link"));
  msg.slew(crane.slew);
  msg.lift(crane.lift);
  msg.hoist(crane.hoist);
  msg.magnet_on(crane.magnet_on);
  msg.held_object(crane.held_object);
  return msg;
}

}  // namespace

struct RobotNode::Topics {
  std::string name;
  Capabilities has;
  // Writers (what the robot has).
  dds::Writer<tf::TFMessage_PubSubType> tf, tf_static;
  dds::Writer<nm::Odometry_PubSubType> odom;
  dds::Writer<sm::JointState_PubSubType> joint_states;
  std::unique_ptr<dds::Writer<nm::Odometry_PubSubType>> ground_truth;
  std::unique_ptr<dds::Writer<sm::Range_PubSubType>> range;
  std::unique_ptr<dds::Writer<sm::Imu_PubSubType>> imu;
  std::unique_ptr<dds::Writer<sm::LaserScan_PubSubType>> scan;
  std::unique_ptr<dds::Writer<sm::PointCloud2_PubSubType>> points;
  std::unique_ptr<dds::Writer<km::CraneState_PubSubType>> crane_state;
  std::unique_ptr<dds::Writer<std_msgs::msg::dds_::String_PubSubType>> description;
  // Readers last: destroyed first, so no callback outlives what it posts into.
  std::unique_ptr<dds::Reader<gm::Twist_PubSubType>> cmd_vel, rot_vel;
  std::unique_ptr<dds::Reader<gm::TwistStamped_PubSubType>> cmd_vel_stamped;
  std::unique_ptr<dds::Reader<km::WheelSpeeds_PubSubType>> wheel_speeds;
  std::unique_ptr<dds::Reader<km::CraneCommand_PubSubType>> crane_command;
  std::unique_ptr<dds::Reader<km::MagnetCommand_PubSubType>> magnet;
  // A plug-in's own commands (Capabilities::commands).
  std::vector<std::unique_ptr<dds::Reader<sd::Float64MultiArray_PubSubType>>> own_commands;

  Topics(dds::Participant& p, const std::string& robot, const Capabilities& c, QosFamily sensors)
      : name(robot),
        has(c),
        tf(p, dds::topics::kTf, QosFamily::State),
        tf_static(p, dds::topics::kTfStatic, QosFamily::Latched),
        odom(p, dds::topics::odom(robot), QosFamily::State),
        joint_states(p, dds::topics::joint_states(robot), QosFamily::State),
        ground_truth(writer_if<nm::Odometry_PubSubType>(
            c.ground_truth, p, dds::topics::ground_truth(robot), QosFamily::State)),
        range(writer_if<sm::Range_PubSubType>(c.ranges, p, dds::topics::range(robot), sensors)),
        imu(writer_if<sm::Imu_PubSubType>(c.imu, p, dds::topics::imu(robot), QosFamily::State)),
        scan(writer_if<sm::LaserScan_PubSubType>(
            c.laser, p, dds::topics::scan(robot, c.laser_rotating), sensors)),
        points(writer_if<sm::PointCloud2_PubSubType>(c.points, p, dds::topics::points(robot),
                                                     sensors)),
        crane_state(writer_if<km::CraneState_PubSubType>(
            c.crane, p, dds::topics::crane_state(robot), QosFamily::State)) {}
};

RobotNode::RobotNode(dds::Participant& p, RobotInterface& robot, PostCommand post,
                     NodeOptions options)
    : robot_(robot),
      options_(std::move(options)),
      frames_(robot.frames()),
      topics_(std::make_unique<Topics>(p, robot.name(), robot.capabilities(), options_.sensors)),
      outbox_(std::make_unique<Outbox>()),
      held_(std::make_unique<Held>()) {
  Topics& t = *topics_;
  const std::string& name = t.name;
  if (!frames_.description.empty()) {  // once: late joiners get it from the writer's history
    t.description = std::make_unique<dds::Writer<std_msgs::msg::dds_::String_PubSubType>>(
        p, dds::topics::robot_description(name), QosFamily::Latched);
    std_msgs::msg::dds_::String_ text;
    text.data(frames_.description);
    t.description->write(text);
  }
  // On Fast DDS's threads: copy the numbers, drop what is not finite (said to `dropped`),
  // post; nothing else.
  const std::function<void(const dds::SampleId&)> dropped =
      options_.dropped ? options_.dropped : [](const dds::SampleId&) {};
  const auto post_if = [post, dropped](bool ok, RobotCommand command, const dds::SampleId& sent) {
    if (ok) {
      post(std::move(command), sent);
    } else {
      dropped(sent);
    }
  };
  auto twist = [post_if](const gm::Twist_& m, const dds::SampleId& sent) {
    const double v = m.linear().x(), w = m.angular().z();
    post_if(finite({v, w}), Twist{v, w}, sent);
  };
  if (options_.cmd_vel_stamped) {
    t.cmd_vel_stamped = std::make_unique<dds::Reader<gm::TwistStamped_PubSubType>>(
        p, dds::topics::cmd_vel(name), QosFamily::Command,
        [twist](const gm::TwistStamped_& m, const dds::SampleId& sent) { twist(m.twist(), sent); });
  } else {
    t.cmd_vel = std::make_unique<dds::Reader<gm::Twist_PubSubType>>(
        p, dds::topics::cmd_vel(name), QosFamily::Command,
        dds::Reader<gm::Twist_PubSubType>::SentCallback(twist));
  }
  t.wheel_speeds = std::make_unique<dds::Reader<km::WheelSpeeds_PubSubType>>(
      p, dds::topics::wheel_speeds(name), QosFamily::Command,
      [post_if](const km::WheelSpeeds_& m, const dds::SampleId& sent) {
        const double l = m.left(), r = m.right();
        post_if(finite({l, r}), WheelSpeedCommand{l, r}, sent);
      });
  if (t.has.rotunit) {
    t.rot_vel = std::make_unique<dds::Reader<gm::Twist_PubSubType>>(
        p, dds::topics::rot_vel(name), QosFamily::Command,
        [post_if](const gm::Twist_& m, const dds::SampleId& sent) {
          const double speed = m.angular().z();
          post_if(finite({speed}), RotunitSpeed{speed}, sent);
        });
  }
  if (t.has.crane) {
    t.crane_command = std::make_unique<dds::Reader<km::CraneCommand_PubSubType>>(
        p, dds::topics::crane_command(name), QosFamily::Command,
        [post_if](const km::CraneCommand_& m, const dds::SampleId& sent) {
          const double slew = m.slew(), lift = m.lift(), hoist = m.hoist();
          post_if(finite({slew, lift, hoist}), CraneTarget{slew, lift, hoist}, sent);
        });
  }
  if (t.has.magnet) {
    t.magnet = std::make_unique<dds::Reader<km::MagnetCommand_PubSubType>>(
        p, dds::topics::crane_magnet(name), QosFamily::Command,
        [post](const km::MagnetCommand_& m, const dds::SampleId& sent) {
          post(MagnetSwitch{m.on()}, sent);
        });
  }
  // A plug-in's own commands: each type's decoder found once, here; a sample whose numbers do
  // not fit the command (or are not finite) is dropped.
  for (const std::string& command : t.has.commands) {
    const auto decode = command_decoder(command);
    if (!decode) {
      throw std::invalid_argument("robot '" + name + "' declares the command '" + command +
                                  "', which no command type registers");
    }
    t.own_commands.push_back(std::make_unique<dds::Reader<sd::Float64MultiArray_PubSubType>>(
        p, dds::topics::robot_command(name, command), QosFamily::Command,
        [post, dropped, decode = *decode](const sd::Float64MultiArray_& m,
                                          const dds::SampleId& sent) {
          for (double v : m.data()) {
            if (!std::isfinite(v)) return dropped(sent);
          }
          if (auto c = decode(m.data())) return post(std::move(*c), sent);
          dropped(sent);
        }));
  }
}

RobotNode::~RobotNode() = default;

void RobotNode::poll_commands() {
  Topics& t = *topics_;
  if (t.cmd_vel) t.cmd_vel->poll();
  if (t.cmd_vel_stamped) t.cmd_vel_stamped->poll();
  t.wheel_speeds->poll();
  if (t.rot_vel) t.rot_vel->poll();
  if (t.crane_command) t.crane_command->poll();
  if (t.magnet) t.magnet->poll();
  for (auto& reader : t.own_commands) reader->poll();
}

/// The newest reading of each kind a held publish() kept, with its stamp.
struct RobotNode::Held {
  template <class T>
  struct Slot {
    double stamp = 0;
    std::optional<T> value;
  };
  Slot<Odometry> odometry;
  Slot<GroundTruth> ground_truth;
  Slot<Imu> imu;
  Slot<Crane> crane;
  Slot<Scan> scan;
  Slot<Rotunit> rotunit;
  Slot<Cloud> cloud;
  Slot<std::vector<Range>> ranges;
};

/// The newest message of each kind not yet written (several publish(true) calls keep only the
/// newest of each).
struct RobotNode::Outbox {
  std::optional<nm::Odometry_> odom, truth;
  std::optional<sm::JointState_> wheels, rotunit;
  std::optional<sm::Imu_> imu;
  std::vector<sm::Range_> ranges;  // of one frame
  std::optional<km::CraneState_> crane;
  std::optional<sm::LaserScan_> scan;
  std::optional<sm::PointCloud2_> cloud;
  std::vector<gm::TransformStamped_> tf_odom, tf_crane, tf_laser;
  std::optional<tf::TFMessage_> tf_static;
};

void RobotNode::remember(const Readings& r) {
  // The newest of each kind, for whoever asks (a step request's conditions).
  if (r.odometry) latest_.odometry = r.odometry;
  if (r.ground_truth) latest_.ground_truth = r.ground_truth;
  if (r.imu) latest_.imu = r.imu;
  if (!r.ranges.empty()) latest_.ranges = r.ranges;
  if (r.crane) latest_.crane = r.crane;
  if (r.scan) latest_.scan = r.scan;
  if (r.rotunit) latest_.rotunit = r.rotunit;
  latest_.stamp = r.stamp;
}

void RobotNode::prime() { remember(robot_.read()); }

void RobotNode::publish(bool hold) {
  Readings r = robot_.read();
  remember(r);
  if (!hold) {
    flush();  // what a held request kept (one cancelled by a pause) goes first: it is older
    fill(r);
    flush();
    return;
  }
  // Held: only the newest reading of each kind, with its stamp; messages are made at flush().
  Held& h = *held_;
  const double now = r.stamp;
  auto keep = [now](auto& slot, auto& value) {
    if (!value) return;
    slot.stamp = now;
    slot.value = std::move(value);
  };
  keep(h.odometry, r.odometry);
  keep(h.ground_truth, r.ground_truth);
  keep(h.imu, r.imu);
  keep(h.crane, r.crane);
  keep(h.scan, r.scan);
  keep(h.rotunit, r.rotunit);
  keep(h.cloud, r.cloud);
  if (!r.ranges.empty()) {
    h.ranges.stamp = now;
    h.ranges.value = std::move(r.ranges);
  }
}

void RobotNode::fill(const Readings& r) {
  Topics& t = *topics_;
  Outbox& out = *outbox_;
  const double now = r.stamp;
  const std::string& fp = options_.frame_prefix;
  if (r.odometry) {
    const Odometry& o = *r.odometry;
    auto odom = dds::kurt_odometry(o.x, o.y, o.yaw, o.linear, o.angular, now);
    odom.child_frame_id(framed(fp, odom.child_frame_id()));
    out.odom = in_frames(odom, fp);
    out.tf_odom = {
        transform(now, framed(fp, "odom"), framed(fp, "base_footprint"), {o.x, o.y, 0.0},
                  Eigen::Quaterniond(Eigen::AngleAxisd(o.yaw, Eigen::Vector3d::UnitZ())))};
    out.wheels = dds::kurt_wheel_joints(o.left_wheel, o.right_wheel, now);
  }
  if (r.ground_truth && t.ground_truth) {
    auto truth = ground_truth_message(*r.ground_truth, now);  // in "world": no robot's frame
    truth.child_frame_id(framed(fp, truth.child_frame_id()));
    out.truth = truth;
  }
  if (r.imu && t.imu) {
    const Imu& i = *r.imu;
    auto imu = dds::kurt_imu(i.roll, i.pitch, i.yaw, i.yaw_variance, i.yaw_rate, now);
    out.imu = in_frames(imu, fp);
  }
  if (t.range && !r.ranges.empty()) {
    out.ranges.clear();
    for (const Range& each : r.ranges) {
      auto range = dds::kurt_range(each.frame, each.sonar, each.range, now);
      out.ranges.push_back(in_frames(range, fp));
    }
  }
  if (r.crane && t.crane_state) {
    auto crane = crane_message(*r.crane, now);
    out.crane = in_frames(crane, fp);
    if (!frames_.crane_pivot.child.empty()) {
      const Crane& c = *r.crane;
      const Mount& pivot = frames_.crane_pivot;
      out.tf_crane = {
          transform(now, framed(fp, pivot.parent), framed(fp, "crane_turret"), position_of(pivot),
                    orientation_of(pivot) * Eigen::AngleAxisd(c.slew, Eigen::Vector3d::UnitZ())),
          transform(now, framed(fp, "crane_turret"), framed(fp, "crane_boom"),
                    Eigen::Vector3d::Zero(),
                    Eigen::Quaterniond(Eigen::AngleAxisd(c.lift, -Eigen::Vector3d::UnitY()))),
          transform(now, framed(fp, "crane_boom"), framed(fp, "crane_magnet"),
                    {frames_.boom_length, 0.0, -c.hoist}, Eigen::Quaterniond::Identity())};
    }
  }
  if (r.scan && t.scan) {
    auto scan = scan_message(*r.scan, now);
    out.scan = in_frames(scan, fp);
  }
  // The driver publishes the rotunit in joint_states messages of its own.
  if (r.rotunit) {
    out.rotunit = dds::kurt_rotunit_joint(r.rotunit->angle, r.rotunit->speed, now);
    const Mount& laser = frames_.laser;
    if (!laser.child.empty()) {
      out.tf_laser = {transform(
          now, framed(fp, laser.parent), framed(fp, laser.child), position_of(laser),
          Eigen::AngleAxisd(r.rotunit->angle, Eigen::Vector3d::UnitZ()) * orientation_of(laser))};
    }
  }
  if (r.cloud && t.points) {
    auto cloud = cloud_message(*r.cloud, now);
    out.cloud = in_frames(cloud, fp);
  }
  if (!static_sent_ && r.odometry) {
    // Once, in one message (tf_static keeps the last sample per writer): every fixed mount.
    tf::TFMessage_ fixed;
    for (const Mount& m : frames_.mounts) {
      fixed.transforms().push_back(transform(now, framed(fp, m.parent), framed(fp, m.child),
                                             position_of(m), orientation_of(m)));
    }
    if (!fixed.transforms().empty()) out.tf_static = fixed;
    static_sent_ = true;
  }
}

void RobotNode::flush(std::vector<std::string>* written) {
  // What publish(true) held, made into messages now, each kind with its own stamp.
  Held& h = *held_;
  auto one = [this](auto& slot, auto member) {
    if (!slot.value) return;
    Readings r;
    r.stamp = slot.stamp;
    r.*member = std::move(slot.value);
    fill(r);
    slot.value.reset();
  };
  one(h.odometry, &Readings::odometry);
  one(h.ground_truth, &Readings::ground_truth);
  one(h.imu, &Readings::imu);
  one(h.crane, &Readings::crane);
  one(h.scan, &Readings::scan);
  one(h.rotunit, &Readings::rotunit);
  one(h.cloud, &Readings::cloud);
  if (h.ranges.value) {
    Readings r;
    r.stamp = h.ranges.stamp;
    r.ranges = std::move(*h.ranges.value);
    fill(r);
    h.ranges.value.reset();
  }
  Topics& t = *topics_;
  Outbox& out = *outbox_;
  const auto write = [written](auto& writer, const auto& message) {
    writer.write(message);
    if (written &&
        std::find(written->begin(), written->end(), writer.topic_name()) == written->end())
      written->push_back(writer.topic_name());
  };
  if (out.odom) write(t.odom, *out.odom);
  if (out.truth) write(*t.ground_truth, *out.truth);
  if (out.wheels) write(t.joint_states, *out.wheels);
  if (out.imu) write(*t.imu, *out.imu);
  for (const auto& range : out.ranges) write(*t.range, range);
  if (out.crane) write(*t.crane_state, *out.crane);
  if (out.scan) write(*t.scan, *out.scan);
  if (out.rotunit) write(t.joint_states, *out.rotunit);
  if (out.cloud) write(*t.points, *out.cloud);
  tf::TFMessage_ moving;
  for (auto* part : {&out.tf_odom, &out.tf_crane, &out.tf_laser}) {
    for (auto& each : *part) moving.transforms().push_back(std::move(each));
  }
  if (!moving.transforms().empty()) write(t.tf, moving);
  if (out.tf_static) write(t.tf_static, *out.tf_static);
  out = Outbox{};
}

namespace {
struct TopicLine {
  bool served;
  std::string topic;
  const char* what;
};

std::vector<TopicLine> topic_table(const std::string& n, const Capabilities& c, bool stamped,
                                   bool described) {
  return {{true, dds::topics::kTf, "tf2_msgs/TFMessage, out"},
          {true, dds::topics::kTfStatic, "tf2_msgs/TFMessage, transient local, out"},
          {true, dds::topics::cmd_vel(n),
           stamped ? "geometry_msgs/TwistStamped, in" : "geometry_msgs/Twist, in"},
          {true, dds::topics::wheel_speeds(n), "kurt_msgs/WheelSpeeds, in"},
          {c.rotunit, dds::topics::rot_vel(n), "geometry_msgs/Twist, in"},
          {c.crane, dds::topics::crane_command(n), "kurt_msgs/CraneCommand, in"},
          {c.magnet, dds::topics::crane_magnet(n), "kurt_msgs/MagnetCommand, in"},
          {true, dds::topics::odom(n), "nav_msgs/Odometry, out"},
          {c.ground_truth, dds::topics::ground_truth(n), "nav_msgs/Odometry, out"},
          {true, dds::topics::joint_states(n), "sensor_msgs/JointState, out"},
          {c.ranges, dds::topics::range(n), "sensor_msgs/Range, out"},
          {c.imu, dds::topics::imu(n), "sensor_msgs/Imu, out"},
          {c.laser, dds::topics::scan(n, c.laser_rotating), "sensor_msgs/LaserScan, out"},
          {c.points, dds::topics::points(n), "sensor_msgs/PointCloud2, out"},
          {c.crane, dds::topics::crane_state(n), "kurt_msgs/CraneState, out"},
          {described, dds::topics::robot_description(n), "std_msgs/String, transient local, out"}};
}
}  // namespace

std::vector<std::string> RobotNode::topic_lines() const {
  std::vector<std::string> lines;
  for (const auto& line : topic_table(topics_->name, topics_->has, options_.cmd_vel_stamped,
                                      !frames_.description.empty())) {
    if (line.served) lines.push_back(line.topic + " (" + line.what + ")");
  }
  for (const auto& command : topics_->has.commands) {
    lines.push_back(dds::topics::robot_command(topics_->name, command) +
                    " (std_msgs/Float64MultiArray, in)");
  }
  return lines;
}

std::vector<std::string> RobotNode::lacking_topics() const {
  Capabilities full;
  full.ground_truth = full.ranges = full.imu = full.rotunit = full.laser = full.laser_rotating =
      full.points = full.crane = full.magnet = true;
  std::vector<std::string> lacking;
  const auto served = topic_table(topics_->name, topics_->has, options_.cmd_vel_stamped,
                                  !frames_.description.empty());
  const auto all = topic_table(topics_->name, full, options_.cmd_vel_stamped, true);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!served[i].served) lacking.push_back(all[i].topic);
  }
  return lacking;
}

}  // namespace macsim::robot
