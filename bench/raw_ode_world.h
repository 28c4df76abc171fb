// The baseline of sim_core's cost: a world built from the same WorldSpec with plain ODE calls
// (bodies, geoms, joints, the KURT3D of vehicle_layout.h) and stepped by a minimal loop:
// collide, QuickStep, empty the contacts. Same solver settings and sleeping as sim_core.
#pragma once

#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "peer_engine.h"

struct dxWorld;
struct dxSpace;
struct dxJointGroup;
struct dxJoint;
struct dxBody;
struct dxGeom;

namespace macsim::bench {

/// Plain ODE on the spec's objects, joints and robots (no sensors, no doors' logic).
class RawOdeWorld : public PeerEngine {
 public:
  explicit RawOdeWorld(const WorldSpec& spec);
  ~RawOdeWorld() override;
  RawOdeWorld(const RawOdeWorld&) = delete;
  RawOdeWorld& operator=(const RawOdeWorld&) = delete;

  void step() override;
  void drive(double speed) override;
  std::vector<Eigen::Vector3d> object_positions() const override;
  Pose robot_pose() const override;
  double kinetic_energy() const override;

 private:
  static void near(void* data, dxGeom* a, dxGeom* b);
  dxGeom* geom(const ComponentSpec& c);
  void add_object(const ObjectSpec& o, double friction);
  void add_joint(const JointSpec& j);
  void add_robot(const RobotSpec& robot);

  dxWorld* world_;
  dxSpace* space_;
  dxJointGroup* contacts_;
  std::vector<dxJoint*> wheel_motors_;
  std::vector<std::pair<dxBody*, Eigen::Vector3d>> portable_;  ///< body, centre of mass in
                                                               ///< the object frame; spec order
  std::deque<double> frictions_;  ///< Coulomb mu per geom (geom data), stable addresses
  std::map<std::string, dxBody*> bodies_;
  dxBody* chassis_ = nullptr;
  double step_ = 0.001;
  double wheel_rate_ = 0.0;  ///< rad/s
  double wheel_radius_ = 0.06;
};

/// Steps per second of an ODE world holding n sleeping boxes (each a body and a geom, allocated
/// as sim_core allocates them) and nothing else: ODE's own cost of a world that lies still.
double sleeping_bodies_rate(int n, double step);

}  // namespace macsim::bench
