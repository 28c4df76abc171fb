// macsim.AffordanceModel: a learned affordance model (affordance_learn --save-model) loaded
// from its file and asked from Python (macsim.affordances.load).
#include "macsim/affordances/model.h"

#include <variant>

#include "bindings.h"

namespace macsim::python {

namespace af = macsim::affordances;

void bind_affordances(py::module_& m) {
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
          "affordance", [](const af::AffordanceModel& m) { return m.info().affordance; },
          "lift, push, climb, stack or traverse.")
      .def_property_readonly(
          "features", [](const af::AffordanceModel& m) { return m.info().features; },
          "The features the model takes, in order.")
      .def_property_readonly(
          "labels", [](const af::AffordanceModel& m) { return m.info().labels; },
          "The labels it answers.")
      .def_property_readonly(
          "generator", [](const af::AffordanceModel& m) { return m.info().generator; },
          "The trials' generator(s) its rows came from.")
      .def_property_readonly(
          "rows", [](const af::AffordanceModel& m) { return m.info().rows; },
          "Trial rows the forest was fitted on.")
      .def_property_readonly(
          "seeds", [](const af::AffordanceModel& m) { return m.info().seeds; },
          "Their seeds as ranges, e.g. '1-300'.")
      .def_property_readonly(
          "held_out_accuracy",
          [](const af::AffordanceModel& m) { return m.info().held_out_accuracy; },
          "Accuracy on the held-out trials, measured before the forest was refit on all rows.")
      .def_property_readonly(
          "project_version",
          [](const af::AffordanceModel& m) { return m.info().project_version; },
          "The version of MACSim-DDS that wrote the file.")
      .def("__repr__", [](const af::AffordanceModel& m) {
        return "<macsim.AffordanceModel " + m.info().affordance + " from " +
               std::to_string(m.info().rows) + " rows>";
      });
}

}  // namespace macsim::python
