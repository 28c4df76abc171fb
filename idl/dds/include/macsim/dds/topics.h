// Topic names of MACSim-DDS, in the ROS 2 convention (rt/ prefix, robot namespace).
#pragma once

#include <string>

namespace macsim::dds::topics {

/// The simulation clock (rosgraph_msgs/Clock).
inline const std::string kClock = "rt/clock";

/// The frames of every robot (tf2_msgs/TFMessage): moving ones on tf, fixed ones on tf_static
/// (transient local: a late tf2 listener still gets them).
inline const std::string kTf = "rt/tf";
inline const std::string kTfStatic = "rt/tf_static";

/// The supervisor's requests and replies (macsim_msgs/SupervisorRequest, SupervisorReply).
inline const std::string kSupervisorRequest = "rt/macsim/supervisor/request";
inline const std::string kSupervisorReply = "rt/macsim/supervisor/reply";
/// The world state, one instance per object id (macsim_msgs/ObjectState; disposed = destroyed).
inline const std::string kWorldObjects = "rt/macsim/world/objects";
/// Door and switch states, one instance per door (macsim_msgs/DoorState).
inline const std::string kWorldDoors = "rt/macsim/world/doors";
/// Events: switch triggered, door opened, object attached, penetration, ...
/// (macsim_msgs/WorldEvent).
inline const std::string kWorldEvents = "rt/macsim/world/events";

/// The world state as unkeyed, ROS-stamped samples, for ROS 2 nodes: every object (every door)
/// in one sample each 0.1 s of sim time (macsim_msgs/ObjectList, DoorList), latched; events
/// with a header (macsim_msgs/Event).
inline const std::string kWorldObjectList = "rt/macsim/world/object_list";
inline const std::string kWorldDoorList = "rt/macsim/world/door_list";
inline const std::string kWorldEventsStamped = "rt/macsim/world/events_stamped";

/// Simulation control: pause, run, real-time factor, lock-step, load world, features.
inline const std::string kSimulationRequest = "rt/macsim/simulation/request";
inline const std::string kSimulationReply = "rt/macsim/simulation/reply";

/// Overview pictures of the simulation (macsim_msgs/PictureRequest, PictureReply).
inline const std::string kPictureRequest = "rt/macsim/picture/request";
inline const std::string kPictureReply = "rt/macsim/picture/reply";

/// rt/<robot>/<name>: a topic of one robot.
inline std::string robot(const std::string& robot_name, const std::string& name) {
  return "rt/" + robot_name + "/" + name;
}

/// Velocity command (geometry_msgs/Twist), as the real driver's cmd_vel.
inline std::string cmd_vel(const std::string& robot_name) { return robot(robot_name, "cmd_vel"); }
/// Wheel odometry (nav_msgs/Odometry), as the real driver computes it from encoder ticks.
inline std::string odom(const std::string& robot_name) { return robot(robot_name, "odom"); }
/// The robot's description as text (std_msgs/String, transient local).
inline std::string robot_description(const std::string& robot_name) {
  return robot(robot_name, "robot_description");
}
/// Simulator-only ground truth pose and velocity of base_footprint (nav_msgs/Odometry).
inline std::string ground_truth(const std::string& robot_name) {
  return robot(robot_name, "ground_truth");
}

/// IR and ultrasound readings (sensor_msgs/Range), one topic told apart by frame_id.
inline std::string range(const std::string& r) { return robot(r, "range"); }
/// Gyro yaw and rates (sensor_msgs/Imu).
inline std::string imu(const std::string& r) { return robot(r, "imu"); }
/// Wheel joints, and laser_rot_joint in messages of its own (sensor_msgs/JointState).
inline std::string joint_states(const std::string& r) { return robot(r, "joint_states"); }
/// Sweeps of the LMS200: "scan" when fixed, "scan360" on the rotating unit (sensor_msgs/LaserScan).
inline std::string scan(const std::string& r, bool rotating) {
  return robot(r, rotating ? "scan360" : "scan");
}
/// Assembled 3D clouds of one rotunit revolution, in base_link (sensor_msgs/PointCloud2).
inline std::string points(const std::string& r) { return robot(r, "points"); }
/// Left and right wheel speeds in m/s (kurt_msgs/WheelSpeeds), instead of a twist.
inline std::string wheel_speeds(const std::string& r) { return robot(r, "wheel_speeds"); }
/// Rotating unit speed in angular.z, rad/s (geometry_msgs/Twist), as the real driver's rot_vel.
inline std::string rot_vel(const std::string& r) { return robot(r, "rot_vel"); }
/// Crane joint targets (kurt_msgs/CraneCommand).
inline std::string crane_command(const std::string& r) { return robot(r, "crane/command"); }
/// The crane's magnet on/off (kurt_msgs/MagnetCommand).
inline std::string crane_magnet(const std::string& r) { return robot(r, "crane/magnet"); }
/// A robot plug-in's own command `name` (idl/robot/robot_command.h).
inline std::string robot_command(const std::string& r, const std::string& name) {
  return robot(r, "command/" + name);
}
/// Crane joints, magnet and what it holds (kurt_msgs/CraneState).
inline std::string crane_state(const std::string& r) { return robot(r, "crane/state"); }
/// The plan a controller acts on (plan_msgs/Plan_, latched): its steps, the one under way, the things it judged.
inline std::string plan(const std::string& r) { return robot(r, "plan"); }
/// A stereo camera's images and calibration; side is "left" or "right".
inline std::string image(const std::string& r, const std::string& side) {
  return robot(r, "camera/" + side + "/image_raw");
}
inline std::string camera_info(const std::string& r, const std::string& side) {
  return robot(r, "camera/" + side + "/camera_info");
}

}  // namespace macsim::dds::topics
