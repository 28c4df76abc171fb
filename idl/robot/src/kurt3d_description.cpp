#include "macsim/robot/kurt3d_description.h"

#include <sstream>

namespace macsim::robot::kurt3d {

namespace {
template <std::size_t N>
std::string numbers(const std::array<double, N>& values) {
  std::ostringstream out;
  for (std::size_t i = 0; i < N; ++i) out << (i ? " " : "") << values[i];
  return out.str();
}
}  // namespace

std::string description_text() {
  std::ostringstream out;
  out.precision(10);
  out << "robot kurt3d\n"
      << "base_mass " << kBaseMass << "\nbase_inertia " << numbers(kBaseInertia)
      << "\nbase_size " << numbers(kBaseSize) << "\ncom_below_base_link " << kComBelowBaseLink
      << "\nbase_link_above_wheel_axle " << kBaseLinkAboveWheelAxle << "\nwheel_x " << kWheelX
      << "\nwheel_y " << kWheelY << "\nwheel_width " << kWheelWidth << "\nwheel_radius "
      << kWheelRadius << "\nwheel_perimeter " << kWheelPerimeter << "\naxis_length "
      << kAxisLength << "\nturning_adaptation " << kTurningAdaptation << "\nticks_per_turn "
      << kTicksPerTurn << "\ncommand_timeout " << kCommandTimeout << "\nbase_height "
      << kBaseHeight << "\nhalf_width " << kHalfWidth << "\nfront " << kFront << "\n";
  for (const RangeSensor& s : kRangeSensors) {
    out << "range_sensor " << s.frame << " " << s.x << " " << s.y << " " << s.yaw << " "
        << (s.sonar ? 1 : 0) << " " << s.min_range << " " << s.max_range << " "
        << s.field_of_view << "\n";
  }
  out << "left_camera " << numbers(kLeftCamera) << "\ncamera_pitch " << kCameraPitch
      << "\nrotating_laser " << numbers(kRotatingLaser) << "\nfixed_laser "
      << numbers(kFixedLaser) << "\nlaser_rate " << kLaserRate << "\nrotunit_ticks "
      << kRotunitTicks << "\npivot_x " << kPivotX << "\npivot_height " << kPivotHeight
      << "\nboom_length " << kBoomLength << "\nlift_min " << kLiftMin << "\nlift_max " << kLiftMax
      << "\nmax_hoist " << kMaxHoist << "\nmagnet_height " << kMagnetHeight
      << "\nmagnet_radius " << kMagnetRadius << "\nmagnet_below_tip " << kMagnetBelowTip << "\n";
  return out.str();
}

}  // namespace macsim::robot::kurt3d
