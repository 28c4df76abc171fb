#include "plan_controller.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>

#include <opencv2/imgproc.hpp>

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/images/image_files.h"

namespace kurt_plan {

namespace af = macsim::affordances;
namespace pddl = macsim::affordances::pddl;
namespace plan_msg = plan_msgs::msg::dds_;

namespace {

/// The least probability of an outcome a second planning round counts on, when no plan counts on
/// likely ones only.
constexpr double kUnlikely = 0.05;
constexpr int kLooksElsewhere = 2;  // looks around from elsewhere when no plan reaches the goal

std::string atoms_text(const std::vector<pddl::Atom>& atoms) {
  return atoms.empty() ? "nothing" : pddl::text(atoms);
}

/// `v` with `places` decimals.
std::string decimals(double v, int places) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", places, v);
  return text;
}

std::string effect_text(const pddl::Outcome& o) {
  std::string s = o.add.empty() ? "" : atoms_text(o.add);
  if (!o.remove.empty()) s += (s.empty() ? "" : ", ") + std::string("not ") + atoms_text(o.remove);
  return s.empty() ? "no change" : s;
}

/// The behaviour an operator runs: the longest known behaviour its name begins with ("put-down-2"
/// and "put-down-on-loaded" run put-down).
std::string behaviour_of(const std::string& op) {
  std::string best;
  for (const char* b : {"go", "lift", "put-down", "push", "drive-through", "look-around"}) {
    const std::string name = b;
    if (op.rfind(name, 0) == 0 && (op.size() == name.size() || op[name.size()] == '-') &&
        name.size() > best.size())
      best = name;
  }
  return best;
}

/// Takes the colour hints out of a problem (whether there were any).
bool drop_like_failed(pddl::Problem& p) {
  const auto before = p.init.size();
  p.init.erase(std::remove_if(p.init.begin(), p.init.end(),
                              [](const pddl::Atom& a) { return a.predicate == "like-failed"; }),
               p.init.end());
  return p.init.size() < before;
}

}  // namespace

std::optional<Goal> Goal::parse(const std::string& text) {
  Goal g;
  if (text == "through-door") return g;
  if (text == "switch-pressed") {
    g.kind = Kind::SwitchPressed;
    return g;
  }
  const std::string prefix = "on-switch:";
  if (text.rfind(prefix, 0) == 0 && text.size() > prefix.size()) {
    g.kind = Kind::OnSwitch;
    g.colour = text.substr(prefix.size());
    if (std::all_of(g.colour.begin(), g.colour.end(), [](char c) { return std::islower(static_cast<unsigned char>(c)); }))
      return g;
  }
  return std::nullopt;
}

std::string Goal::text() const {
  switch (kind) {
    case Kind::ThroughDoor: return "through-door";
    case Kind::SwitchPressed: return "switch-pressed";
    case Kind::OnSwitch: return "on-switch:" + colour;
  }
  return {};
}

PlanController::PlanController(macsim::dds::Participant& participant, const PlanOptions& options)
    : Behaviours(participant,
                 [&] {
                   af::BehaviourOptions b;
                   b.loop = options.loop;
                   b.program = "kurt_plan";
                   b.debug_images = options.debug_images;
                   b.pictures = options.pictures;
                   b.traverse_model = options.traverse_model;
                   return b;
                 }()),
      options_(options),
      plan_writer_(participant, macsim::dds::topics::plan(options.loop.robot), macsim::dds::QosFamily::Latched) {
  shown_.header().frame_id("odom");
  shown_.goal(options.goal.text());
  shown_.current(-1);
}

void PlanController::picture(const std::string& name) {
  const auto file = overview_picture(name);
  if (!file) return;
  const cv::Mat taken = macsim::images::read_image(*file);
  if (taken.empty()) {
    say(name, *file + " cannot be read here (the simulator runs elsewhere?); no plan drawn on it");
    return;
  }
  // The plan in a panel on the right: goal and round, each step coloured as it went.
  constexpr int kPanel = 460, kLine = 16;
  cv::Mat out(taken.rows, taken.cols + kPanel, CV_8UC3, cv::Scalar(30, 26, 22));
  taken.copyTo(out(cv::Rect(0, 0, taken.cols, taken.rows)));
  int y = kLine + 4;
  const auto line = [&](const std::string& text, const cv::Scalar& colour) {
    cv::putText(out, text.substr(0, 62), {taken.cols + 8, y}, cv::FONT_HERSHEY_SIMPLEX, 0.42, colour, 1, cv::LINE_AA);
    y += kLine;
  };
  line("plan " + std::to_string(shown_.round()) + " for " + shown_.goal(), cv::Scalar(255, 255, 255));
  for (std::size_t i = 0; i < shown_.steps().size(); ++i) {
    const auto& step = shown_.steps()[i];
    static const cv::Scalar kColour[] = {{200, 200, 200}, {80, 220, 255}, {120, 220, 120}, {110, 110, 240}};
    line(std::to_string(i + 1) + ". " + step.action() + "  p " + decimals(step.probability(), 2),
         kColour[std::min<int>(step.status(), 3)]);
  }
  for (const auto& t : shown_.things()) line(t.name() + ": " + t.label() + " " + decimals(t.confidence(), 2), cv::Scalar(230, 200, 160));
  const std::string drawn = std::filesystem::path(*file).replace_extension().string() + "_plan.png";
  if (macsim::images::write_image(drawn, out)) say(name, "with the plan: " + drawn);
}

std::vector<plan_msg::JudgedThing_> PlanController::judged_things() const {
  std::vector<plan_msg::JudgedThing_> out;
  for (const auto& t : scene().things) {
    if (t.lost) continue;
    plan_msg::JudgedThing_ j;
    j.name(t.name);
    j.x(t.x);
    j.y(t.y);
    j.confidence(1.0);
    const bool on_switch = std::count(scene().on_switch.begin(), scene().on_switch.end(), t.name) > 0;
    if (on_switch) {
      j.label("on the switch");
    } else if (scene().holding == t.name) {
      j.label("held");
    } else if (t.tried) {
      j.label("not liftable (tried)");
    } else {
      // How likely a plan to hold it succeeds from here, with the hand free.
      pddl::Problem p = problem({"holding", {t.name}});
      p.init.erase(std::remove_if(p.init.begin(), p.init.end(),
                                  [](const pddl::Atom& a) { return a.predicate == "holding"; }),
                   p.init.end());
      p.init.push_back({"hand-free", {}});
      const af::PlanResult r = af::plan(options_.domain, p);
      const double chance = r.plan ? r.plan->probability : 0.0;
      j.label(chance >= 0.5 ? "liftable" : "not liftable");
      j.confidence(chance >= 0.5 ? chance : 1.0 - chance);
    }
    out.push_back(std::move(j));
  }
  return out;
}

void PlanController::publish_plan() {
  shown_.header(macsim::dds::header(now_, "odom"));
  shown_.things(judged_things());
  plan_writer_.write(shown_);
}

void PlanController::publish_outcome(const std::string& line) {
  shown_.current(-1);
  shown_.outcome(line);
  publish_plan();
  // The last word of a program about to exit: its readers get it before it goes.
  plan_writer_.wait_acknowledged(std::chrono::seconds(2));
}

std::vector<pddl::Atom> PlanController::goal_atoms() const {
  switch (options_.goal.kind) {
    case Goal::Kind::ThroughDoor: return {{"beyond", {"door"}}};
    case Goal::Kind::SwitchPressed: return {{"pressed", {"switch"}}};
    case Goal::Kind::OnSwitch: {
      std::vector<pddl::Atom> out;
      for (const auto& t : scene().things)
        if (t.colour == options_.goal.colour && !t.lost) out.push_back({"on", {t.name, "switch"}});
      return out;
    }
  }
  return {};
}

pddl::Problem PlanController::problem(const pddl::Atom& goal) const {
  pddl::Problem p;
  p.name = "scene-" + std::to_string(round_);
  p.domain = options_.domain.name;
  p.note = "kurt_plan's scene at robot time " + std::to_string(elapsed()) + " s, goal " +
           options_.goal.text();
  p.objects = {{"start", "place"}, {"switch", "switch"}, {"door", "door"}};
  std::vector<const af::SeenThing*> things;
  for (const auto& t : scene().things)
    if (!t.lost) things.push_back(&t);
  const auto distance = [&](const af::SeenThing* t) {
    return std::hypot(t->x - scene().robot.x, t->y - scene().robot.y);
  };
  std::stable_sort(things.begin(), things.end(),
                   [&](const af::SeenThing* a, const af::SeenThing* b) { return distance(a) < distance(b); });
  std::vector<af::PerceivedObject> perceived;
  for (const auto* t : things) {
    p.objects.push_back({t->name, "thing"});
    perceived.push_back({t->name, "thing", t->features});
  }
  p.init = af::scene_atoms(scene());
  for (auto& a : af::threshold_atoms(options_.domain, options_.thresholds, perceived)) p.init.push_back(std::move(a));
  p.goal_true = {goal};
  return p;
}

std::optional<af::Plan> PlanController::plan_round(std::string& reason, double& seconds) {
  ++round_;
  std::optional<af::Plan> best;
  const auto goals = goal_atoms();
  if (goals.empty()) {
    reason = "no " + options_.goal.colour + " thing in sight";
    return std::nullopt;
  }
  for (const auto& goal : goals) {
    pddl::Problem p = problem(goal);
    if (!options_.problems.empty())
      pddl::save_text(options_.problems + "/" + p.name + (goals.size() > 1 ? "-" + goal.arguments[0] : "") +
                          ".pddl",
                      pddl::write(p));
    // Likely outcomes first; when none reaches the goal, one that counts on an unlikely one is
    // still worth trying (a can whose colour lifted one time in five); when nothing else is left,
    // a thing of the colour of one that did not come up may yet (colour is a hint of what a can
    // is made of, not a rule).
    af::PlanLimits unlikely;
    unlikely.min_probability = kUnlikely;
    af::PlanResult r = af::plan(options_.domain, p);
    seconds += r.seconds;
    const auto instead = [&](const pddl::Problem& q, const af::PlanLimits& limits, const std::string& said) {
      if (r.plan || r.limit_reached) return;
      const af::PlanResult other = af::plan(options_.domain, q, limits);
      seconds += other.seconds;
      if (!other.plan) return;
      say("plan", said);
      r = other;
    };
    instead(p, unlikely,
            "no plan counts on outcomes of at least " + decimals(af::PlanLimits{}.min_probability, 2) +
                "; one that counts on less likely ones:");
    if (drop_like_failed(p))
      instead(p, unlikely, "no plan without trying a thing of the colour of one that did not come up; one that does:");
    if (!r.plan) {
      reason = r.reason;
      continue;
    }
    if (!best || r.plan->steps.size() < best->steps.size() ||
        (r.plan->steps.size() == best->steps.size() && r.plan->probability > best->probability))
      best = r.plan;
  }
  return best;
}

bool PlanController::execute(const af::PlanStep& step, std::string& outcome) {
  const std::string behaviour = behaviour_of(step.operator_name);
  af::BehaviourReport report;
  if (behaviour == "go") {
    const std::string& to = step.arguments.at(1);
    if (to == "switch") {
      report = go_to_switch();
    } else if (to == "door") {
      report = go_to_door();
    } else if (to == "start") {
      report.setback = af::Setback::NotSeen;
      report.reason = "start is no place to go back to";
    } else {
      report = go_to(to);
    }
  } else if (behaviour == "lift") {
    report = lift(step.arguments.at(0));
  } else if (behaviour == "put-down") {
    report = put_down();
    perceive_door();  // watch what the load did
  } else if (behaviour == "push") {
    report = push(step.arguments.at(0));
    perceive_door();  // watch what the load did
  } else if (behaviour == "drive-through") {
    report = drive_through();
  } else if (behaviour == "look-around") {
    report = look_around();
  } else {
    report.setback = af::Setback::NotSeen;
    report.reason = "no behaviour runs '" + step.operator_name + "'";
  }
  const auto perceived = af::scene_atoms(scene());
  const std::set<pddl::Atom> now(perceived.begin(), perceived.end());
  std::vector<pddl::Atom> missing, still;
  for (const auto& a : step.expected.add)
    if (!now.count(a)) missing.push_back(a);
  for (const auto& a : step.expected.remove)
    if (now.count(a)) still.push_back(a);
  const bool as_predicted = missing.empty() && still.empty();
  outcome = as_predicted ? "as predicted" : "not as predicted:";
  if (!missing.empty()) outcome += " perceived no " + atoms_text(missing);
  if (!still.empty()) outcome += std::string(missing.empty() ? "" : ";") + " still " + atoms_text(still);
  if (!report.done()) outcome += " (" + report.reason + ")";
  say("act", step.text() + ": " + outcome);
  return as_predicted;
}

Summary PlanController::run() {
  start();
  set_stage("look");
  look_around();
  perceive_door();
  if (options_.policy == Policy::Random)
    run_random();
  else
    run_plan();
  halt();
  if (summary_.reached) summary_.exit = kReached;
  return summary_;
}

bool PlanController::goal_holds() const {
  const auto atoms = af::scene_atoms(scene());
  const std::set<pddl::Atom> now(atoms.begin(), atoms.end());
  const auto goals = goal_atoms();
  return std::any_of(goals.begin(), goals.end(), [&](const pddl::Atom& g) { return now.count(g) > 0; });
}

plan_msg::PlanStep_ PlanController::shown_step(const af::PlanStep& step) {
  plan_msg::PlanStep_ shown;
  shown.action(step.text());
  shown.predicted(effect_text(step.expected));
  shown.probability(step.probability);
  shown.status(plan_msg::STEP_TO_DO);
  return shown;
}

bool PlanController::act(std::size_t i, const af::PlanStep& step) {
  ++summary_.plan_steps;
  shown_.current(static_cast<std::int32_t>(i));
  shown_.steps()[i].status(plan_msg::STEP_UNDER_WAY);
  publish_plan();
  std::string outcome;
  const bool as_predicted = execute(step, outcome);
  shown_.steps()[i].status(as_predicted ? plan_msg::STEP_AS_PREDICTED : plan_msg::STEP_NOT_AS_PREDICTED);
  shown_.steps()[i].perceived(outcome);
  shown_.current(-1);
  publish_plan();
  picture("plan_" + std::to_string(round_) + "_step_" + std::to_string(i + 1));
  // A thing not where it was seen: the odometry moved on (the tracks slipped), so what it
  // remembers may lie off too. A look around marks what is not there and sees what is.
  const bool lost = std::any_of(scene().things.begin(), scene().things.end(), [&](const af::SeenThing& t) {
    return t.lost && std::find(step.arguments.begin(), step.arguments.end(), t.name) != step.arguments.end();
  });
  if (!as_predicted && lost) {
    set_stage("look");
    look_around();
  }
  return as_predicted;
}

bool PlanController::out_of_steps() {
  if (summary_.plan_steps < options_.max_steps) return false;
  summary_.exit = kNotReached;
  summary_.reason = "took " + std::to_string(summary_.plan_steps) + " steps, the most it may";
  return true;
}

void PlanController::run_plan() {
  Summary& summary = summary_;
  int looks_elsewhere = 0;
  while (!(summary.reached = goal_holds())) {
    set_stage("plan");
    std::string reason;
    const auto plan = plan_round(reason, summary.planning_seconds);
    if (!plan) {
      if (looks_elsewhere < kLooksElsewhere) {
        // Perhaps something was out of sight: a look around from elsewhere before giving up.
        ++looks_elsewhere;
        say("plan", "no plan (" + reason + "); looking around from elsewhere");
        set_stage("look");
        look_from_elsewhere();
        continue;
      }
      summary.exit = kUnreachable;
      summary.reason = reason;
      return;
    }
    say("plan", "plan of " + std::to_string(plan->steps.size()) + " step(s), probability " +
                    decimals(plan->probability, 3) + ":");
    for (std::size_t i = 0; i < plan->steps.size(); ++i) {
      const auto& s = plan->steps[i];
      say("plan", "  " + std::to_string(i + 1) + ". " + s.text() + " -> " + effect_text(s.expected) +
                      " (p = " + decimals(s.probability, 2) + ")");
    }
    shown_.round(static_cast<std::uint32_t>(round_));
    shown_.steps().clear();
    for (const auto& s : plan->steps) shown_.steps().push_back(shown_step(s));
    set_stage("act");
    bool replan = false;
    for (std::size_t i = 0; i < plan->steps.size() && !replan && !out_of_steps(); ++i)
      replan = !act(i, plan->steps[i]);
    if (summary.exit == kNotReached) return;
    if (replan) {
      if (++summary.replans > options_.max_replans) {
        summary.exit = kNotReached;
        summary.reason = "planned again " + std::to_string(options_.max_replans) + " times, the most it may";
        return;
      }
      say("plan", "what it perceived differs from what was predicted: planning again");
    }
  }
}

void PlanController::run_random() {
  std::mt19937 rng(options_.policy_seed);
  int looks_elsewhere = 0;
  while (!(summary_.reached = goal_holds()) && !out_of_steps()) {
    // The steps the domain allows now (the problem's goal plays no part in which).
    const auto goals = goal_atoms();
    const auto steps = af::applicable(options_.domain, problem(goals.empty() ? pddl::Atom{"beyond", {"door"}} : goals.front()));
    if (steps.empty()) {
      if (looks_elsewhere < kLooksElsewhere) {
        ++looks_elsewhere;
        set_stage("look");
        look_from_elsewhere();
        continue;
      }
      summary_.exit = kUnreachable;
      summary_.reason = "no step of the domain applies to what the robot perceives";
      return;
    }
    const auto& step = steps[std::uniform_int_distribution<std::size_t>(0, steps.size() - 1)(rng)];
    set_stage("act");
    say("act", "chosen at random from " + std::to_string(steps.size()) + " step(s): " + step.text());
    shown_.round(static_cast<std::uint32_t>(++round_));
    shown_.steps() = {shown_step(step)};
    act(0, step);
  }
}

}  // namespace kurt_plan
