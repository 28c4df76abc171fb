// What one affordance trial is: the affordance, and the object (or ramp) its seed draws, with
// every true property. The same seed gives the same trial on every machine and instance.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "macsim/affordances/perception.h"

namespace affordances {

/// The affordances of the seed (the perception library's: macsim/affordances/perception.h).
using macsim::affordances::Affordance;
using macsim::affordances::affordance_from_name;
using macsim::affordances::name;
/// How objects are drawn. Material: liftability follows from mass and magnetizability (each
/// material has its colour, density and friction; sizes vary). Figure11: the seed's Figure 11,
/// heavy objects are blue, every other colour is light, all magnetizable. Balanced: the draws
/// of each affordance weighted so that none of its labels falls below about a fifth.
enum class Generator { Material, Figure11, Balanced };
/// What a trial puts before the robot. Joist (a thin bar), Step (a platform), Doorstep (a low
/// bar between two walls) and Passage (two walls) are fixed across the robot's way.
enum class Shape { Box, Cylinder, LyingCylinder, Sphere, Ramp, Joist, Step, Doorstep, Passage };

const char* name(Generator generator);
const char* name(Shape shape);
std::optional<Generator> generator_from_name(const std::string& name);

/// A material of the trials (worlds/AffordanceEnvironment/materials.xml) and how it looks.
struct Material {
  const char* name;
  std::array<float, 3> colour;  ///< rgb in [0, 1]
  double density;               ///< kg/m^3
  double friction;              ///< Coulomb mu against the floor (as in the world file)
  bool magnetizable;
};

/// The object a stack trial carries with the magnet: a light magnetizable box or upright
/// cylinder beside the robot, within the crane's reach.
struct Carried {
  Shape shape = Shape::Box;
  std::array<double, 3> size{};  ///< box x,y,z; cylinder diameter,-,height (m)
  std::string material;
  std::array<float, 3> colour{};
  double density = 0, mass = 0;
  double x = 0, y = 0;  ///< where it stands (m, world frame)
};

/// The true properties of a trial's object or ramp, all drawn from its seed.
struct TrialSpec {
  Affordance affordance = Affordance::Lift;
  Generator generator = Generator::Material;
  uint64_t seed = 0;
  Shape shape = Shape::Box;
  std::array<double, 3> size{};  ///< box x,y,z; cylinder diameter,-,height; sphere diameter (m)
  std::string material;
  std::array<float, 3> colour{};
  double density = 0;   ///< kg/m^3
  double mass = 0;      ///< kg
  double friction = 0;  ///< of its material
  bool magnetizable = false;
  double x = 0,
         y = 0;  ///< where it stands (m, world frame: the robot starts at the origin facing +x)
  // ramps (Climb): width across, height of the top edge, slope
  double ramp_width = 0, ramp_height = 0, ramp_angle = 0;  ///< m, m, rad
  double yaw = 0;      ///< rad about z; a lying cylinder at 0 lies across the robot's way
  bool fixed = false;  ///< fixed to the floor (obstacles, steps, walls, ramps)
  double gap = 0;      ///< m between the walls of a Passage or Doorstep
  Carried carried;     ///< Stack: what the crane puts onto the object

  /// Height of its top above the floor, m.
  double height() const;
  /// Volume, m^3 (0 for ramps and fixed pieces).
  double volume() const;
  /// How far ahead of its middle (x) it reaches, m: a traverse trial's far edge is x + this.
  double reach_ahead() const;
};

/// The trial of that affordance, generator and seed.
TrialSpec make_trial(Affordance affordance, Generator generator, uint64_t seed);

/// The trials' materials.
const std::array<Material, 7>& materials();

}  // namespace affordances
