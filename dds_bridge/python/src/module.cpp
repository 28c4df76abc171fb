// The `macsim._macsim` extension: the participant, the shared helpers, and the parts bound in
// robot.cpp, supervisor.cpp and wire_types.cpp.
#include <cmath>
#include <sstream>

#include "bindings.h"
#include "macsim/robot/kurt3d_description.h"

namespace macsim::python {

std::chrono::milliseconds to_milliseconds(double seconds, const char* what) {
  if (!std::isfinite(seconds) || seconds < 0 || seconds > 1e7) {
    throw py::value_error(std::string(what) + " must be a finite number of seconds >= 0, not " +
                          std::to_string(seconds));
  }
  return std::chrono::milliseconds(static_cast<long long>(std::llround(seconds * 1000.0)));
}

bool python_interrupted() {
  py::gil_scoped_acquire acquire;
  return PyErr_CheckSignals() != 0;
}

void raise_pending() { throw py::error_already_set(); }

py::dict kurt3d_description() {
  py::dict out;
  std::istringstream lines(robot::kurt3d::description_text());
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string key, word;
    words >> key;
    std::vector<std::string> values;
    while (words >> word) values.push_back(word);
    if (key == "robot") {
      out["robot"] = values.empty() ? "" : values.front();
      continue;
    }
    if (key == "range_sensor" && !values.empty()) {  // keyed by its frame
      key += " " + values.front();
      values.erase(values.begin());
    }
    std::vector<double> numbers;
    for (const auto& v : values) numbers.push_back(std::stod(v));
    if (numbers.size() == 1) {
      out[py::str(key)] = numbers.front();
    } else {
      out[py::str(key)] = py::tuple(py::cast(numbers));
    }
  }
  return out;
}

void raise_timeout(const std::string& message) {
  PyErr_SetString(PyExc_TimeoutError, message.c_str());
  throw py::error_already_set();
}

}  // namespace macsim::python

PYBIND11_MODULE(_macsim, m) {
  namespace py = pybind11;
  using macsim::python::PythonParticipant;
  m.doc() =
      "MACSim-DDS over DDS: drive a KURT3D (simulated or real), supervise and step the "
      "simulator. Images and clouds come as numpy arrays.";

  py::class_<PythonParticipant>(
      m, "Participant", "A Fast DDS participant on one domain: every handle is made on one.")
      .def(py::init([](int domain, std::optional<std::string> profile, const std::string& name) {
             if (domain < 0 || domain > macsim::dds::kMaxDomainId) {
               throw py::value_error("domain must be 0.." +
                                     std::to_string(macsim::dds::kMaxDomainId) + ", not " +
                                     std::to_string(domain));
             }
             macsim::dds::ParticipantOptions options;
             options.domain = domain;
             options.profile_file = profile.value_or("");
             options.name = name;
             return std::make_unique<PythonParticipant>(options);
           }),
           py::arg("domain"), py::arg("profile") = py::none(), py::arg("name") = "macsim_python",
           "Joins DDS domain `domain` (0..232). `profile`: a Fast DDS XML profile file (None: "
           "FASTRTPS_DEFAULT_PROFILES_FILE, else Fast DDS's defaults). `name`: the participant's "
           "(and ROS 2 node's) name.")
      .def_readonly("domain", &PythonParticipant::domain, "The DDS domain id.")
      .def("__repr__", [](const PythonParticipant& p) {
        return "<macsim.Participant domain=" + std::to_string(p.domain) + ">";
      });

  m.def("kurt3d_description", &macsim::python::kurt3d_description,
        "The KURT3D's description (what macsim publishes on rt/kurt/robot_description): its "
        "dimensions, mounts and limits by name, in m, kg and rad ('base_height', 'pivot_x', "
        "'boom_length', 'left_camera': (x, y, z), 'range_sensor ir_left': (x, y, yaw, sonar, "
        "min, max, fov), ...).");
  macsim::python::bind_wire_types(m);
  macsim::python::bind_robot(m);
  macsim::python::bind_supervisor(m);
  macsim::python::bind_affordances(m);
}
