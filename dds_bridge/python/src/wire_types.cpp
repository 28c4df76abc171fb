// The wire types a Python user reads (and the one it builds, Component), as Python classes
// with read-only attributes in SI units: vectors as (x, y, z), orientations as (x, y, z, w).
#include <pybind11/numpy.h>

#include <cmath>
#include <initializer_list>
#include <sstream>

#include "bindings.h"
#include "macsim/client/robot_devices.h"
#include "macsim/msg/kurt_msgs.h"
#include "macsim/msg/macsim_msgs.h"
#include "macsim/msg/nav_msgs.h"
#include "macsim/msg/sensor_msgs.h"

namespace macsim::python {

namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;

double yaw_of(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

template <class T, std::size_t N>
std::array<T, N> array_of(const py::sequence& values, const char* what) {
  if (py::len(values) != N) {
    throw py::value_error(std::string(what) + " needs " + std::to_string(N) + " numbers, not " +
                          std::to_string(py::len(values)));
  }
  std::array<T, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = values[i].cast<T>();
  return out;
}

std::string format_vec(const Vec3& v) {
  std::ostringstream out;
  out << "(" << std::get<0>(v) << ", " << std::get<1>(v) << ", " << std::get<2>(v) << ")";
  return out.str();
}

}  // namespace

void bind_wire_types(py::module_& m) {
  // Constants: the wire's values (macsim_msgs.idl), under the same names.
  m.attr("SHAPE_BOX") = mm::SHAPE_BOX;
  m.attr("SHAPE_CYLINDER") = mm::SHAPE_CYLINDER;
  m.attr("SHAPE_SPHERE") = mm::SHAPE_SPHERE;
  m.attr("KIND_OBJECT") = mm::KIND_OBJECT;
  m.attr("KIND_WALL") = mm::KIND_WALL;
  m.attr("KIND_RAMP") = mm::KIND_RAMP;
  m.attr("KIND_SWITCH_BASE") = mm::KIND_SWITCH_BASE;
  m.attr("KIND_SWITCH_PLATFORM") = mm::KIND_SWITCH_PLATFORM;
  m.attr("KIND_DOOR_FRAME") = mm::KIND_DOOR_FRAME;
  m.attr("KIND_DOOR_LEAF") = mm::KIND_DOOR_LEAF;
  m.attr("GAP_CLOSED") = mm::GAP_CLOSED;
  m.attr("GAP_HALF") = mm::GAP_HALF;
  m.attr("GAP_OPEN") = mm::GAP_OPEN;
  m.attr("DESTROY_EVERY_OBJECT") = mm::DESTROY_EVERY_OBJECT;
  m.attr("DESTROY_PORTABLE_OBJECTS") = mm::DESTROY_PORTABLE_OBJECTS;
  m.attr("DESTROY_FIXED_OBJECTS") = mm::DESTROY_FIXED_OBJECTS;
  m.attr("RESET_POSES") = mm::RESET_POSES;
  m.attr("RESET_POSES_AND_TIME") = mm::RESET_POSES_AND_TIME;
  m.attr("RESET_EVERYTHING") = mm::RESET_EVERYTHING;
  // A step request's readings, tests and options (Simulation.step_until).
  for (const auto& [name, value] : std::initializer_list<std::pair<const char*, int>>{
           {"STEP_READ_SIM_TIME", mm::STEP_READ_SIM_TIME},
           {"STEP_READ_ODOMETRY_X", mm::STEP_READ_ODOMETRY_X},
           {"STEP_READ_ODOMETRY_Y", mm::STEP_READ_ODOMETRY_Y},
           {"STEP_READ_ODOMETRY_YAW", mm::STEP_READ_ODOMETRY_YAW},
           {"STEP_READ_TRUTH_X", mm::STEP_READ_TRUTH_X},
           {"STEP_READ_TRUTH_Y", mm::STEP_READ_TRUTH_Y},
           {"STEP_READ_TRUTH_Z", mm::STEP_READ_TRUTH_Z},
           {"STEP_READ_CRANE_SLEW", mm::STEP_READ_CRANE_SLEW},
           {"STEP_READ_CRANE_LIFT", mm::STEP_READ_CRANE_LIFT},
           {"STEP_READ_CRANE_HOIST", mm::STEP_READ_CRANE_HOIST},
           {"STEP_READ_CRANE_HOLDING", mm::STEP_READ_CRANE_HOLDING},
           {"STEP_READ_OBJECT_X", mm::STEP_READ_OBJECT_X},
           {"STEP_READ_OBJECT_Y", mm::STEP_READ_OBJECT_Y},
           {"STEP_READ_OBJECT_Z", mm::STEP_READ_OBJECT_Z},
           {"STEP_READ_OBJECT_TILT_RATE", mm::STEP_READ_OBJECT_TILT_RATE},
           {"STEP_TEST_ABOVE", mm::STEP_TEST_ABOVE},
           {"STEP_TEST_BELOW", mm::STEP_TEST_BELOW},
           {"STEP_TEST_NEAR", mm::STEP_TEST_NEAR},
           {"STEP_TEST_STALLED", mm::STEP_TEST_STALLED},
           {"STEP_CANCELLED", mm::STEP_CANCELLED}}) {
    m.attr(name) = value;
  }
  py::class_<mm::StepCondition_>(
      m, "StepCondition",
      "A reading of a step request (STEP_READ_*, of `robot` or of the object `object_id`) and, "
      "as a condition, its test (STEP_TEST_*) against `value` (and `tolerance`); conditions of "
      "one `group` must all hold.")
      .def(py::init([](int reading, int test, double value, double tolerance, int group,
                       const std::string& robot, uint32_t object_id) {
             mm::StepCondition_ c;
             c.reading(reading);
             c.test(test);
             c.value(value);
             c.tolerance(tolerance);
             c.group(group);
             c.robot(robot);
             c.object_id(object_id);
             return c;
           }),
           py::arg("reading"), py::arg("test") = 0, py::arg("value") = 0.0,
           py::arg("tolerance") = 0.0, py::arg("group") = 0, py::arg("robot") = "",
           py::arg("object_id") = 0)
      .def_property_readonly("reading", [](const mm::StepCondition_& c) { return c.reading(); })
      .def_property_readonly("test", [](const mm::StepCondition_& c) { return c.test(); })
      .def_property_readonly("value", [](const mm::StepCondition_& c) { return c.value(); });
  m.attr("ERR_OK") = mm::ERR_OK;
  m.attr("ERR_UNKNOWN_OBJECT") = mm::ERR_UNKNOWN_OBJECT;
  m.attr("ERR_WRONG_GEOMETRY") = mm::ERR_WRONG_GEOMETRY;
  m.attr("ERR_INVALID_ARGUMENT") = mm::ERR_INVALID_ARGUMENT;
  m.attr("ERR_NOT_APPLICABLE") = mm::ERR_NOT_APPLICABLE;
  m.attr("ERR_PENETRATION") = mm::ERR_PENETRATION;
  m.attr("ERR_BAD_TEXTURE") = mm::ERR_BAD_TEXTURE;
  m.attr("ERR_BAD_FILE") = mm::ERR_BAD_FILE;
  m.attr("ERR_LIMIT_REACHED") = mm::ERR_LIMIT_REACHED;
  m.attr("ERR_IN_PROGRESS") = mm::ERR_IN_PROGRESS;
  m.attr("ERR_UNKNOWN_OPERATION") = mm::ERR_UNKNOWN_OPERATION;

  py::class_<mm::Component_>(m, "Component", "One shape of an object, in the object's frame.")
      .def(py::init([](int shape, const py::sequence& size, const py::sequence& position,
                       const py::sequence& orientation, const py::sequence& color,
                       const std::string& texture) {
             if (shape != mm::SHAPE_BOX && shape != mm::SHAPE_CYLINDER && shape != mm::SHAPE_SPHERE)
               throw py::value_error("shape must be SHAPE_BOX, SHAPE_CYLINDER or SHAPE_SPHERE");
             mm::Component_ c;
             c.shape(shape);
             c.size(array_of<double, 3>(size, "size"));
             const auto p = array_of<double, 3>(position, "position");
             const auto q = array_of<double, 4>(orientation, "orientation");
             c.pose().position().x(p[0]);
             c.pose().position().y(p[1]);
             c.pose().position().z(p[2]);
             c.pose().orientation().x(q[0]);
             c.pose().orientation().y(q[1]);
             c.pose().orientation().z(q[2]);
             c.pose().orientation().w(q[3]);
             c.color(array_of<float, 4>(color, "color"));
             c.texture(texture);
             return c;
           }),
           py::arg("shape"), py::arg("size"), py::arg("position") = py::make_tuple(0, 0, 0),
           py::arg("orientation") = py::make_tuple(0, 0, 0, 1),
           py::arg("color") = py::make_tuple(0.5, 0.5, 0.5, 1.0), py::arg("texture") = "",
           "A box (size: full x, y, z), cylinder (size: radius, -, height; axis along z) or "
           "sphere (size: radius, -, -), m; color rgba in [0, 1]; texture a BMP path.")
      .def_property_readonly("shape", [](const mm::Component_& c) { return c.shape(); })
      .def_property_readonly("size",
                             [](const mm::Component_& c) {
                               return Vec3{c.size()[0], c.size()[1], c.size()[2]};
                             })
      .def_property_readonly("position",
                             [](const mm::Component_& c) { return vec3(c.pose().position()); })
      .def_property_readonly("orientation",
                             [](const mm::Component_& c) { return quat(c.pose().orientation()); })
      .def_property_readonly("color",
                             [](const mm::Component_& c) {
                               return std::tuple<float, float, float, float>{
                                   c.color()[0], c.color()[1], c.color()[2], c.color()[3]};
                             })
      .def_property_readonly("texture", [](const mm::Component_& c) { return c.texture(); })
      .def("__repr__", [](const mm::Component_& c) {
        static const char* names[] = {"box", "cylinder", "sphere"};
        const bool known = c.shape() >= 0 && c.shape() <= 2;
        return std::string("<macsim.Component ") + (known ? names[c.shape()] : "?") + " size " +
               format_vec({c.size()[0], c.size()[1], c.size()[2]}) + ">";
      });

  py::class_<mm::Object_>(m, "Object", "An object of the world: what it is and where it is.")
      .def_property_readonly("id", [](const mm::Object_& o) { return o.id(); })
      .def_property_readonly("name", [](const mm::Object_& o) { return o.name(); })
      .def_property_readonly(
          "kind", [](const mm::Object_& o) { return o.kind(); },
          "KIND_OBJECT, KIND_WALL, KIND_RAMP, ...")
      .def_property_readonly("portable", [](const mm::Object_& o) { return o.portable(); })
      .def_property_readonly("components", [](const mm::Object_& o) { return o.components(); })
      .def_property_readonly("position",
                             [](const mm::Object_& o) { return vec3(o.pose().position()); })
      .def_property_readonly("orientation",
                             [](const mm::Object_& o) { return quat(o.pose().orientation()); })
      .def_property_readonly("linear_velocity",
                             [](const mm::Object_& o) { return vec3(o.velocity().linear()); })
      .def_property_readonly("angular_velocity",
                             [](const mm::Object_& o) { return vec3(o.velocity().angular()); })
      .def_property_readonly("density", [](const mm::Object_& o) { return o.density(); })
      .def_property_readonly("mass", [](const mm::Object_& o) { return o.mass(); })
      .def_property_readonly("material", [](const mm::Object_& o) { return o.material(); })
      .def_property_readonly("magnetizable", [](const mm::Object_& o) { return o.magnetizable(); })
      .def_property_readonly("frozen", [](const mm::Object_& o) { return o.frozen(); })
      .def_property_readonly("user_data", [](const mm::Object_& o) { return o.user_data(); })
      .def_property_readonly("user_color", [](const mm::Object_& o) { return o.user_color(); })
      .def_property_readonly("user_shape", [](const mm::Object_& o) { return o.user_shape(); })
      .def_property_readonly("ramp",
                             [](const mm::Object_& o) {
                               return Vec3{o.ramp()[0], o.ramp()[1], o.ramp()[2]};
                             })
      .def("__repr__", [](const mm::Object_& o) {
        return "<macsim.Object " + std::to_string(o.id()) + " '" + o.name() + "' at " +
               format_vec(vec3(o.pose().position())) + ">";
      });

  py::class_<nav_msgs::msg::dds_::Odometry_>(m, "Odometry",
                                             "The robot's odometry: pose in odom, velocity in "
                                             "base_link.")
      .def_property_readonly(
          "stamp",
          [](const nav_msgs::msg::dds_::Odometry_& o) { return client::stamp_seconds(o.header()); })
      .def_property_readonly(
          "position",
          [](const nav_msgs::msg::dds_::Odometry_& o) { return vec3(o.pose().pose().position()); })
      .def_property_readonly("orientation",
                             [](const nav_msgs::msg::dds_::Odometry_& o) {
                               return quat(o.pose().pose().orientation());
                             })
      .def_property_readonly(
          "yaw",
          [](const nav_msgs::msg::dds_::Odometry_& o) {
            return yaw_of(o.pose().pose().orientation());
          },
          "rad, counter-clockwise from the odom frame's x")
      .def_property_readonly(
          "linear_velocity",
          [](const nav_msgs::msg::dds_::Odometry_& o) { return vec3(o.twist().twist().linear()); })
      .def_property_readonly(
          "angular_velocity",
          [](const nav_msgs::msg::dds_::Odometry_& o) { return vec3(o.twist().twist().angular()); })
      .def("__repr__", [](const nav_msgs::msg::dds_::Odometry_& o) {
        return "<macsim.Odometry t=" + std::to_string(client::stamp_seconds(o.header())) + " at " +
               format_vec(vec3(o.pose().pose().position())) + ">";
      });

  py::class_<sm::Imu_>(m, "Imu", "The IMU's orientation and rates.")
      .def_property_readonly("stamp",
                             [](const sm::Imu_& i) { return client::stamp_seconds(i.header()); })
      .def_property_readonly("orientation", [](const sm::Imu_& i) { return quat(i.orientation()); })
      .def_property_readonly(
          "yaw", [](const sm::Imu_& i) { return yaw_of(i.orientation()); },
          "rad, counter-clockwise")
      .def_property_readonly("angular_velocity",
                             [](const sm::Imu_& i) { return vec3(i.angular_velocity()); })
      .def_property_readonly("linear_acceleration",
                             [](const sm::Imu_& i) { return vec3(i.linear_acceleration()); });

  py::class_<sm::LaserScan_>(m, "Scan", "One sweep of the laser scanner.")
      .def_property_readonly(
          "stamp", [](const sm::LaserScan_& s) { return client::stamp_seconds(s.header()); })
      .def_property_readonly("frame_id",
                             [](const sm::LaserScan_& s) { return s.header().frame_id(); })
      .def_property_readonly("angle_min", [](const sm::LaserScan_& s) { return s.angle_min(); })
      .def_property_readonly("angle_max", [](const sm::LaserScan_& s) { return s.angle_max(); })
      .def_property_readonly("angle_increment",
                             [](const sm::LaserScan_& s) { return s.angle_increment(); })
      .def_property_readonly("range_min", [](const sm::LaserScan_& s) { return s.range_min(); })
      .def_property_readonly("range_max", [](const sm::LaserScan_& s) { return s.range_max(); })
      .def_property_readonly(
          "ranges",
          [](const sm::LaserScan_& s) {
            return py::array_t<float>(static_cast<py::ssize_t>(s.ranges().size()),
                                      s.ranges().data());
          },
          "m per beam from angle_min (float32 array; inf: no echo)");

  py::class_<kurt_msgs::msg::dds_::CraneState_>(m, "CraneState",
                                                "The crane's joints as measured and its magnet.")
      .def_property_readonly("stamp",
                             [](const kurt_msgs::msg::dds_::CraneState_& c) {
                               return client::stamp_seconds(c.header());
                             })
      .def_property_readonly("slew",
                             [](const kurt_msgs::msg::dds_::CraneState_& c) { return c.slew(); })
      .def_property_readonly("lift",
                             [](const kurt_msgs::msg::dds_::CraneState_& c) { return c.lift(); })
      .def_property_readonly("hoist",
                             [](const kurt_msgs::msg::dds_::CraneState_& c) { return c.hoist(); })
      .def_property_readonly(
          "magnet_on", [](const kurt_msgs::msg::dds_::CraneState_& c) { return c.magnet_on(); })
      .def_property_readonly(
          "held_object", [](const kurt_msgs::msg::dds_::CraneState_& c) { return c.held_object(); },
          "name of the object on the magnet, empty if none");

  py::class_<mm::SimulationReply_>(m, "SimulationStatus",
                                   "Where the simulation stands after a command.")
      .def_property_readonly("sim_time", [](const mm::SimulationReply_& r) { return r.sim_time(); })
      .def_property_readonly(
          "steps", [](const mm::SimulationReply_& r) { return r.steps(); },
          "steps since the world was loaded")
      .def_property_readonly("state_hash",
                             [](const mm::SimulationReply_& r) { return r.state_hash(); })
      .def_property_readonly("paused", [](const mm::SimulationReply_& r) { return r.paused(); })
      .def_property_readonly("real_time_factor",
                             [](const mm::SimulationReply_& r) { return r.real_time_factor(); })
      .def_property_readonly(
          "ended_by", [](const mm::SimulationReply_& r) { return r.ended_by(); },
          "step_until: the group of conditions that ended it, -1 (the steps ran out) or "
          "STEP_CANCELLED")
      .def_property_readonly(
          "samples", [](const mm::SimulationReply_& r) { return r.samples(); },
          "step_until: the samples' readings at every check, in order")
      .def_property_readonly(
          "step_trace", [](const mm::SimulationReply_& r) { return r.step_trace(); },
          "step_until(trace_hash=True): every step's state hash mixed in order")
      .def_property_readonly(
          "steps_done", [](const mm::SimulationReply_& r) { return r.steps_done(); },
          "step, step_until, cancel: the steps of the (cancelled) request done")
      .def_property_readonly(
          "steps_asked", [](const mm::SimulationReply_& r) { return r.steps_asked(); },
          "step, step_until, cancel: the steps the (cancelled) request asked for")
      .def_property_readonly(
          "message", [](const mm::SimulationReply_& r) { return r.message(); },
          "what the simulator said, e.g. of a cancel")
      .def_property_readonly(
          "published", [](const mm::SimulationReply_& r) { return r.published(); },
          "step_until(publish_at_end=True): the topics its end wrote (Robot.topic names them); "
          "a lock-step read of one of them waits for that sample, of another finds none new")
      .def("__repr__", [](const mm::SimulationReply_& r) {
        return "<macsim.SimulationStatus t=" + std::to_string(r.sim_time()) +
               " steps=" + std::to_string(r.steps()) + " hash=" + std::to_string(r.state_hash()) +
               (r.paused() ? " paused>" : ">");
      });
}

}  // namespace macsim::python
