// learn_effects: learns what the KURT3D's behaviours do, from its own sensors, and writes the
// planning domain kurt_plan plans over (--affordances DIR). It plays exploration episodes on
// seeded layouts of a room (K lock-step simulators, each episode a fresh layout): the robot
// starts, looks around, then tries behaviours drawn at random among those that can start from
// what it perceives; every behaviour is a trial: the features of what it acted on before, the
// perceived change after, the scene's atoms before and after. Per behaviour the changes are
// grouped into effect categories and a tree learns to predict them (macsim/affordances/
// effects.h); the domain is read off both. Writes into DIR: trials.csv, effects.pddl (STRIPS),
// effects.ppddl (PPDDL, what kurt_plan reads), thresholds.yml, report.txt.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <functional>
#include <set>
#include <sstream>
#include <thread>

#include "macsim/affordances/behaviours.h"
#include "macsim/affordances/effects.h"
#include "macsim/affordances/scene_atoms.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"
#include "macsim/process/child_process.h"

namespace {

namespace af = macsim::affordances;
namespace pddl = macsim::affordances::pddl;
using namespace std::chrono_literals;

/// One behaviour as a trial, still with the scene's object names.
struct Played {
  std::string behaviour;  // go, lift, put-down, drive-through
  std::map<std::string, std::string> parameters;  // object -> parameter ("red_1" -> "?t")
  std::vector<double> features;
  std::vector<double> change;
  std::vector<pddl::Atom> before, after;
  std::string label;
};

/// The trials' columns per behaviour: parameters, features, changes (with resolutions).
af::BehaviourTrials columns(const std::string& behaviour) {
  af::BehaviourTrials b;
  b.behaviour = behaviour;
  if (behaviour == "go") {
    b.parameters = {{"?from", "location"}, {"?to", "location"}};
    b.changes = {{"arrived", 0.5}, {"distance_left", 0.5}};
  } else if (behaviour == "lift") {
    b.parameters = {{"?t", "thing"}};
    for (const auto& f : af::thing_features()) b.features.push_back({f, "?t"});
    b.changes = {{"held_height", 0.05}, {"robot_moved", 0.3}};
  } else if (behaviour == "put-down") {
    b.parameters = {{"?t", "thing"}, {"?s", "switch"}, {"?d", "door"}};
    b.changes = {{"held_height", 0.05}, {"door_gap", 0.2}};
  } else if (behaviour == "push") {
    b.parameters = {{"?t", "thing"}, {"?s", "switch"}, {"?d", "door"}};
    b.changes = {{"closer_to_switch", 0.2}, {"door_gap", 0.2}};
  } else {
    b.parameters = {{"?d", "door"}};
    b.changes = {{"robot_moved", 0.3}, {"beyond", 0.5}};
  }
  return b;
}

/// The scene's atoms with the behaviour's objects as its parameters; atoms naming other objects
/// are left out.
std::vector<pddl::Atom> lifted(const std::vector<pddl::Atom>& atoms,
                               const std::map<std::string, std::string>& parameters) {
  std::vector<pddl::Atom> out;
  for (const auto& a : atoms) {
    pddl::Atom l{a.predicate, {}};
    bool all = true;
    for (const auto& arg : a.arguments) {
      const auto p = parameters.find(arg);
      if (p == parameters.end()) {
        all = false;
        break;
      }
      l.arguments.push_back(p->second);
    }
    if (all) out.push_back(std::move(l));
  }
  return out;
}

std::string label_of(const af::BehaviourReport& r) {
  switch (r.setback) {
    case af::Setback::None: return "done";
    case af::Setback::NotSeen: return "not_seen";
    case af::Setback::NotHeld: return "not_held";
    case af::Setback::TooHeavy: return "too_heavy";
    case af::Setback::NoSwitch: return "no_switch";
    case af::Setback::DoorClosed: return "door_closed";
    case af::Setback::NoDoor: return "no_door";
    case af::Setback::NotThrough: return "not_through";
    case af::Setback::NotPushed: return "not_pushed";
  }
  return "?";
}

/// A behaviour's report as a trial of `behaviour` with these objects as its parameters.
Played played(const std::string& behaviour, const af::BehaviourReport& r,
              std::map<std::string, std::string> parameters) {
  Played p;
  p.behaviour = behaviour;
  p.label = label_of(r);
  const double moved = std::hypot(r.after.robot.x - r.before.robot.x, r.after.robot.y - r.before.robot.y);
  const double gap = r.after.door ? r.after.door->width : 0.0;
  if (behaviour == "go") {
    // Where it ended: at the target (as the behaviour judged), and how far from it.
    const std::string& to = r.argument;
    double left = 0;
    for (const auto& t : r.after.things)
      if (t.name == to) left = std::hypot(t.x - r.after.robot.x, t.y - r.after.robot.y);
    if (to == "switch" && r.after.switch_platform)
      left = std::hypot(r.after.switch_platform->x - r.after.robot.x, r.after.switch_platform->y - r.after.robot.y);
    if (to == "door" && r.after.door) left = std::hypot(r.after.door->x - r.after.robot.x, r.after.door->y - r.after.robot.y);
    p.change = {r.done() ? 1.0 : 0.0, left};
  } else if (behaviour == "lift") {
    const auto thing = std::find_if(r.before.things.begin(), r.before.things.end(),
                                    [&](const af::SeenThing& t) { return t.name == r.argument; });
    for (const auto& f : af::thing_features())
      p.features.push_back(thing != r.before.things.end() && thing->features.count(f) ? thing->features.at(f) : 0.0);
    p.change = {r.after.held_height - r.before.held_height, moved};
  } else if (behaviour == "put-down") {
    p.change = {r.after.held_height - r.before.held_height, gap};
  } else if (behaviour == "push") {
    // How much nearer the switch the thing stands, as the robot saw it before and after.
    const auto to_switch = [&](const af::Scene& scene) {
      const auto t = std::find_if(scene.things.begin(), scene.things.end(),
                                  [&](const af::SeenThing& s) { return s.name == r.argument; });
      if (t == scene.things.end() || !scene.switch_platform) return 0.0;
      return std::hypot(t->x - scene.switch_platform->x, t->y - scene.switch_platform->y);
    };
    p.change = {to_switch(r.before) - to_switch(r.after), gap};
  } else {
    p.change = {moved, r.after.beyond_door ? 1.0 : 0.0};
  }
  p.parameters = std::move(parameters);
  p.before = lifted(af::scene_atoms(r.before), p.parameters);
  p.after = lifted(af::scene_atoms(r.after), p.parameters);
  return p;
}

void explore_from(af::Behaviours& robot, std::mt19937& rng, int steps, std::vector<Played>& out);

/// One episode: a fresh layout, the robot's behaviours drawn at random among those that can
/// start from what it perceives, until it is through the door or `steps` behaviours ran.
std::vector<Played> explore(int domain, std::uint32_t seed, int steps) {
  macsim::dds::Participant participant({domain, "", "learn_effects"});
  af::BehaviourOptions o;
  o.loop.lockstep = true;
  o.loop.timeout = 600;
  o.loop.restart_patience = 0;
  o.verbose = false;
  af::Behaviours robot(participant, o);
  std::mt19937 rng(seed);
  std::vector<Played> out;
  robot.start();
  robot.look_around();
  robot.perceive_door();
  try {
    explore_from(robot, rng, steps, out);
    robot.halt();
  } catch (const af::LoopError& e) {
    // Out of robot time (a behaviour that kept trying): the trials so far stand; the episode's
    // simulator is stopped with it, so nothing more is sent.
    if (e.stop != af::Stop::Timeout) throw;
  }
  return out;
}

/// The episode's behaviours after the first look, appended to `out` as they end.
void explore_from(af::Behaviours& robot, std::mt19937& rng, int steps, std::vector<Played>& out) {
  std::set<std::string> pushed;
  // A load on the switch may open the door: the report's scene after it includes a look at the wall.
  const auto door_watched = [&](af::BehaviourReport r) {
    robot.perceive_door();
    r.after = robot.scene();
    return r;
  };
  for (int k = 0; k < steps && !robot.scene().beyond_door; ++k) {
    const af::Scene& s = robot.scene();
    std::vector<std::pair<double, std::function<void()>>> options;  // weight, action
    if (!s.holding.empty()) {
      if (s.at != "switch" && s.switch_platform) {
        const std::string from = af::robot_place(s);
        options.emplace_back(1.0, [&, from] { out.push_back(played("go", robot.go_to_switch(), {{from, "?from"}, {"switch", "?to"}})); });
      }
      if (s.at == "switch") {
        const std::string held = s.holding;
        options.emplace_back(1.0, [&, held] {
          out.push_back(played("put-down", door_watched(robot.put_down()), {{held, "?t"}, {"switch", "?s"}, {"door", "?d"}}));
        });
      }
    } else {
      std::vector<std::string> untried;
      for (const auto& t : s.things)
        if (!t.tried && !t.lost && t.name != s.at) untried.push_back(t.name);
      if (!untried.empty()) {
        const std::string to = untried[std::uniform_int_distribution<std::size_t>(0, untried.size() - 1)(rng)];
        const std::string from = af::robot_place(s);
        options.emplace_back(1.0, [&, to, from] { out.push_back(played("go", robot.go_to(to), {{from, "?from"}, {to, "?to"}})); });
      }
      const auto at_thing = std::find_if(s.things.begin(), s.things.end(),
                                         [&](const af::SeenThing& t) { return t.name == s.at && !t.tried && !t.lost; });
      if (at_thing != s.things.end()) {
        const std::string t = at_thing->name;
        options.emplace_back(4.0, [&, t] { out.push_back(played("lift", robot.lift(t), {{t, "?t"}})); });
      }
      if (s.door && s.at != "door") {
        const std::string from = af::robot_place(s);
        options.emplace_back(s.on_switch.empty() ? 0.5 : 4.0,
                             [&, from] { out.push_back(played("go", robot.go_to_door(), {{from, "?from"}, {"door", "?to"}})); });
      }
      if (s.at == "door")
        options.emplace_back(2.0, [&] { out.push_back(played("drive-through", robot.drive_through(), {{"door", "?d"}})); });
      // The push trials: a thing it stands at pushed toward a switch plate flush with the floor,
      // once per thing (boxes and cans alike: what moves is for the trials to tell).
      const auto at_pushable = std::find_if(s.things.begin(), s.things.end(), [&](const af::SeenThing& t) {
        return t.name == s.at && !t.lost && !pushed.count(t.name) && t.outcome != "on the switch";
      });
      const auto atoms = af::scene_atoms(s);
      const bool flush = std::count(atoms.begin(), atoms.end(), pddl::Atom{"flush", {"switch"}}) > 0;
      if (at_pushable != s.things.end() && flush) {
        const std::string t = at_pushable->name;
        options.emplace_back(2.0, [&, t] {
          pushed.insert(t);
          out.push_back(played("push", door_watched(robot.push(t)), {{t, "?t"}, {"switch", "?s"}, {"door", "?d"}}));
        });
      }
    }
    if (options.empty()) break;
    double total = 0;
    for (const auto& [w, a] : options) total += w;
    double pick = std::uniform_real_distribution<double>(0, total)(rng);
    for (auto& [w, a] : options) {
      if ((pick -= w) <= 0 || &a == &options.back().second) {
        a();
        break;
      }
    }
  }
}

/// Learns each behaviour's effects from its trials and writes DIR's files; 0, or 1 on a fault.
int learn_and_write(std::vector<af::BehaviourTrials> trials, const std::string& out_dir,
                    const std::string& source) {
  try {
    pddl::save_text(out_dir + "/trials.csv", af::write_effect_trials(trials));
    const pddl::Domain vocabulary = pddl::load_domain(macsim::dds::data_file("affordances/kurt3d_room_by_hand.pddl"));
    for (auto& t : trials) af::keep_typed_atoms(vocabulary, t);
    std::vector<af::LearnedBehaviour> learned;
    std::ostringstream report;
    for (const auto& t : trials) {
      learned.push_back(af::learn_behaviour(t));
      const auto& l = learned.back();
      report << t.behaviour << ": " << t.trials.size() << " trials, " << l.categories.count
             << " effect categories (k-means, silhouette), " << l.rules.size() << " rules, held-out accuracy "
             << (l.held_out_trials ? std::to_string(100 * l.held_out_accuracy).substr(0, 5) + " %" : "n/a")
             << " of " << l.held_out_trials << ", adjusted Rand index with the labels "
             << std::to_string(l.categories.adjusted_rand).substr(0, 5) << "\n";
      for (const auto& [key, count] : l.categories.with_label)
        report << "  e" << key.first + 1 << " " << key.second << ": " << count << "\n";
    }
    const af::LearnedDomain domain = af::learned_domain(vocabulary, trials, learned);
    pddl::Domain written = domain.domain;
    written.note = "Learned by learn_effects from " + source + ".";
    pddl::save_text(out_dir + "/effects.pddl", pddl::write(written, pddl::Dialect::Strips));
    pddl::save_text(out_dir + "/effects.ppddl", pddl::write(written, pddl::Dialect::Probabilistic));
    af::save_thresholds(domain.thresholds, out_dir + "/thresholds.yml");
    pddl::save_text(out_dir + "/report.txt", report.str());
    std::printf("%s", report.str().c_str());
    return 0;
  } catch (const std::exception& e) {
    macsim::log::error("learn_effects: {}", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{-1, "", "learn_effects"};
  std::string out_dir;
  std::vector<std::string> worlds;
  int seed = 3;
  int episodes = 40, instances = 2, steps = 16;
  macsim::dds::CommandLine cli(
      "learn_effects",
      "Learns what the KURT3D's behaviours do from exploration episodes on K lock-step simulators "
      "(each episode a fresh layout of the world) and writes the planning domain kurt_plan plans "
      "over into DIR: trials.csv, effects.pddl, effects.ppddl, thresholds.yml, report.txt.\n"
      "--domain N is the first simulator's DDS domain (the others follow); required.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("out", "DIR", "where the trials, the domain and the report go (required)", &out_dir);
  cli.option("seed", "S", "episode e plays the world's layout S*1000+e (default 3: layouts 3001-; 1001-1050 are kept for measuring)", &seed);
  cli.option("episodes", "N", "exploration episodes (default 40)", &episodes);
  cli.option("instances", "K", "simulators side by side (default 2)", &instances);
  cli.option("steps", "N", "behaviours per episode at most (default 16)", &steps);
  cli.repeated_option("world", "FILE",
                      "a room to explore, repeatable: episode e plays the (e mod count)-th (default "
                      "worlds/behaviour_trials.xml, the demonstrator's room, its switch from softer than one "
                      "can to stiffer, and worlds/goals/push_to_switch.xml, a switch flush with the floor and "
                      "boxes to push)",
                      &worlds);
  std::string from_trials;
  cli.option("from-trials", "FILE",
             "learn from the rows of an earlier run (its DIR/trials.csv) instead of playing episodes",
             &from_trials);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (out_dir.empty() || seed < 0 || episodes < 1 || instances < 1 || instances > 16 || steps < 1) {
    macsim::log::error("learn_effects: --out DIR is required; --episodes, --steps positive, --instances 1-16");
    return 2;
  }
  if (worlds.empty())
    worlds = {macsim::dds::data_file("worlds/behaviour_trials.xml"),
              macsim::dds::data_file("worlds/goals/push_to_switch.xml")};
  for (const auto& world : worlds) {
    if (from_trials.empty() && !std::filesystem::is_regular_file(world)) {
      macsim::log::error("learn_effects: --world {}: no such world file", world);
      return 2;
    }
  }
  std::filesystem::create_directories(out_dir);
  if (!from_trials.empty()) {
    try {
      std::ifstream in(from_trials);
      if (!in) throw pddl::PddlError(from_trials + ": cannot be read");
      std::stringstream text;
      text << in.rdbuf();
      return learn_and_write(af::read_effect_trials(text.str(), from_trials), out_dir,
                             "the rows of " + from_trials);
    } catch (const std::exception& e) {
      macsim::log::error("learn_effects: {}", e.what());
      return 2;
    }
  }
  const auto started = std::chrono::steady_clock::now();
  std::vector<std::pair<std::uint32_t, std::vector<Played>>> results;
  std::mutex lock;
  std::atomic<int> next{0}, failures{0};
  auto worker = [&](int index) {
    const int domain = participant.domain + index;
    for (int e; (e = next++) < episodes;) {
      const std::uint32_t layout = static_cast<std::uint32_t>(seed) * 1000 + static_cast<std::uint32_t>(e) + 1;
      try {
        macsim::process::Options output;
        output.output = macsim::process::Output::file(out_dir + "/macsim_domain_" + std::to_string(domain) + ".log");
        macsim::process::ChildProcess simulator(
            {macsim::process::sibling_program("macsim"), "--world", worlds[static_cast<std::size_t>(e) % worlds.size()],
             "--seed", std::to_string(layout),
             "--domain", std::to_string(domain), "--lockstep", "--quiet"},
            output);
        auto played = explore(domain, layout, steps);
        std::lock_guard<std::mutex> guard(lock);
        results.emplace_back(layout, std::move(played));
        std::printf("learn_effects: episode %d (layout %u) on domain %d: %zu behaviour(s)\n", e + 1, layout,
                    domain, results.back().second.size());
        std::fflush(stdout);
      } catch (const std::exception& ex) {
        ++failures;
        std::lock_guard<std::mutex> guard(lock);
        macsim::log::warn("learn_effects: episode {} (layout {}) failed: {}", e + 1, layout, ex.what());
      }
    }
  };
  std::vector<std::thread> threads;
  for (int i = 0; i < instances; ++i) threads.emplace_back(worker, i);
  for (auto& t : threads) t.join();
  std::sort(results.begin(), results.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  // The trials per behaviour, in a fixed order.
  std::vector<af::BehaviourTrials> trials;
  for (const char* b : {"go", "lift", "put-down", "push", "drive-through"}) trials.push_back(columns(b));
  for (const auto& [layout, played] : results) {
    int index = 0;
    for (const auto& p : played) {
      auto& b = *std::find_if(trials.begin(), trials.end(), [&](const af::BehaviourTrials& t) { return t.behaviour == p.behaviour; });
      b.trials.push_back({static_cast<std::uint64_t>(layout) * 100 + static_cast<std::uint64_t>(index++), p.label,
                          p.features, p.change, p.before, p.after});
    }
  }
  trials.erase(std::remove_if(trials.begin(), trials.end(), [](const af::BehaviourTrials& t) { return t.trials.empty(); }),
               trials.end());
  if (const int status = learn_and_write(trials, out_dir, std::to_string(results.size()) +
                                                            " exploration episodes (seed " +
                                                            std::to_string(seed) + ")"))
    return status;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf("learn_effects: %zu episode(s), %d failed, wall time %.0f s; the domain is %s/effects.ppddl\n",
              results.size(), failures.load(), wall, out_dir.c_str());
  return results.empty() ? 1 : 0;
}
