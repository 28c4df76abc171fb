// The real KURT's documented geometry, shared with kurt_adapter (no ODE, no DDS).
#include <cmath>

#include "macsim/sim_core/kurt_sensors.h"

namespace macsim {

const std::array<RangeSensorSpec, 8>& kurt_range_sensors() {
  // kurt_driver's infrared_sonar.urdf.xacro poses; ranges and cones from kurt.h.
  constexpr double kIrFov = 0.07486, kSonarFov = 0.17809;
  static const std::array<RangeSensorSpec, 8> sensors{{
      {"ultrasound_front", 0.217, 0.0, 0.0, true, 0.10, 1.00, kSonarFov},
      {"ir_left_front", 0.203, 0.153, M_PI / 4, false, 0.10, 0.80, kIrFov},
      {"ir_left", 0.0, 0.165, M_PI / 2, false, 0.10, 0.80, kIrFov},
      {"ir_left_back", -0.203, 0.153, 3 * M_PI / 4, false, 0.10, 0.80, kIrFov},
      {"ir_back", -0.217, 0.0, M_PI, false, 0.10, 0.80, kIrFov},
      {"ir_right_back", -0.203, -0.153, 5 * M_PI / 4, false, 0.10, 0.80, kIrFov},
      {"ir_right", 0.0, -0.165, 3 * M_PI / 2, false, 0.10, 0.80, kIrFov},
      {"ir_right_front", 0.203, -0.153, 7 * M_PI / 4, false, 0.10, 0.80, kIrFov},
  }};
  return sensors;
}

}  // namespace macsim
