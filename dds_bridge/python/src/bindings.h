// What the binding's files share: seconds to durations, waits that let Python run and hear
// Ctrl-C, tuples for the wire types' vectors, and the functions that bind each part.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <tuple>

#include "macsim/client/robot_devices.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/geometry_msgs.h"

namespace macsim::python {

namespace py = pybind11;

using Vec3 = std::tuple<double, double, double>;
using Quat = std::tuple<double, double, double, double>;  ///< x, y, z, w (ROS order)

/// A DDS participant as Python holds it: the handles made on it keep it alive.
struct PythonParticipant {
  explicit PythonParticipant(const dds::ParticipantOptions& options)
      : domain(options.domain), dds(options) {}
  int domain;
  dds::Participant dds;
};

/// A timeout in seconds (finite, >= 0) as milliseconds; ValueError naming `what` otherwise.
std::chrono::milliseconds to_milliseconds(double seconds, const char* what = "timeout");

/// True if a signal handler raised (Ctrl-C: KeyboardInterrupt); takes the GIL to ask.
bool python_interrupted();

/// Raises the pending Python error (after python_interrupted() said so).
[[noreturn]] void raise_pending();

/// Raises TimeoutError with `message`.
[[noreturn]] void raise_timeout(const std::string& message);
/// The KURT3D's description, its numbers by name (macsim.kurt3d_description()).
py::dict kurt3d_description();

/// Calls `wait(slice)` with the GIL released, in slices of at most 50 ms, until it returns
/// true (then true) or `timeout` passed (then false); Ctrl-C between slices raises.
template <class Wait>
bool wait_interruptibly(std::chrono::milliseconds timeout, Wait&& wait) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    const auto slice =
        std::clamp(left, std::chrono::milliseconds(0), std::chrono::milliseconds(50));
    {
      py::gil_scoped_release release;
      if (wait(slice)) return true;
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (left <= std::chrono::milliseconds(0)) return false;
  }
}

inline Vec3 vec3(const geometry_msgs::msg::dds_::Point_& p) { return {p.x(), p.y(), p.z()}; }
inline Vec3 vec3(const geometry_msgs::msg::dds_::Vector3_& v) { return {v.x(), v.y(), v.z()}; }
inline Quat quat(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return {q.x(), q.y(), q.z(), q.w()};
}

/// A 3D cloud as an N x 3 float32 array (m, base_link) owning its points.
py::array points_array(client::Cloud cloud);

void bind_wire_types(py::module_& m);
void bind_robot(py::module_& m);
void bind_supervisor(py::module_& m);
void bind_affordances(py::module_& m);

}  // namespace macsim::python
