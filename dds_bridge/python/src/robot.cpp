// macsim.Robot: one KURT3D's topics (drive, odometry, sensors, cameras, laser, crane) through
// the client library. Images and clouds become numpy arrays without a copy of their own.
#include <pybind11/numpy.h>

#include <memory>
#include <thread>

#include "bindings.h"
#include "macsim/client/robot_client.h"
#include "macsim/client/robot_devices.h"
#include "macsim/dds/topics.h"

namespace macsim::python {

namespace {

namespace sm = sensor_msgs::msg::dds_;
using Ms = std::chrono::milliseconds;

/// A read-only H x W x 3 BGR view of an image message that keeps the message alive; rgb8 and
/// mono8 are viewed as BGR through strides (no copy either).
py::array bgr_view(std::shared_ptr<const sm::Image_> image) {
  const auto& encoding = image->encoding();
  const py::ssize_t rows = image->height(), cols = image->width(), step = image->step();
  const int channels = encoding == "mono8" ? 1 : (encoding == "bgr8" || encoding == "rgb8") ? 3 : 0;
  if (channels == 0)
    throw py::value_error("an image of encoding '" + encoding +
                          "': only bgr8, rgb8 and mono8 are read");
  if (rows <= 0 || cols <= 0 || step < cols * channels ||
      image->data().size() < static_cast<std::size_t>(step * rows)) {
    throw py::value_error("an image whose sizes do not add up (" + std::to_string(cols) + "x" +
                          std::to_string(rows) + ", step " + std::to_string(step) + ", " +
                          std::to_string(image->data().size()) + " bytes)");
  }
  auto* data = const_cast<uint8_t*>(image->data().data());
  std::vector<py::ssize_t> strides{step, channels, 1};
  if (encoding == "rgb8") {
    data += 2;  // blue is the third byte: walk the channels backwards
    strides[2] = -1;
  } else if (encoding == "mono8") {
    strides[2] = 0;  // one grey byte, seen three times
  }
  auto* owner = new std::shared_ptr<const sm::Image_>(std::move(image));
  py::capsule keep(owner,
                   [](void* p) { delete static_cast<std::shared_ptr<const sm::Image_>*>(p); });
  py::array view(py::dtype::of<uint8_t>(), {rows, cols, py::ssize_t{3}}, strides, data, keep);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

/// One camera image and when it was taken.
struct CameraImage {
  double stamp;          ///< s
  std::string frame_id;  ///< the camera's optical frame
  py::array image;       ///< H x W x 3 uint8, BGR, read-only
};

/// Every handle on one robot's topics.
struct PythonRobot {
  PythonRobot(PythonParticipant& p, const std::string& robot_name, bool rotating_laser,
              bool lockstep)
      : domain(p.domain),
        drive(p.dds, robot_name, dds::sensor_family(lockstep)),
        crane(p.dds, robot_name, dds::sensor_family(lockstep)),
        cameras(p.dds, robot_name, dds::sensor_family(lockstep)),
        laser(p.dds, robot_name, rotating_laser, dds::sensor_family(lockstep)),
        ranges(p.dds, robot_name, dds::sensor_family(lockstep)),
        imu(p.dds, robot_name, dds::sensor_family(lockstep)) {}

  /// "no X from robot 'kurt' on DDS domain 7 within 2 s: ..."
  [[noreturn]] void raise_nothing(const std::string& what, double timeout) const {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%g", timeout);
    raise_timeout("no " + what + " from robot '" + drive.robot_name() + "' on DDS domain " +
                  std::to_string(domain) + " within " + seconds +
                  " s: is macsim (or kurt_adapter) running with the same --domain and DDS "
                  "profile?");
  }

  /// `get()` now; when it has nothing and `timeout` > 0, asks again every 2 ms until it has,
  /// and raises TimeoutError after `timeout`.
  template <class Get>
  auto fetch(Get get, double timeout, const std::string& what) -> decltype(get()) {
    auto value = get();
    if (value || timeout == 0) return value;
    wait_interruptibly(to_milliseconds(timeout), [&](Ms slice) {
      const auto end = std::chrono::steady_clock::now() + slice;
      do {
        if ((value = get())) return true;
        std::this_thread::sleep_for(Ms(2));
      } while (std::chrono::steady_clock::now() < end);
      return false;
    });
    if (!value) raise_nothing(what, timeout);
    return value;
  }

  /// The newest image of one eye later than `after` as a BGR view, waiting up to `timeout`.
  CameraImage camera_image(const std::string& side, double after, double timeout) {
    const auto& eye = cameras.eye(side);
    std::shared_ptr<const sm::Image_> image = eye.get_shared();
    auto fresh = [&] { return image && client::stamp_seconds(image->header()) > after; };
    if (!fresh()) {
      wait_interruptibly(to_milliseconds(timeout), [&](Ms slice) {
        const auto end = std::chrono::steady_clock::now() + slice;
        while (true) {
          const uint64_t seen = eye.count();
          image = eye.get_shared();
          if (fresh()) return true;
          const auto now = std::chrono::steady_clock::now();
          if (now >= end) return false;
          eye.wait_shared_after(seen, std::chrono::duration_cast<Ms>(end - now) + Ms(1));
        }
      });
    }
    if (!fresh()) raise_nothing(side + " image", timeout);
    const double stamp = client::stamp_seconds(image->header());
    std::string frame_id = image->header().frame_id();
    return {stamp, std::move(frame_id), bgr_view(std::move(image))};
  }

  int domain;
  client::RobotClient drive;
  client::Crane crane;
  client::StereoCamera cameras;
  client::Laser laser;
  client::RangeSensors ranges;
  client::Imu imu;
};

/// A cv::Mat (8-bit, 1 or 3 channels) as a numpy array sharing its pixels.
py::array mat_view(const cv::Mat& mat) {
  auto* owner = new cv::Mat(mat);
  py::capsule keep(owner, [](void* p) { delete static_cast<cv::Mat*>(p); });
  return py::array(
      py::dtype::of<uint8_t>(),
      {py::ssize_t{mat.rows}, py::ssize_t{mat.cols}, py::ssize_t{mat.channels()}},
      {static_cast<py::ssize_t>(mat.step[0]), py::ssize_t{mat.channels()}, py::ssize_t{1}},
      mat.data, keep);
}

/// A cloud's points as an N x 3 float32 array owning the decoded vector.
}  // namespace

py::array points_array(client::Cloud cloud) {
  auto* owner = new std::vector<std::array<float, 3>>(std::move(cloud.points));
  py::capsule keep(owner,
                   [](void* p) { delete static_cast<std::vector<std::array<float, 3>>*>(p); });
  return py::array_t<float>({static_cast<py::ssize_t>(owner->size()), py::ssize_t{3}},
                            owner->empty() ? nullptr : owner->front().data(), keep);
}

void bind_robot(py::module_& m) {
  py::class_<CameraImage>(m, "CameraImage", "One camera image and when it was taken.")
      .def_readonly("stamp", &CameraImage::stamp, "s of sim (or robot) time")
      .def_readonly("frame_id", &CameraImage::frame_id, "the camera's optical frame")
      .def_readonly("image", &CameraImage::image,
                    "H x W x 3 uint8, BGR, read-only (a view of the received sample)");

  py::class_<client::StereoFrame>(m, "StereoFrame",
                                  "A stereo pair of one instant and its pinhole calibration.")
      .def_readonly("stamp", &client::StereoFrame::stamp, "s of sim (or robot) time")
      .def_property_readonly(
          "left", [](const client::StereoFrame& f) { return mat_view(f.left); },
          "H x W x 3 uint8, BGR")
      .def_property_readonly(
          "right", [](const client::StereoFrame& f) { return mat_view(f.right); },
          "H x W x 3 uint8, BGR")
      .def_readonly("focal", &client::StereoFrame::focal, "px")
      .def_readonly("cx", &client::StereoFrame::cx, "px, principal point")
      .def_readonly("cy", &client::StereoFrame::cy, "px, principal point")
      .def_readonly("baseline", &client::StereoFrame::baseline, "m between the optical centres");

  py::class_<PythonRobot>(m, "Robot",
                          "One KURT3D over DDS: the same topics whether macsim or the real "
                          "robot's kurt_adapter serves them.")
      .def(py::init<PythonParticipant&, const std::string&, bool, bool>(), py::arg("participant"),
           py::arg("name") = "kurt", py::arg("rotating_laser") = true, py::arg("lockstep") = false,
           py::keep_alive<1, 2>(),
           "Handles on robot `name`'s topics. `rotating_laser`: the scanner turns on the "
           "rotating unit (scan360), else it is fixed (scan). `lockstep`: its data is read "
           "reliably, as a lock-step simulator (macsim --lockstep) sends it, each sample once: "
           "none is lost on a network (a real-time simulator's or the real robot's sensors are "
           "then not heard).")
      .def_property_readonly("name", [](const PythonRobot& r) { return r.drive.robot_name(); })
      .def(
          "topic",
          [](const PythonRobot& r, const std::string& name) {
            return dds::topics::robot(r.drive.robot_name(), name);
          },
          py::arg("name"),
          "The DDS name of this robot's topic `name` (e.g. 'points' -> 'rt/kurt/points'), as a "
          "step's published lists it.")
      .def_property_readonly(
          "connected", [](const PythonRobot& r) { return r.drive.commander_matched(); },
          "True once a participant serving this robot's cmd_vel is matched.")
      .def_property_readonly(
          "crane_connected", [](const PythonRobot& r) { return r.crane.matched(); },
          "True once the robot's crane and magnet readers are matched.")
      .def(
          "cmd_vel",
          [](PythonRobot& r, double linear, double angular) {
            return r.drive.drive(linear, angular);
          },
          py::arg("linear"), py::arg("angular"),
          "Velocity command: m/s forward, rad/s counter-clockwise. The robot stops by itself "
          "0.6 s after the last command: repeat it while moving.")
      .def(
          "wheel_speeds",
          [](PythonRobot& r, double left, double right) {
            return r.drive.drive_wheels(left, right);
          },
          py::arg("left"), py::arg("right"),
          "Wheel rim speeds, m/s (the same 0.6 s timeout as cmd_vel).")
      .def(
          "stop", [](PythonRobot& r) { return r.drive.stop(); }, "A zero velocity command.")
      .def(
          "wait_delivered",
          [](PythonRobot& r, double timeout) {
            const auto t = to_milliseconds(timeout);
            py::gil_scoped_release release;
            return r.drive.wait_delivered(t) && r.crane.wait_delivered(t) &&
                   r.laser.wait_delivered(t);
          },
          py::arg("timeout") = 5.0,
          "Waits until the robot received every command sent so far; False after `timeout` s. "
          "Lock-step needs no such wait: a step request names the commands sent before it and "
          "the simulator waits for them.")
      .def(
          "odometry",
          [](PythonRobot& r, double timeout) {
            std::optional<client::RobotClient::Odometry> odometry;
            wait_interruptibly(to_milliseconds(timeout), [&](Ms slice) {
              return (odometry = r.drive.wait_for_odometry(slice)).has_value();
            });
            if (!odometry) r.raise_nothing("odometry", timeout);
            return *odometry;
          },
          py::arg("timeout") = 5.0,
          "Waits for an odometry newer than the last one returned; TimeoutError after "
          "`timeout` s.")
      .def(
          "latest_odometry", [](const PythonRobot& r) { return r.drive.latest_odometry(); },
          "The latest odometry received, or None.")
      .def(
          "ranges", [](const PythonRobot& r) { return r.ranges.latest(); },
          "The latest IR/sonar readings by frame id, m (the KURT reports -0.01 when invalid).")
      .def(
          "imu",
          [](PythonRobot& r, double timeout) {
            return r.fetch([&] { return r.imu.latest(); }, timeout, "IMU data");
          },
          py::arg("timeout") = 0.0,
          "The latest IMU data; None if none came (timeout 0), else waits up to `timeout` s "
          "and raises TimeoutError.")
      .def(
          "scan",
          [](PythonRobot& r, double after, double timeout) {
            return r.fetch(
                [&]() -> std::optional<client::Laser::Scan> {
                  auto scan = r.laser.scan();
                  if (scan && client::stamp_seconds(scan->header()) > after) return scan;
                  return std::nullopt;
                },
                timeout, "laser scan");
          },
          py::arg("after") = -1.0, py::arg("timeout") = 0.0,
          "The latest sweep stamped later than `after` (s); None if none (timeout 0), else "
          "waits up to `timeout` s and raises TimeoutError.")
      .def(
          "points",
          [](PythonRobot& r, double after, double timeout) -> std::optional<py::array> {
            auto cloud = r.fetch([&] { return r.laser.cloud(after); }, timeout, "3D cloud");
            if (!cloud) return std::nullopt;
            return points_array(std::move(*cloud));
          },
          py::arg("after") = -1.0, py::arg("timeout") = 0.0,
          "The latest 3D cloud stamped later than `after` (s), as an N x 3 float32 array in "
          "base_link (m); None if none (timeout 0), else waits and raises TimeoutError.")
      .def(
          "camera",
          [](PythonRobot& r, const std::string& side, double after, double timeout) {
            return r.camera_image(side, after, timeout);
          },
          py::arg("side") = "left", py::arg("after") = -1.0, py::arg("timeout") = 5.0,
          "The newest image of camera `side` ('left' or 'right') stamped later than `after` "
          "(s), with its stamp; waits up to `timeout` s, then TimeoutError.")
      .def(
          "image",
          [](PythonRobot& r, const std::string& side, double after, double timeout) {
            return r.camera_image(side, after, timeout).image;
          },
          py::arg("side") = "left", py::arg("after") = -1.0, py::arg("timeout") = 5.0,
          "The newest image of camera `side` ('left' or 'right') stamped later than `after` "
          "(s), as a read-only H x W x 3 uint8 BGR array sharing the received sample "
          "(.copy() to draw on it); waits up to `timeout` s, then TimeoutError.")
      .def(
          "stereo",
          [](PythonRobot& r, double after, double timeout) {
            std::optional<client::StereoFrame> frame = r.cameras.latest(after);
            if (!frame) {
              wait_interruptibly(to_milliseconds(timeout), [&](Ms slice) {
                return (frame = r.cameras.wait(after, slice)).has_value();
              });
            }
            if (!frame) r.raise_nothing("stereo pair", timeout);
            return *frame;
          },
          py::arg("after") = -1.0, py::arg("timeout") = 5.0,
          "The newest stereo pair of one instant later than `after` (s), with its "
          "calibration; waits up to `timeout` s, then TimeoutError.")
      .def(
          "crane",
          [](PythonRobot& r, double slew, double lift, double hoist) {
            return r.crane.command(slew, lift, hoist);
          },
          py::arg("slew"), py::arg("lift"), py::arg("hoist"),
          "Crane joint targets: slew (rad, counter-clockwise), lift (rad, tip up), hoist (m "
          "below the tip).")
      .def(
          "magnet", [](PythonRobot& r, bool on) { return r.crane.magnet(on); }, py::arg("on"),
          "Switches the crane's magnet; off drops what it holds.")
      .def(
          "crane_state",
          [](PythonRobot& r, double timeout) {
            return r.fetch([&] { return r.crane.state(); }, timeout, "crane state");
          },
          py::arg("timeout") = 0.0,
          "The latest crane state; None if none came (timeout 0), else waits up to `timeout` "
          "s and raises TimeoutError.")
      .def(
          "rotate_laser", [](PythonRobot& r, double speed) { return r.laser.rotate(speed); },
          py::arg("speed"),
          "Turns the laser's rotating unit at `speed` rad/s (0 stops it; a cloud comes once "
          "per turn).")
      .def("__repr__", [](const PythonRobot& r) {
        return "<macsim.Robot '" + r.drive.robot_name() + "' domain=" + std::to_string(r.domain) +
               ">";
      });
}

}  // namespace macsim::python
