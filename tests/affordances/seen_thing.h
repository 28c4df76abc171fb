// Things as the scene's tests write them: a name and a colour, the rest as a first sighting.
#pragma once

#include <string>

#include "macsim/affordances/behaviours.h"

namespace macsim::affordances::test_scenes {

/// A thing of NAME and COLOUR, seen once, nothing else known of it.
inline SeenThing seen(const std::string& name, const std::string& colour) {
  SeenThing t;
  t.name = name;
  t.colour = colour;
  return t;
}

}  // namespace macsim::affordances::test_scenes
