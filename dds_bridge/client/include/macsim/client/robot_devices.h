// Typed handles on a robot's devices besides its drive: the crane and its magnet, the stereo
// cameras, the laser (scans, 3D clouds, the rotating unit), the IR/sonar ranges and the IMU.
// The same topics whether a simulator or the real robot's adapter serves them.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "macsim/client/commands_sent.h"
#include "macsim/client/latest.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"

namespace macsim::client {

/// The crane's joints and its electromagnet.
class Crane {
 public:
  using State = kurt_msgs::msg::dds_::CraneState_;

  /// `reading`: the QoS family of its readers: Sensor (best effort, matches every server) or
  /// LockstepSensor (reliable: a lock-step simulator's samples, each sent once, never lost).
  Crane(dds::Participant& participant, const std::string& robot_name,
        dds::QosFamily reading = dds::QosFamily::Sensor);
  /// Joint targets: slew (rad, counter-clockwise), lift (rad, tip up), hoist (m below the tip).
  bool command(double slew, double lift, double hoist);
  /// Switches the magnet; off drops what it holds.
  bool magnet(bool on);
  /// The latest crane state (joints as measured, magnet, what it holds), if any came.
  std::optional<State> state() const { return state_.get(); }
  /// Forgets the states received so far (Latest::forget()).
  void forget() { state_.forget(); }
  /// State writers matched so far, those gone included (Latest::writers_seen()).
  int writers_seen() const { return state_.writers_seen(); }
  /// True once the robot's crane and magnet readers are matched.
  bool matched() const { return command_.matched() > 0 && magnet_.matched() > 0; }
  /// The most readers one of its command writers has matched (a killed simulator's count
  /// until its lease runs out).
  int command_readers() const { return std::max(command_.matched(), magnet_.matched()); }
  /// The fewest readers one of its command writers matched so far, those gone included.
  int command_readers_seen() const {
    return std::min(command_.readers_seen(), magnet_.readers_seen());
  }
  /// Waits until the robot received every crane and magnet command sent so far (lock-step).
  bool wait_delivered(std::chrono::milliseconds timeout = std::chrono::seconds(5));

 private:
  CommandWriter<kurt_msgs::msg::dds_::CraneCommand_PubSubType> command_;
  CommandWriter<kurt_msgs::msg::dds_::MagnetCommand_PubSubType> magnet_;
  Latest<kurt_msgs::msg::dds_::CraneState_PubSubType> state_;
};

/// One stereo pair taken at the same instant, with the pinhole calibration.
struct StereoFrame {
  double stamp = 0;       ///< s
  cv::Mat left, right;    ///< BGR, 8 bits per channel
  double focal = 0;       ///< px
  double cx = 0, cy = 0;  ///< px, principal point
  double baseline = 0;    ///< m between the optical centres (from the right camera's P)
};

/// The two cameras of a stereo pair.
class StereoCamera {
 public:
  /// `reading`: as Crane's.
  StereoCamera(dds::Participant& participant, const std::string& robot_name,
               dds::QosFamily reading = dds::QosFamily::Sensor);
  /// The newest pair whose two images share a stamp later than `after` (s), if one came.
  std::optional<StereoFrame> latest(double after = -1.0) const;
  /// Waits up to `timeout` for a pair later than `after`.
  std::optional<StereoFrame> wait(double after, std::chrono::milliseconds timeout) const;
  /// Forgets the images received so far (Latest::forget()).
  void forget() {
    left_.forget();
    right_.forget();
  }
  /// The fewest writers one of its readers matched so far, those gone included.
  int writers_seen() const {
    return std::min({left_.writers_seen(), right_.writers_seen(), right_info_.writers_seen()});
  }
  /// One eye's images as they come ("left" or "right"; anything else: std::invalid_argument).
  const Latest<sensor_msgs::msg::dds_::Image_PubSubType>& eye(const std::string& side) const;

 private:
  Latest<sensor_msgs::msg::dds_::Image_PubSubType> left_, right_;
  Latest<sensor_msgs::msg::dds_::CameraInfo_PubSubType> right_info_;
};

/// An image message as a cv::Mat (BGR; rgb8 and mono8 converted); empty if the encoding is
/// not one of bgr8, rgb8, mono8 or the sizes do not add up.
cv::Mat to_bgr(const sensor_msgs::msg::dds_::Image_& image);

/// A 3D cloud: points in the cloud's frame (base_link for the KURT).
struct Cloud {
  double stamp = 0;
  std::vector<std::array<float, 3>> points;
};

/// The laser scanner: sweeps, assembled 3D clouds, and the rotating unit it turns on.
class Laser {
 public:
  using Scan = sensor_msgs::msg::dds_::LaserScan_;

  /// `rotating`: the scanner turns on a rotating unit (scan360); otherwise fixed (scan).
  /// `reading`: as Crane's.
  Laser(dds::Participant& participant, const std::string& robot_name, bool rotating = true,
        dds::QosFamily reading = dds::QosFamily::Sensor);
  /// Turns the rotating unit at `speed` rad/s (0 stops it; a cloud comes once per turn).
  bool rotate(double speed);
  bool wait_delivered(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    return rot_vel_.wait_acknowledged(timeout);
  }
  std::optional<Scan> scan() const { return scan_.get(); }
  /// Forgets the scans and clouds received so far (Latest::forget()); clouds() goes on.
  void forget() {
    scan_.forget();
    points_.forget();
  }
  /// The fewest writers its scan or cloud reader matched so far, those gone included.
  int writers_seen() const { return std::min(scan_.writers_seen(), points_.writers_seen()); }
  /// The latest cloud with a stamp later than `after` (s), decoded, if one came.
  std::optional<Cloud> cloud(double after = -1.0) const;
  /// How many clouds came so far.
  uint64_t clouds() const { return points_.count(); }
  /// True once the robot's rotating unit reads our commands and its clouds' writer is matched.
  bool matched() const { return rot_vel_.matched() > 0 && points_.matched() > 0; }
  /// Readers its rotation command writer has matched (a killed simulator's count until its
  /// lease runs out).
  int command_readers() const { return rot_vel_.matched(); }
  /// Readers its rotation command writer matched so far, those gone included.
  int command_readers_seen() const { return rot_vel_.readers_seen(); }

 private:
  CommandWriter<geometry_msgs::msg::dds_::Twist_PubSubType> rot_vel_;
  Latest<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan_;
  Latest<sensor_msgs::msg::dds_::PointCloud2_PubSubType> points_;
};

/// A cloud message's x, y, z (FLOAT32 fields); empty if it has no such fields.
Cloud to_cloud(const sensor_msgs::msg::dds_::PointCloud2_& message);

/// The IR and sonar distance sensors, by frame.
class RangeSensors {
 public:
  /// `reading`: as Crane's.
  RangeSensors(dds::Participant& participant, const std::string& robot_name,
               dds::QosFamily reading = dds::QosFamily::Sensor);
  /// The latest reading of each sensor (m; the KURT reports -0.01 when invalid), by frame_id.
  std::map<std::string, double> latest() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, double> latest_;
  dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType> reader_;
};

/// The IMU's orientation and rates.
class Imu {
 public:
  using Data = sensor_msgs::msg::dds_::Imu_;
  /// `reading`: as Crane's.
  Imu(dds::Participant& participant, const std::string& robot_name,
      dds::QosFamily reading = dds::QosFamily::Sensor);
  std::optional<Data> latest() const { return imu_.get(); }
  /// IMU writers matched so far, those gone included.
  int writers_seen() const { return imu_.writers_seen(); }
  /// The latest yaw (rad, counter-clockwise), if any came.
  std::optional<double> yaw() const;

 private:
  Latest<sensor_msgs::msg::dds_::Imu_PubSubType> imu_;
};

/// Seconds of a message header's stamp.
double stamp_seconds(const std_msgs::msg::dds_::Header_& header);

}  // namespace macsim::client
