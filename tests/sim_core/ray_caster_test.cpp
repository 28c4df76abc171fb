// The laser's fan of rays gives the answers single rays give, geom for geom and to the bit,
// while setting aside what lies off its plane (sim_core/src/ray_caster.cpp).
#include "ray_caster.h"

#include <gtest/gtest.h>

#include <random>

#include "ode_support.h"

namespace macsim::detail {
namespace {

class RayCasterFan : public ::testing::Test {
 protected:
  RayCasterFan() {
    dInitODE2(0);
    space_ = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    dCreatePlane(space_, 0, 0, 1, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> at(-4.0, 4.0), size(0.05, 0.6), turn(-3.0, 3.0);
    for (int i = 0; i < 150; ++i) {
      dGeomID g = i % 3 == 0   ? dCreateBox(space_, size(rng), size(rng), size(rng))
                  : i % 3 == 1 ? dCreateCylinder(space_, size(rng) / 2, size(rng))
                               : dCreateSphere(space_, size(rng) / 2);
      dGeomSetPosition(g, at(rng), at(rng), std::fabs(at(rng)) / 3);
      dMatrix3 r;
      dRFromEulerAngles(r, turn(rng), turn(rng), turn(rng));
      dGeomSetRotation(g, r);
      if (i % 10 == 0) dGeomSetData(g, &robot_);  // the robot's own: never seen
    }
    robot_.group = 1;
  }
  ~RayCasterFan() override { dSpaceDestroy(space_); }

  dSpaceID space_;
  GeomTag robot_;
};

TEST_F(RayCasterFan, EveryRayOfAFanHitsWhatASingleRayHits) {
  RayCaster rays(space_, 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> at(-3.0, 3.0), angle(-M_PI, M_PI);
  int hits = 0, misses = 0;
  for (int sweep = 0; sweep < 40; ++sweep) {
    const Eigen::Vector3d origin(at(rng), at(rng), 0.2 + std::fabs(at(rng)) / 4);
    // Vertical fans turned about z (the KURT3D's rotating laser), horizontal ones (a KURT2's),
    // and fans in a tilted plane.
    const Eigen::Matrix3d turn =
        (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(sweep % 3 == 2 ? angle(rng) / 4 : 0.0, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    std::vector<Eigen::Vector3d> fan;
    for (int i = 0; i < 181; ++i) {
      const double a = -M_PI / 2 + i * M_PI / 180;
      fan.push_back(turn * (sweep % 3 == 1 ? Eigen::Vector3d(std::cos(a), std::sin(a), 0)
                                           : Eigen::Vector3d(std::cos(a), 0, std::sin(a))));
    }
    const auto together = rays.cast_fan(origin, fan, 6.0);
    ASSERT_EQ(together.size(), fan.size());
    for (std::size_t i = 0; i < fan.size(); ++i) {
      const auto alone = rays.cast(origin, fan[i], 6.0);
      ASSERT_EQ(together[i].has_value(), alone.has_value()) << "sweep " << sweep << " ray " << i;
      if (alone) {
        EXPECT_EQ(*together[i], *alone) << "sweep " << sweep << " ray " << i;
        ++hits;
      } else {
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 2000);  // the scene is full: most rays hit something, some go free
  EXPECT_GT(misses, 100);
}

TEST_F(RayCasterFan, RaysNotInOnePlaneAreCastOneByOne) {
  RayCaster rays(space_, 1);
  const Eigen::Vector3d origin(0.1, -0.2, 0.5);
  std::vector<Eigen::Vector3d> scattered;
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  for (int i = 0; i < 100; ++i)
    scattered.push_back(Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized());
  const auto together = rays.cast_fan(origin, scattered, 5.0);
  for (std::size_t i = 0; i < scattered.size(); ++i) {
    const auto alone = rays.cast(origin, scattered[i], 5.0);
    ASSERT_EQ(together[i].has_value(), alone.has_value()) << i;
    if (alone) {
      EXPECT_EQ(*together[i], *alone) << i;
    }
  }
}

// A robot's range sensors: rays from several origins, of several lengths, cast as one bundle.
TEST_F(RayCasterFan, EveryRayOfABundleHitsWhatASingleRayHits) {
  RayCaster rays(space_, 1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> at(-3.0, 3.0), angle(-M_PI, M_PI), range(0.3, 4.0);
  int hits = 0, misses = 0;
  for (int frame = 0; frame < 60; ++frame) {
    const Eigen::Vector3d centre(at(rng), at(rng), 0.15);
    std::vector<RayCaster::Ray> bundle;
    for (int sensor = 0; sensor < 8; ++sensor) {
      const Eigen::Vector3d origin = centre + Eigen::Vector3d(at(rng), at(rng), 0) / 10;
      const double yaw = angle(rng), reach = range(rng);
      for (double offset : {-0.1, 0.0, 0.1}) {
        bundle.push_back(
            {origin, Eigen::Vector3d(std::cos(yaw + offset), std::sin(yaw + offset), 0), reach});
      }
    }
    const auto together = rays.cast_bundle(bundle);
    ASSERT_EQ(together.size(), bundle.size());
    for (std::size_t i = 0; i < bundle.size(); ++i) {
      const auto alone = rays.cast(bundle[i].origin, bundle[i].direction, bundle[i].max_range);
      ASSERT_EQ(together[i].has_value(), alone.has_value()) << "frame " << frame << " ray " << i;
      if (alone) {
        EXPECT_EQ(*together[i], *alone) << "frame " << frame << " ray " << i;
        ++hits;
      } else {
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 300);
  EXPECT_GT(misses, 100);
}

}  // namespace
}  // namespace macsim::detail
