// Something that happened in a world: typed, timed, naming what it happened to.
#pragma once

#include <string>

namespace macsim {

/// Something that happened during a step or an operation, for the supervisor's clients.
struct WorldEvent {
  enum class Type {
    SwitchTriggered,
    SwitchReleased,
    DoorOpened,
    DoorClosed,
    Penetration,
    Instability,
    ObjectAttached,  ///< a robot's magnet grabbed an object (subject: robot, detail: object)
    ObjectReleased,  ///< a robot's magnet let go (detail: object and why)
  };
  Type type;
  double time = 0.0;
  std::string subject;  ///< object or door name
  std::string detail;
};

}  // namespace macsim
