// The `macsim._macsim` extension: the participant, the shared helpers, and the parts bound in
// robot.cpp, supervisor.cpp and wire_types.cpp.
#include <cmath>

#include "bindings.h"

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

  macsim::python::bind_wire_types(m);
  macsim::python::bind_robot(m);
  macsim::python::bind_supervisor(m);
}
