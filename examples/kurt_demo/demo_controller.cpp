#include "demo_controller.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "macsim/affordances/perception.h"

namespace kurt_demo {

namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;

namespace af = macsim::affordances;

/// A number with `decimals` decimals.
std::string fixed(double v, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

/// The features the demonstrator computes of a can from where it stands: the cameras'.
const std::vector<std::string>& camera_features() {
  return *macsim::affordances::feature_group("camera");
}

}  // namespace

macsim::affordances::AffordanceModel load_lift_model(const std::string& dir) {
  const std::string file = dir + "/lift.yml";
  try {
    auto model = macsim::affordances::AffordanceModel::load(file);
    if (model.info().affordance != "lift")
      throw Failure{kUsage, file + " is a model of " + model.info().affordance + ", not lift"};
    if (std::find(model.info().labels.begin(), model.info().labels.end(), "liftable") ==
        model.info().labels.end())
      throw Failure{kUsage, file + " has no label 'liftable'"};
    std::string missing;
    for (const auto& f : model.info().features) {
      if (std::find(camera_features().begin(), camera_features().end(), f) ==
          camera_features().end())
        missing += (missing.empty() ? "" : ",") + f;
    }
    if (!missing.empty())
      throw Failure{kUsage, file + " takes " + missing +
                                ", which the demonstrator cannot compute from where it stands "
                                "(it sees the cans with its cameras; train with "
                                "affordance_learn --features hue)"};
    return model;
  } catch (const macsim::affordances::ModelError& e) {
    throw Failure{kUsage, e.what()};
  }
}

namespace {

af::BehaviourOptions behaviour_options(const DemoOptions& o) {
  af::BehaviourOptions b;
  b.loop = o.loop;
  b.program = "kurt_demo";
  b.debug_images = o.debug_images;
  b.lift_model = o.lift_model;
  b.pictures = o.pictures;
  return b;
}

/// The scenario's exit code for a behaviour that did not do what it set out to.
Failure failure(const af::BehaviourReport& r, Exit otherwise) {
  switch (r.setback) {
    case af::Setback::NoSwitch: return {kNoSwitch, r.reason};
    case af::Setback::DoorClosed:
    case af::Setback::NoDoor: return {kDoorClosed, r.reason};
    case af::Setback::NotThrough: return {kNoPassage, r.reason};
    default: return {otherwise, r.reason};
  }
}

}  // namespace

DemoController::DemoController(macsim::dds::Participant& participant, const DemoOptions& options)
    : Behaviours(participant, behaviour_options(options)), options_(options) {
  on_event = [this](const std::string& event) {
    if (event == "lifted") overview_picture("scene2_can_on_magnet");
    if (event == "gap_seen") overview_picture("scene3_can_on_switch_door_open");
    if (event == "through") overview_picture("scene4_robot_through");
  };
}

DemoController::~DemoController() = default;

void DemoController::lift_a_can() {
  set_stage("scene 2");
  if (options_.lift_model) {
    const auto& info = options_.lift_model->info();
    std::string said;
    for (const auto& c : scene().things) {
      if (c.kind != af::Kind::Can) continue;
      said += " [" + c.colour + " at " + fixed(c.x, 2) + "," + fixed(c.y, 2) + ": " +
              (!c.judged           ? std::string("not judged")
               : c.liftable >= 0.5 ? "liftable " + fixed(c.liftable, 2)
                                   : "not_liftable " + fixed(1.0 - c.liftable, 2)) +
              "]";
    }
    say("scene 2", "the lift model (" + std::to_string(info.rows) + " rows of " + info.generator +
                       ", held-out accuracy " + fixed(100 * info.held_out_accuracy, 1) +
                       " %) says:" + said);
  }
  bool looked_again = false;
  for (;;) {
    const af::SeenThing* next = nullptr;
    double best = 1e9;
    for (const auto& c : scene().things) {
      if (c.tried || c.kind != af::Kind::Can) continue;
      const double failures =
          std::count(failed_colours_.begin(), failed_colours_.end(), c.colour);
      // A can the model never judged counts as even odds: after those it finds likely.
      const double unlikely =
          options_.lift_model ? 100.0 * (1.0 - (c.judged ? c.liftable : 0.5)) : 0.0;
      const double cost =
          unlikely + std::hypot(c.x - scene().robot.x, c.y - scene().robot.y) + 10.0 * failures;
      if (cost < best) {
        best = cost;
        next = &c;
      }
    }
    if (!next && !looked_again) {
      // Every candidate failed: maybe a can was hidden behind another; one more look around.
      looked_again = true;
      look_around();
      continue;
    }
    if (!next) {
      std::string tried;
      int cans = 0;
      for (const auto& c : scene().things) {
        if (c.kind != af::Kind::Can) continue;
        tried += " " + c.colour + ": " + c.outcome + ";";
        ++cans;
      }
      throw Failure{kNoLiftableCan, "no can could be lifted (" + std::to_string(cans) + " tried:" + tried + ")"};
    }
    const std::string name = next->name;
    thing(name)->tried = true;
    if (!go_to(name).done()) continue;
    const auto lifted = lift(name);
    if (lifted.done()) return;
    failed_colours_.push_back(thing(name)->colour);
  }
}

void DemoController::run() {
  start();
  set_stage("scene 1");
  look_around();
  if (std::none_of(scene().things.begin(), scene().things.end(),
                   [](const af::SeenThing& c) { return c.kind == af::Kind::Can; }))
    throw Failure{kNoCan, "no can in sight after a full turn"};
  overview_picture("scene1_cans_found");
  lift_a_can();
  set_stage("scene 3");
  if (const auto there = go_to_switch(); !there.done()) throw failure(there, kNoSwitch);
  put_down();
  set_stage("scene 4");
  if (const auto through = drive_through(); !through.done()) throw failure(through, kNoPassage);
  halt();
}

}  // namespace kurt_demo
