#include "macsim/dds/convert.h"

#include <cfloat>

namespace macsim::dds {

void set_driver_covariance(nav_msgs::msg::dds_::Odometry_& msg, double linear, double angular) {
  constexpr double kSigmaX = 0.002, kSigmaTheta = 0.017;
  constexpr double kCovXY = 0.0, kCovXTheta = 0.0, kCovYTheta = 0.0;
  const bool standing = std::fabs(linear) <= 1e-8 && std::fabs(angular) <= 1e-8;
  std::array<double, 36> twist{};
  twist[0] = standing ? 1e-12 : kSigmaX * kSigmaX;
  twist[35] = standing ? 1e-12 : kSigmaTheta * kSigmaTheta;
  twist[30] = twist[5] = standing ? 1e-12 : kCovXTheta;
  twist[7] = twist[14] = twist[21] = twist[28] = DBL_MAX;
  std::array<double, 36> pose = twist;
  pose[7] = standing ? 1e-12 : kSigmaX * kSigmaX * kSigmaTheta * kSigmaTheta;
  pose[1] = pose[6] = standing ? 1e-12 : kCovXY;
  pose[31] = pose[11] = standing ? 1e-12 : kCovYTheta;
  msg.twist().covariance(twist);
  msg.pose().covariance(pose);
}

}  // namespace macsim::dds
