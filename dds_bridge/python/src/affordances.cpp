// macsim.AffordanceModel: a learned affordance model (affordance_learn --save-model) loaded
// from its file and asked from Python (macsim.affordances.load), and the one perception that
// gives it its features from what the robot sees (macsim.affordances.features).
#include "macsim/affordances/model.h"
#include "macsim/affordances/perception.h"
#include "macsim/affordances/planner.h"

#include <tuple>
#include <variant>

#include "bindings.h"

namespace macsim::python {

namespace af = macsim::affordances;

namespace {

using Points = py::array_t<float, py::array::c_style | py::array::forcecast>;

af::Affordance affordance_named(const std::string& name) {
  const auto affordance = af::affordance_from_name(name);
  if (!affordance)
    throw py::value_error("no affordance '" + name + "' (lift, push, climb, stack, traverse)");
  return *affordance;
}

client::Cloud cloud_of(const Points& points) {
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw py::value_error("points must be an N x 3 array (m, base_link)");
  client::Cloud cloud;
  const auto view = points.unchecked<2>();
  for (py::ssize_t i = 0; i < points.shape(0); ++i)
    cloud.points.push_back({view(i, 0), view(i, 1), view(i, 2)});
  return cloud;
}

}  // namespace

void bind_affordances(py::module_& m) {
  m.def(
      "affordance_features",
      [](const std::string& affordance, std::optional<client::StereoFrame> frame,
         std::optional<client::Laser::Scan> scan, std::optional<Points> points,
         std::optional<std::tuple<int, int, int, int>> region) {
        af::SensorInputs inputs{std::move(frame), std::move(scan), std::nullopt};
        if (points) inputs.cloud = cloud_of(*points);
        std::optional<cv::Rect> box;
        if (region) {
          const auto [x, y, w, h] = *region;
          if (w <= 0 || h <= 0) throw py::value_error("region: width and height must be positive");
          box = cv::Rect(x, y, w, h);
        }
        py::gil_scoped_release release;
        return af::named_features(af::perceive(inputs, {}, box), affordance_named(affordance));
      },
      py::arg("affordance"), py::arg("frame") = py::none(), py::arg("scan") = py::none(),
      py::arg("points") = py::none(), py::arg("region") = py::none(),
      "The features of `affordance` (a dict by name, what AffordanceModel.predict takes) from "
      "one look: a stereo pair (Robot.stereo()), a sweep of the scanner standing still "
      "(Robot.scan()) and a 3D cloud (Robot.points()), each optional; the cameras' of the "
      "thing whose centre lies in `region` (x, y, width, height in the left image; one of "
      "objects_in_view()), else of the largest. The same code as the trials' rows.");
  m.def(
      "affordance_feature_group",
      [](const std::string& name) {
        const auto* group = af::feature_group(name);
        if (!group)
          throw py::value_error("no feature group '" + name +
                                "' (camera, sweep, top, cloud or shape)");
        return *group;
      },
      py::arg("name"),
      "The features of one sensor, in order, by group name: camera (the blob in the stereo "
      "pair), sweep (the laser's sweep ahead), top (stack: the top's profile, the carried "
      "height), cloud (traverse: the grid) or shape (traverse: the corridor and what stands in "
      "it, measured from itself). ValueError for another name.");
  m.def(
      "objects_in_view",
      [](const client::StereoFrame& frame) {
        std::vector<std::tuple<int, int, int, int>> boxes;
        for (const auto& b : af::objects_in_view(frame.left))
          boxes.emplace_back(b.x, b.y, b.width, b.height);
        return boxes;
      },
      py::arg("frame"),
      "The boxes (x, y, width, height) of the things the cameras' perception looks at in the "
      "left image, largest first: each a `region` for affordance_features().");
  m.def(
      "load_sensor_inputs",
      [](const std::string& dir, const std::string& name) {
        af::SensorInputs inputs;
        try {
          inputs = af::load_inputs(dir, name);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
        std::optional<py::array> points;
        if (inputs.cloud) points = points_array(std::move(*inputs.cloud));
        return std::make_tuple(inputs.frame, inputs.scan, points);
      },
      py::arg("dir"), py::arg("name"),
      "(frame, scan, points) of a look saved by affordance_trials --keep-inputs DIR (NAME: "
      "<affordance>_<seed>); each None when the look lacks it. ValueError naming the file.");

  auto& pddl_error =
      py::register_exception<af::pddl::PddlError>(m, "PddlError", PyExc_ValueError);
  pddl_error.doc() = "A PDDL domain or problem that cannot be read; the message starts FILE:LINE.";
  m.def(
      "plan_files",
      [](const std::string& domain, const std::string& problem) {
        const af::pddl::Domain d = af::pddl::load_domain(domain);
        const af::pddl::Problem p = af::pddl::load_problem(problem, d);
        af::PlanResult r;
        {
          py::gil_scoped_release release;
          r = af::plan(d, p);
        }
        py::list steps;
        if (r.plan)
          for (const auto& s : r.plan->steps) {
            const auto texts = [](const std::vector<af::pddl::Atom>& atoms) {
              std::vector<std::string> out;
              for (const auto& a : atoms) out.push_back(af::pddl::text(a));
              return out;
            };
            steps.append(py::make_tuple(s.text(), s.probability, texts(s.expected.add),
                                        texts(s.expected.remove)));
          }
        py::dict out;
        out["reached"] = r.plan.has_value();
        out["steps"] = steps;
        out["probability"] = r.plan ? r.plan->probability : 0.0;
        out["reason"] = r.reason;
        out["seconds"] = r.seconds;
        return out;
      },
      py::arg("domain"), py::arg("problem"),
      "Plans for the PDDL problem file over the domain file (STRIPS or PPDDL; the planner of "
      "kurt_plan): a dict with 'reached', 'steps' (each (text, probability, atoms added, atoms "
      "removed)), 'probability', 'reason' (why no plan) and 'seconds'. PddlError (a ValueError) "
      "names the file and line of a fault.");

  auto& error = py::register_exception<af::ModelError>(m, "AffordanceModelError", PyExc_ValueError);
  error.doc() =
      "A model file that cannot be loaded (missing, damaged, another format version, other "
      "features, values that are not finite) or a prediction asked with bad features; the "
      "message names the file or the feature.";
  py::class_<af::AffordanceModel>(
      m, "AffordanceModel",
      "A learned affordance model: a random forest and what its file says of it.")
      .def_static(
          "load",
          [](const std::string& path, const std::vector<std::string>& features) {
            return af::AffordanceModel::load(path, features);
          },
          py::arg("path"), py::arg("features") = std::vector<std::string>{},
          "Reads a model file (affordance_learn --save-model). With `features`, refuses a "
          "model whose features differ from them.")
      .def(
          "predict",
          [](const af::AffordanceModel& model,
             const std::variant<std::map<std::string, double>, std::vector<double>>& features) {
            const af::Prediction p = std::visit([&](const auto& f) { return model.predict(f); },
                                                features);
            return std::make_tuple(p.label, p.confidence);
          },
          py::arg("features"),
          "(label, confidence) for one object's features: a dict by name (every feature of "
          "the model; others are ignored) or a sequence in `features` order. Confidence: the "
          "share of the forest's trees that voted for the label.")
      .def_property_readonly(
          "affordance", [](const af::AffordanceModel& model) { return model.info().affordance; },
          "lift, push, climb, stack or traverse.")
      .def_property_readonly(
          "features", [](const af::AffordanceModel& model) { return model.info().features; },
          "The features the model takes, in order.")
      .def_property_readonly(
          "labels", [](const af::AffordanceModel& model) { return model.info().labels; },
          "The labels it answers.")
      .def_property_readonly(
          "generator", [](const af::AffordanceModel& model) { return model.info().generator; },
          "The trials' generator(s) its rows came from.")
      .def_property_readonly(
          "rows", [](const af::AffordanceModel& model) { return model.info().rows; },
          "Trial rows the forest was fitted on.")
      .def_property_readonly(
          "seeds", [](const af::AffordanceModel& model) { return model.info().seeds; },
          "Their seeds as ranges, e.g. '1-300'.")
      .def_property_readonly(
          "held_out_accuracy",
          [](const af::AffordanceModel& model) { return model.info().held_out_accuracy; },
          "Accuracy on the held-out trials, measured before the forest was refit on all rows.")
      .def_property_readonly(
          "project_version",
          [](const af::AffordanceModel& model) { return model.info().project_version; },
          "The version of MACSim-DDS that wrote the file.")
      .def("__repr__", [](const af::AffordanceModel& model) {
        return "<macsim.AffordanceModel " + model.info().affordance + " from " +
               std::to_string(model.info().rows) + " rows>";
      });
}

}  // namespace macsim::python
