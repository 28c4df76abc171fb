#include "macsim/client/robot_devices.h"

#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"

namespace macsim::client {

namespace km = kurt_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;

double stamp_seconds(const std_msgs::msg::dds_::Header_& header) {
  return dds::to_seconds(header.stamp());
}

// ---- crane ---------------------------------------------------------------------------------

Crane::Crane(dds::Participant& participant, const std::string& robot_name, dds::QosFamily reading)
    : command_(participant, dds::topics::crane_command(robot_name)),
      magnet_(participant, dds::topics::crane_magnet(robot_name)),
      state_(participant, dds::topics::crane_state(robot_name), reading) {}

bool Crane::command(double slew, double lift, double hoist) {
  km::CraneCommand_ c;
  c.slew(slew);
  c.lift(lift);
  c.hoist(hoist);
  return command_.write(c);
}

bool Crane::magnet(bool on) {
  km::MagnetCommand_ c;
  c.on(on);
  return magnet_.write(c);
}

bool Crane::wait_delivered(std::chrono::milliseconds timeout) {
  return command_.wait_acknowledged(timeout) && magnet_.wait_acknowledged(timeout);
}

// ---- cameras -------------------------------------------------------------------------------

cv::Mat to_bgr(const sm::Image_& image) {
  const int rows = static_cast<int>(image.height()), cols = static_cast<int>(image.width());
  const std::string& encoding = image.encoding();
  const int channels = encoding == "mono8" ? 1 : (encoding == "bgr8" || encoding == "rgb8") ? 3 : 0;
  if (channels == 0 || rows <= 0 || cols <= 0 ||
      image.step() < static_cast<uint32_t>(cols * channels) ||
      image.data().size() < static_cast<std::size_t>(image.step()) * rows) {
    return {};
  }
  const cv::Mat view(rows, cols, channels == 1 ? CV_8UC1 : CV_8UC3,
                     const_cast<uint8_t*>(image.data().data()), image.step());
  cv::Mat bgr;
  if (encoding == "bgr8") {
    bgr = view.clone();
  } else {
    cv::cvtColor(view, bgr, encoding == "rgb8" ? cv::COLOR_RGB2BGR : cv::COLOR_GRAY2BGR);
  }
  return bgr;
}

StereoCamera::StereoCamera(dds::Participant& participant, const std::string& robot_name,
                           dds::QosFamily reading)
    : left_(participant, dds::topics::image(robot_name, "left"), reading),
      right_(participant, dds::topics::image(robot_name, "right"), reading),
      right_info_(participant, dds::topics::camera_info(robot_name, "right"), reading) {}

std::optional<StereoFrame> StereoCamera::latest(double after) const {
  const auto left = left_.get();
  const auto right = right_.get();
  const auto info = right_info_.get();
  if (!left || !right || !info) return std::nullopt;
  const double stamp = stamp_seconds(left->header());
  if (stamp <= after || std::fabs(stamp - stamp_seconds(right->header())) > 1e-6) {
    return std::nullopt;
  }
  StereoFrame frame;
  frame.stamp = stamp;
  frame.left = to_bgr(*left);
  frame.right = to_bgr(*right);
  const auto& p = info->p();
  frame.focal = p[0];
  frame.cx = p[2];
  frame.cy = p[6];
  frame.baseline = frame.focal > 0 ? -p[3] / frame.focal : 0.0;
  if (frame.left.empty() || frame.right.empty() || frame.focal <= 0 || frame.baseline <= 0) {
    return std::nullopt;
  }
  return frame;
}

const Latest<sm::Image_PubSubType>& StereoCamera::eye(const std::string& side) const {
  if (side == "left") return left_;
  if (side == "right") return right_;
  throw std::invalid_argument("a camera is \"left\" or \"right\", not \"" + side + "\"");
}

std::optional<StereoFrame> StereoCamera::wait(double after,
                                              std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (auto frame = latest(after)) return frame;
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return std::nullopt;
    const auto left_seen = left_.count(), right_seen = right_.count();
    // Whichever eye is behind brings the pair together when it arrives.
    if (!left_.wait_after(left_seen, std::chrono::milliseconds(5)))
      right_.wait_after(right_seen, std::chrono::duration_cast<std::chrono::milliseconds>(
                                        std::min<std::chrono::steady_clock::duration>(
                                            deadline - now, std::chrono::milliseconds(20))));
  }
}

// ---- laser ---------------------------------------------------------------------------------

Laser::Laser(dds::Participant& participant, const std::string& robot_name, bool rotating,
             dds::QosFamily reading)
    : rot_vel_(participant, dds::topics::rot_vel(robot_name)),
      scan_(participant, dds::topics::scan(robot_name, rotating), reading),
      points_(participant, dds::topics::points(robot_name), reading) {}

bool Laser::rotate(double speed) { return rot_vel_.write(dds::planar_twist(0.0, speed)); }

std::optional<Cloud> Laser::cloud(double after) const {
  const auto message = points_.get();
  if (!message || stamp_seconds(message->header()) <= after) return std::nullopt;
  return to_cloud(*message);
}

Cloud to_cloud(const sm::PointCloud2_& message) {
  Cloud cloud;
  cloud.stamp = stamp_seconds(message.header());
  std::array<int, 3> offset{-1, -1, -1};
  for (const auto& field : message.fields()) {
    const int axis = field.name() == "x"   ? 0
                     : field.name() == "y" ? 1
                     : field.name() == "z" ? 2
                                           : -1;
    if (axis >= 0 && field.datatype() == 7 /* FLOAT32 */)
      offset[axis] = static_cast<int>(field.offset());
  }
  const std::size_t step = message.point_step();
  const std::size_t count = std::size_t{message.width()} * message.height();
  if (offset[0] < 0 || offset[1] < 0 || offset[2] < 0 || message.is_bigendian() || step < 12 ||
      message.data().size() < count * step) {
    return cloud;
  }
  cloud.points.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (static_cast<std::size_t>(offset[a]) + 4 > step) return Cloud{cloud.stamp, {}};
      std::memcpy(&cloud.points[i][a], message.data().data() + i * step + offset[a], 4);
    }
  }
  return cloud;
}

// ---- ranges and IMU ------------------------------------------------------------------------

RangeSensors::RangeSensors(dds::Participant& participant, const std::string& robot_name,
                           dds::QosFamily reading)
    : reader_(participant, dds::topics::range(robot_name), reading, [this](const sm::Range_& r) {
        std::lock_guard<std::mutex> lock(mutex_);
        latest_[r.header().frame_id()] = r.range();
      }) {}

std::map<std::string, double> RangeSensors::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

Imu::Imu(dds::Participant& participant, const std::string& robot_name, dds::QosFamily reading)
    : imu_(participant, dds::topics::imu(robot_name), reading) {}

std::optional<double> Imu::yaw() const {
  const auto imu = imu_.get();
  if (!imu) return std::nullopt;
  const auto& q = imu->orientation();
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

}  // namespace macsim::client
