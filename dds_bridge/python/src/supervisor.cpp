// macsim.Supervisor (every supervisor operation, keyword arguments, SupervisorError on a
// refusal; the methods of most are generated from the IDL into supervisor_operations.inc),
// macsim.Simulation (pause, run, real-time factor, lock-step steps, reset, load,
// features) and macsim.WorldState (the world state topic as a dict of objects by id).
#include <pybind11/eval.h>

#include <cstdio>
#include <sstream>
#include <thread>

#include "bindings.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/client/world_state.h"

namespace macsim::python {

namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace sv = client::supervisor;

/// A request the simulator answered with an error code.
struct SupervisorFailure {
  int code;
  std::string message;
  std::vector<std::string> names;
};

std::string seconds_text(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", s);
  return text;
}

/// Calls over one request/reply pair: the GIL released while waiting, Ctrl-C heard, no answer a
/// TimeoutError saying why (no simulator, busy with the request, gone), an error code a
/// SupervisorError.
template <class Client>
struct PythonCaller {
  PythonCaller(PythonParticipant& p, double seconds, const char* name)
      : domain(p.domain), timeout(seconds), service(name), client(p.dds) {
    to_milliseconds(seconds);
  }

  typename Client::Reply call(typename Client::Request request, std::optional<double> wait = {}) {
    const double seconds = wait.value_or(timeout);
    const auto limit = to_milliseconds(seconds);
    std::optional<typename Client::Reply> reply;
    client::CallOutcome outcome;
    {
      py::gil_scoped_release release;
      reply = client.call(
          std::move(request), limit, [] { return python_interrupted(); }, &outcome);
    }
    if (PyErr_Occurred()) raise_pending();
    if (!reply) {
      if (outcome.kind == client::CallOutcome::Kind::NoServer) outcome.waited = seconds;
      raise_timeout(client::describe(outcome, service, domain));
    }
    if (reply->code() != mm::ERR_OK)
      throw SupervisorFailure{reply->code(), reply->message(), names(*reply)};
    return std::move(*reply);
  }
  static std::vector<std::string> names(const mm::SupervisorReply_& r) { return r.names(); }
  static std::vector<std::string> names(const mm::SimulationReply_&) { return {}; }

  int domain;
  double timeout;
  const char* service;
  Client client;
};

using PythonSupervisor = PythonCaller<client::SupervisorClient>;

/// Simulation control, and the supervisor's reset.
struct PythonSimulation {
  PythonSimulation(PythonParticipant& p, double timeout)
      : control(p, timeout, "simulation control"), supervisor(p, timeout, "supervisor") {}
  mm::SimulationReply_ command(int32_t command) {
    return control.call(client::SimulationClient::request(command));
  }
  /// A step request; a Ctrl-C while it waits cancels it on the simulator too.
  mm::SimulationReply_ step(const mm::SimulationRequest_& request, std::optional<double> wait) {
    try {
      return control.call(request, wait);
    } catch (py::error_already_set& error) {
      if (error.matches(PyExc_KeyboardInterrupt)) {
        py::gil_scoped_release release;
        control.client.call(client::SimulationClient::request(mm::SIM_CANCEL),
                            std::chrono::seconds(2));
      }
      throw;
    }
  }
  PythonCaller<client::SimulationClient> control;
  PythonSupervisor supervisor;
};

/// A door-switch structure as get_door answers it.
struct DoorInfo {
  std::string name;
  bool triggered, virtually_triggered;
  int gap;
  double opening, switch_travel;
  std::vector<uint32_t> object_ids;  ///< leaf, frame, platform, base
};

mm::Object_ object_of(const std::string& name, const std::vector<mm::Component_>& components,
                      const sv::Vec3& position, const sv::Quat& orientation, int kind,
                      bool portable, double density, double mass, const std::string& material,
                      bool magnetizable, bool frozen, const std::string& user_data, int user_color,
                      int user_shape, const sv::Vec3& ramp) {
  mm::Object_ o;
  o.name(name);
  o.kind(kind);
  o.portable(portable);
  o.components(components);
  o.pose().position().x(position[0]);
  o.pose().position().y(position[1]);
  o.pose().position().z(position[2]);
  o.pose().orientation().x(orientation[0]);
  o.pose().orientation().y(orientation[1]);
  o.pose().orientation().z(orientation[2]);
  o.pose().orientation().w(orientation[3]);
  o.density(density);
  o.mass(mass);
  o.material(material);
  o.magnetizable(magnetizable);
  o.frozen(frozen);
  o.user_data(user_data);
  o.user_color(user_color);
  o.user_shape(user_shape);
  o.ramp(ramp);
  return o;
}

constexpr const char* kSupervisorErrorClass = R"py(
class SupervisorError(RuntimeError):
    """A request the simulator refused: `code` (ERR_*), its `message`, and `names` (the
    objects a change would penetrate, when that is why)."""
    __module__ = "macsim"

    def __init__(self, code, message, names=()):
        super().__init__(f"{message} (code {code})")
        self.code = code
        self.message = message
        self.names = list(names)
)py";

}  // namespace

void bind_supervisor(py::module_& m) {
  py::dict definitions;
  py::exec(kSupervisorErrorClass, py::globals(), definitions);
  m.attr("SupervisorError") = definitions["SupervisorError"];
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SupervisorFailure& e) {
      py::object cls = py::module_::import("macsim._macsim").attr("SupervisorError");
      py::object error = cls(e.code, e.message, e.names);
      PyErr_SetObject(cls.ptr(), error.ptr());
    }
  });

  py::class_<DoorInfo>(m, "Door", "A door-switch structure.")
      .def_readonly("name", &DoorInfo::name)
      .def_readonly("triggered", &DoorInfo::triggered, "the switch is pressed (by weight)")
      .def_readonly("virtually_triggered", &DoorInfo::virtually_triggered,
                    "triggered by the supervisor")
      .def_readonly("gap", &DoorInfo::gap, "GAP_CLOSED, GAP_HALF or GAP_OPEN")
      .def_readonly("opening", &DoorInfo::opening, "0 (closed) .. 1 (open)")
      .def_readonly("switch_travel", &DoorInfo::switch_travel, "0 .. 1")
      .def_readonly("object_ids", &DoorInfo::object_ids,
                    "the leaf's, frame's, switch platform's and switch base's object ids");

  using S = PythonSupervisor;
  const sv::Quat identity = sv::kIdentity;
  py::class_<S>(m, "Supervisor",
                "The simulator's supervisor: every operation on the world's objects and doors. A "
                "refusal raises SupervisorError; no answer within `timeout` s, TimeoutError.")
      .def(py::init([](PythonParticipant& p, double timeout) {
             return std::make_unique<S>(p, timeout, "supervisor");
           }),
           py::arg("participant"), py::arg("timeout") = 10.0, py::keep_alive<1, 2>())
      .def_readwrite("timeout", &S::timeout, "s to wait for each answer")
      .def(
          "list_objects",
          [](S& s) {
            const auto r = s.call(sv::list_objects());
            py::dict objects;
            for (std::size_t i = 0; i < r.object_ids().size() && i < r.names().size(); ++i)
              objects[py::int_(r.object_ids()[i])] = r.names()[i];
            return objects;
          },
          "Every object: {id: name}, in the world's order.")
      .def(
          "create_object",
          [](S& s, const std::string& name, const std::vector<mm::Component_>& components,
             const sv::Vec3& position, const sv::Quat& orientation, int kind, bool portable,
             double density, double mass, const std::string& material, bool magnetizable,
             bool frozen, const std::string& user_data, int user_color, int user_shape,
             const sv::Vec3& ramp, bool allow_penetration) {
            return s
                .call(sv::create_object(object_of(name, components, position, orientation, kind,
                                                  portable, density, mass, material, magnetizable,
                                                  frozen, user_data, user_color, user_shape, ramp),
                                        allow_penetration))
                .object_id();
          },
          py::arg("name"), py::arg("components") = std::vector<mm::Component_>{},
          py::arg("position") = sv::Vec3{0, 0, 0}, py::arg("orientation") = identity, py::kw_only(),
          py::arg("kind") = mm::KIND_OBJECT, py::arg("portable") = true, py::arg("density") = 0.0,
          py::arg("mass") = 0.0, py::arg("material") = "", py::arg("magnetizable") = false,
          py::arg("frozen") = false, py::arg("user_data") = "", py::arg("user_color") = 0,
          py::arg("user_shape") = 0, py::arg("ramp") = sv::Vec3{0, 0, 0},
          py::arg("allow_penetration") = true,
          "Creates an object (KIND_OBJECT of Components, or KIND_RAMP of `ramp` = width, "
          "height, angle) and returns its id. density kg/m^3 (0: 100); mass > 0 sets the "
          "density from the volume.")
      .def(
          "get_door",
          [](S& s, int door) {
            const auto r = s.call(sv::get_door(door));
            const auto& d = r.door();
            return DoorInfo{d.name(),    d.triggered(),     d.virtually_triggered(), d.gap(),
                            d.opening(), d.switch_travel(), r.object_ids()};
          },
          py::arg("door"), "Door `door` (0 .. door_count() - 1).")
// The methods of the other operations, generated from the IDL (idl/tools/generate_operations.py).
#include "supervisor_operations.inc"
      ;  // the end of the Supervisor class's definitions

  using Sim = PythonSimulation;
  py::class_<Sim>(m, "Simulation",
                  "Controls the simulation: pause, run, real-time factor, lock-step steps, "
                  "reset, load a world. No answer within `timeout` s: TimeoutError.")
      .def(py::init([](PythonParticipant& p, double timeout, double restart_patience) {
             auto sim = std::make_unique<Sim>(p, timeout);
             const auto patience = to_milliseconds(restart_patience, "restart_patience");
             sim->control.client.set_restart_patience(patience);
             sim->supervisor.client.set_restart_patience(patience);
             return sim;
           }),
           py::arg("participant"), py::arg("timeout") = 10.0, py::arg("restart_patience") = 0.0,
           py::keep_alive<1, 2>())
      .def_property_readonly(
          "gaps",
          [](const Sim& s) {
            py::list gaps;
            for (const auto& gap : s.control.client.gaps()) {
              py::dict d;
              d["seconds"] = gap.seconds;
              d["step"] = gap.step ? py::cast(*gap.step) : py::none();
              gaps.append(d);
            }
            return gaps;
          },
          "The times the simulator went away during a call and came back (restart_patience > "
          "0): each a dict with its 'seconds' and the 'step' it was back at.")
      .def_property(
          "timeout", [](const Sim& s) { return s.control.timeout; },
          [](Sim& s, double t) {
            to_milliseconds(t);
            s.control.timeout = s.supervisor.timeout = t;
          },
          "s to wait for each answer")
      .def(
          "pause", [](Sim& s) { return s.command(mm::SIM_PAUSE); }, "Stops stepping.")
      .def(
          "run", [](Sim& s) { return s.command(mm::SIM_RUN); },
          "Steps again, at the real-time factor.")
      .def(
          "set_real_time_factor",
          [](Sim& s, double factor) {
            auto request = client::SimulationClient::request(mm::SIM_SET_RTF);
            request.real_time_factor(factor);
            return s.control.call(request);
          },
          py::arg("factor"), "> 0, or 0 for as fast as possible.")
      .def(
          "step",
          [](Sim& s, uint64_t steps, std::optional<double> timeout) {
            auto request = client::SimulationClient::request(mm::SIM_STEP);
            request.steps(steps);
            return s.step(request, timeout);
          },
          py::arg("steps") = 1, py::arg("timeout") = py::none(),
          "Lock-step: advances `steps` steps; answered once the steps' data is out, with the "
          "new sim time and state hash. Ctrl-C while it waits cancels it on the simulator; a "
          "TimeoutError leaves it running (cancel() ends it).")
      .def(
          "step_until",
          [](Sim& s, uint64_t steps, const std::vector<mm::StepCondition_>& until,
             const std::vector<mm::StepCondition_>& samples, uint32_t check_every,
             bool publish_at_end, bool cameras, bool hold_commands, bool trace_hash,
             std::optional<double> timeout, const std::vector<std::string>& hold_robots) {
            uint32_t options = 0;
            if (publish_at_end) options |= mm::STEP_PUBLISH_AT_END;
            if (!cameras) options |= mm::STEP_NO_CAMERAS;
            if (hold_commands) options |= mm::STEP_HOLD_COMMANDS;
            if (trace_hash) options |= mm::STEP_TRACE_HASH;
            auto request = client::step_until::request(steps, check_every, options);
            request.until(until);
            request.samples(samples);
            request.hold_robots(hold_robots);
            return s.step(request, timeout);
          },
          py::arg("steps"), py::arg("until") = std::vector<mm::StepCondition_>{},
          py::arg("samples") = std::vector<mm::StepCondition_>{}, py::arg("check_every") = 1,
          py::arg("publish_at_end") = false, py::arg("cameras") = true,
          py::arg("hold_commands") = false, py::arg("trace_hash") = false,
          py::arg("timeout") = py::none(), py::arg("hold_robots") = std::vector<std::string>{},
          "Lock-step: at most `steps` steps, ended at the first check (every `check_every` "
          "steps) where a group of `until` conditions holds; `samples` read at every check. "
          "The reply's ended_by names the group (-1: the steps ran out), its samples hold the "
          "readings. publish_at_end: topics bring only their newest sample, at the end; "
          "cameras=False: no images of its instants; hold_commands: drive commands do not time "
          "out meanwhile, those of the robots in hold_robots (empty: every robot's). A bad "
          "condition or robot: SupervisorError naming the field.")
      .def(
          "status", [](Sim& s) { return s.command(mm::SIM_STATUS); },
          "Time, steps, state hash, paused, real-time factor.")
      .def(
          "cancel",
          [](Sim& s, uint64_t sequence_number) {
            auto request = client::SimulationClient::request(mm::SIM_CANCEL);
            request.cancel_sequence_number(sequence_number);
            return s.control.call(request);
          },
          py::arg("sequence_number") = 0,
          "Ends this Simulation's step request still running (one a TimeoutError left behind, "
          "or one another thread waits on); its reply says STEP_CANCELLED. This reply's "
          "steps_done and steps_asked are the cancelled request's; SupervisorError "
          "(ERR_NOT_APPLICABLE) if none runs.")
      .def(
          "reset",
          [](Sim& s, int scope) {
            s.supervisor.call(sv::reset(scope));
            return s.command(mm::SIM_STATUS);
          },
          py::arg("scope") = mm::RESET_EVERYTHING,
          "Puts the world back (RESET_POSES, RESET_POSES_AND_TIME or RESET_EVERYTHING).")
      .def(
          "load_world",
          [](Sim& s, const std::string& file, double timeout) {
            auto request = client::SimulationClient::request(mm::SIM_LOAD_WORLD);
            request.world_file(file);
            return s.control.call(request, timeout);
          },
          py::arg("file"), py::arg("timeout") = 60.0,
          "Loads another world file (same robot names); answered once it runs.")
      .def(
          "features",
          [](Sim& s) {
            std::vector<std::string> out;
            std::stringstream list(s.command(mm::SIM_FEATURES).features());
            for (std::string item; std::getline(list, item, ',');)
              if (!item.empty()) out.push_back(item);
            return out;
          },
          "What the participant supports: 'simulator', 'supervisor', 'lockstep', ...");

  using W = client::WorldStateClient;
  py::class_<W>(m, "WorldState", "The world state topic: the latest state of every object, by id.")
      .def(py::init([](PythonParticipant& p) { return std::make_unique<W>(p.dds); }),
           py::arg("participant"), py::keep_alive<1, 2>())
      .def(
          "objects",
          [](W& w) {
            W::Objects objects;
            {
              py::gil_scoped_release release;
              objects = w.objects();
            }
            py::dict out;
            for (auto& [id, state] : objects) out[py::int_(id)] = py::cast(state.object());
            return out;
          },
          "{id: Object} of every object alive, as last published.")
      .def(
          "wait",
          [](W& w, const py::function& check, double timeout) {
            const auto limit = to_milliseconds(timeout);
            const auto deadline = std::chrono::steady_clock::now() + limit;
            while (true) {
              W::Objects objects;
              {
                py::gil_scoped_release release;
                objects = w.objects();
              }
              py::dict view;
              for (auto& [id, state] : objects) view[py::int_(id)] = py::cast(state.object());
              if (check(view).cast<bool>()) return view;
              if (std::chrono::steady_clock::now() >= deadline) {
                raise_timeout("the world state did not come to what was asked within " +
                              seconds_text(timeout) + " s");
              }
              {
                py::gil_scoped_release release;
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
              }
              if (PyErr_CheckSignals() != 0) raise_pending();
            }
          },
          py::arg("check"), py::arg("timeout") = 10.0,
          "Waits until check({id: Object}) is true and returns that dict; TimeoutError after "
          "`timeout` s.");
}

}  // namespace macsim::python
