// What the robot perceived, said in a planning domain's vocabulary: the behaviours' scene as PDDL
// atoms, the initial state of a plan and what an executed step is compared with.
#pragma once

#include <vector>

#include "macsim/affordances/behaviours.h"
#include "macsim/affordances/pddl.h"

namespace macsim::affordances {

/// The scene as atoms of the room's vocabulary (affordances/README.md, "The scene's atoms"):
/// robot-at, hand-free or holding, tried (a lift was tried on it), like-failed (untried, of the
/// colour of one that did not come up), box (a box the cameras saw), on, loaded, pressed (the door
/// was seen open with something on the switch), flush (a switch plate level with the floor),
/// open, beyond and opens; objects named as in the scene ("switch", "door", "start"); lost
/// things say nothing.
std::vector<pddl::Atom> scene_atoms(const Scene& scene);

}  // namespace macsim::affordances
