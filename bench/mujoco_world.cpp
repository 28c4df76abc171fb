#include "mujoco_world.h"

#include <mujoco/mujoco.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "macsim/sim_core/kurt_robot.h"
#include "vehicle_layout.h"

namespace macsim::bench {

namespace {

std::string vec(const Eigen::Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", v.x(), v.y(), v.z());
  return buf;
}

std::string quat(const Eigen::Quaterniond& q) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g", q.w(), q.x(), q.y(), q.z());
  return buf;
}

/// A <geom> for one component at `pose` relative to its body (MuJoCo sizes are half sizes).
std::string geom_xml(const ComponentSpec& c, const Pose& pose, const std::string& extra) {
  std::ostringstream g;
  g << "<geom ";
  switch (c.shape) {
    case Shape::Box:
      g << "type='box' size='" << vec(c.size / 2) << "'";
      break;
    case Shape::Cylinder:
      g << "type='cylinder' size='" << c.size.x() << " " << c.size.z() / 2 << "'";
      break;
    case Shape::Sphere:
      g << "type='sphere' size='" << c.size.x() << "'";
      break;
  }
  g << " pos='" << vec(pose.position) << "' quat='" << quat(pose.orientation) << "' " << extra
    << "/>\n";
  return g.str();
}

/// MuJoCo takes the larger friction of a contact's two geoms; sim_core the geometric mean. Each
/// geom gets sqrt(mu x ground mu) and the floor 0, so every contact with the floor has sim_core's
/// friction (contacts between objects: the larger of the two means).
std::string friction(double mu, double ground) {
  return "friction='" + std::to_string(std::sqrt(mu * ground)) + " 0.005 0.0001'";
}

/// Joint axis and anchor in the frame of a body at `body`.
std::string joint_xml(const char* type, const Pose& body, const Eigen::Vector3d& anchor,
                      const Eigen::Vector3d& axis, double lo, double hi, const std::string& name) {
  const Pose inv = body.inverse();
  std::ostringstream j;
  const Eigen::Vector3d local_anchor = inv.orientation * anchor + inv.position;
  const Eigen::Vector3d local_axis = inv.orientation * axis;
  j << "<joint name='" << name << "' type='" << type << "' pos='" << vec(local_anchor) << "' axis='"
    << vec(local_axis) << "'";
  if (std::isfinite(lo) && std::isfinite(hi) && hi > lo) {
    j << " limited='true' range='" << lo << " " << hi << "'";
  }
  j << "/>\n";
  return j.str();
}

/// A velocity servo: force = kv (set-point - rate), saturated at the motor's limit, as ODE's
/// joint motor is (full force 0.1 rad/s or m/s off the set-point; stiffer gains made the
/// wheels spin up unstably at a 1 ms step, even with the implicit integrator).
std::string servo_xml(const std::string& joint, double max_force, const std::string& name) {
  std::ostringstream a;
  a << "<velocity name='" << name << "' joint='" << joint << "' kv='" << max_force / 0.1
    << "' forcelimited='true' forcerange='" << -max_force << " " << max_force << "'/>\n";
  return a.str();
}

}  // namespace

std::string mujoco_version() { return mj_versionString(); }

std::string mjcf_from_spec(const WorldSpec& spec, const MujocoOptions& options) {
  int portable = 0;
  for (const auto& o : spec.objects) portable += o.portable ? 1 : 0;
  // Degrees of freedom, about: free bodies, joints, the robots' free chassis and nine joints.
  const int nv = 6 * portable + static_cast<int>(spec.joints.size()) +
                 15 * static_cast<int>(spec.robots.size());
  // Room for about four contacts per object and the robot's, four rows each (pyramidal cones).
  // MuJoCo 2.2.2's buffer size is an int and its constraint arrays are dense (njmax x nv,
  // njmax x njmax): njmax is capped where the buffer still fits in 2 GiB. A scene needing more
  // drops contacts, which overflows() reports.
  const int nconmax = 100 + 4 * portable;
  const double per_row = 24.0 * nv + 400.0, budget = 1.8e9;  // 12 njmax^2 + per_row njmax
  const int fits = static_cast<int>((-per_row + std::sqrt(per_row * per_row + 48 * budget)) / 24);
  const int njmax = std::min(4 * nconmax, fits);
  std::ostringstream x;
  x << "<mujoco model='" << spec.name << "'>\n<compiler angle='radian'/>\n"
    << "<option timestep='" << spec.physics.step << "' gravity='" << vec(spec.physics.gravity)
    << "' integrator='" << options.integrator << "'>"
    << (options.multiccd ? "<flag multiccd='enable'/>" : "") << "</option>\n"
    << "<size nconmax='" << nconmax << "' njmax='" << njmax
    << "'/>\n"
    // The robot's parts touch the world but not each other (contype 2), as in sim_core.
    << "<worldbody>\n<geom name='floor' type='plane' size='0 0 1' contype='1' conaffinity='3' "
    << friction(0.0, 0.0) << "/>\n";
  std::string actuators;
  for (const auto& o : spec.objects) {
    const MaterialSpec* material = spec.material(o.material);
    const std::string surface =
        friction(material ? material->friction : 1.0, spec.ground_friction) +
        " contype='1' conaffinity='3'";
    if (!o.portable) {
      for (const auto& c : o.components) x << geom_xml(c, o.pose * c.pose, surface);
      continue;
    }
    x << "<body name='" << o.name << "' pos='" << vec(o.pose.position) << "' quat='"
      << quat(o.pose.orientation) << "'>\n";
    bool jointed = false;
    for (std::size_t i = 0; i < spec.joints.size(); ++i) {
      const JointSpec& j = spec.joints[i];
      if (j.body1 != o.name) continue;
      const std::string name = "joint" + std::to_string(i);
      x << joint_xml(j.type == JointSpec::Type::Slider ? "slide" : "hinge", o.pose, j.anchor,
                     j.axis, j.lo, j.hi, name);
      if (j.max_force > 0) actuators += servo_xml(name, j.max_force, name + "_motor");
      jointed = true;
    }
    if (!jointed) x << "<freejoint/>\n";
    for (const auto& c : o.components)
      x << geom_xml(c, c.pose, surface + " density='" + std::to_string(o.density) + "'");
    x << "</body>\n";
  }
  for (const auto& robot : spec.robots) {
    const KurtConfig* config = find_kurt_type(robot.type);
    const VehicleLayout layout = vehicle_layout(config ? *config : KurtConfig{}, robot.pose);
    // The body tree: chassis (free) > wheels, turret > boom > magnet. Each child's joint
    // names the part it hangs from; nested bodies take poses relative to their parent.
    std::vector<int> parent(layout.parts.size(), -1);
    std::vector<const VehicleJoint*> joint_of(layout.parts.size(), nullptr);
    for (const auto& j : layout.joints) {
      parent[j.child] = j.parent;
      joint_of[j.child] = &j;
    }
    std::function<void(int)> emit = [&](int i) {
      const VehiclePart& part = layout.parts[i];
      const Pose local =
          parent[i] < 0 ? part.pose : layout.parts[parent[i]].pose.inverse() * part.pose;
      const std::string name = robot.name + "_" + part.name + std::to_string(i);
      x << "<body name='" << name << "' pos='" << vec(local.position) << "' quat='"
        << quat(local.orientation) << "'>\n";
      if (parent[i] < 0) {
        x << "<freejoint/>\n";
      } else {
        const VehicleJoint& j = *joint_of[i];
        x << joint_xml(j.slider ? "slide" : "hinge", part.pose, j.anchor, j.axis, j.lo, j.hi,
                       name + "_joint");
        actuators += servo_xml(name + "_joint", j.max_force, name + "_motor");
      }
      // Inertia as given, or the shape's own (MuJoCo's from the geom's mass).
      std::string mass = " mass='" + std::to_string(part.mass) + "'";
      if (part.inertia.squaredNorm() > 0) {
        x << "<inertial pos='0 0 0' mass='" << part.mass << "' diaginertia='" << vec(part.inertia)
          << "'/>\n";
        mass = " mass='0'";
      }
      const double mu = i >= 1 && i <= 6 ? layout.wheel_friction : 1.0;
      x << geom_xml(part.shape, part.shape.pose,
                    friction(mu, spec.ground_friction) + " contype='2' conaffinity='1'" + mass);
      for (std::size_t c = 0; c < layout.parts.size(); ++c) {
        if (parent[c] == i) emit(static_cast<int>(c));
      }
      x << "</body>\n";
    };
    emit(0);
  }
  x << "</worldbody>\n<actuator>\n" << actuators << "</actuator>\n</mujoco>\n";
  return x.str();
}

MujocoWorld::MujocoWorld(const WorldSpec& spec, const MujocoOptions& options) {
  // MuJoCo prints its warnings to stdout; they are counted in mjData and reported instead.
  mju_user_warning = [](const char*) {};
  const std::string xml = mjcf_from_spec(spec, options);
  const auto path = std::filesystem::temp_directory_path() /
                    ("bench_peers_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << xml;
  char error[1000] = "";
  model_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  if (!model_) throw std::runtime_error("MuJoCo rejected the scene: " + std::string(error));
  data_ = mj_makeData(model_);
  if (!data_) throw std::runtime_error("MuJoCo could not allocate the scene's data");
  mj_forward(model_, data_);  // poses of the first state, before any step
  for (const auto& o : spec.objects) {
    if (o.portable) portable_.push_back(mj_name2id(model_, mjOBJ_BODY, o.name.c_str()));
  }
  if (!spec.robots.empty()) {
    const std::string robot = spec.robots[0].name;
    chassis_ = mj_name2id(model_, mjOBJ_BODY, (robot + "_chassis0").c_str());
    for (int i = 1; i <= 6; ++i) {
      wheel_actuators_.push_back(mj_name2id(
          model_, mjOBJ_ACTUATOR, (robot + "_wheel" + std::to_string(i) + "_motor").c_str()));
    }
    const KurtConfig* config = find_kurt_type(spec.robots[0].type);
    wheel_radius_ = (config ? *config : KurtConfig{}).drive.wheel_radius();
  }
}

MujocoWorld::~MujocoWorld() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

void MujocoWorld::step() { mj_step(model_, data_); }

void MujocoWorld::drive(double speed) {
  for (int a : wheel_actuators_) data_->ctrl[a] = speed / wheel_radius_;
}

std::vector<Eigen::Vector3d> MujocoWorld::object_positions() const {
  std::vector<Eigen::Vector3d> out;
  for (int b : portable_)
    out.emplace_back(data_->xpos[3 * b], data_->xpos[3 * b + 1], data_->xpos[3 * b + 2]);
  return out;
}

Pose MujocoWorld::robot_pose() const {
  if (chassis_ < 0) return {};
  const mjtNum* p = data_->xpos + 3 * chassis_;
  const mjtNum* q = data_->xquat + 4 * chassis_;
  return {{p[0], p[1], p[2]}, Eigen::Quaterniond(q[0], q[1], q[2], q[3])};
}

double MujocoWorld::kinetic_energy() const {
  double e = 0.0;
  for (int b : portable_) {
    mjtNum v[6];
    mj_objectVelocity(model_, data_, mjOBJ_BODY, b, v, 0);
    e += 0.5 * model_->body_mass[b] * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
  }
  return e;
}

int MujocoWorld::overflows() const {
  return data_->warning[mjWARN_CONTACTFULL].number + data_->warning[mjWARN_CNSTRFULL].number;
}

}  // namespace macsim::bench
