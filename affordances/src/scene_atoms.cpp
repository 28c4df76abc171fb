#include "macsim/affordances/scene_atoms.h"

#include <algorithm>

namespace macsim::affordances {

std::vector<pddl::Atom> scene_atoms(const Scene& scene) {
  std::vector<pddl::Atom> atoms{{"robot-at", {robot_place(scene)}}};
  if (scene.holding.empty()) atoms.push_back({"hand-free", {}});
  else atoms.push_back({"holding", {scene.holding}});
  for (const auto& t : scene.things) {
    if (t.lost) continue;
    if (t.tried) atoms.push_back({"tried", {t.name}});
    // Untried, but of the colour of one that did not come up.
    const bool like_failed = std::any_of(scene.things.begin(), scene.things.end(), [&](const SeenThing& o) {
      return o.tried && o.colour == t.colour && o.outcome != "lifted";
    });
    if (!t.tried && like_failed) atoms.push_back({"like-failed", {t.name}});
    if (t.kind == Kind::Box) atoms.push_back({"box", {t.name}});
  }
  for (const auto& t : scene.on_switch) atoms.push_back({"on", {t, "switch"}});
  if (!scene.on_switch.empty()) atoms.push_back({"loaded", {"switch"}});
  if (scene.door && !scene.on_switch.empty()) atoms.push_back({"pressed", {"switch"}});
  if (scene.door) atoms.push_back({"open", {"door"}});
  if (scene.beyond_door) atoms.push_back({"beyond", {"door"}});
  if (scene.switch_platform) atoms.push_back({"opens", {"switch", "door"}});
  if (flush_switch(scene)) atoms.push_back({"flush", {"switch"}});
  std::sort(atoms.begin(), atoms.end());
  return atoms;
}

}  // namespace macsim::affordances
