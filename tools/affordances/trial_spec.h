// What one affordance trial is: the affordance, and the object (or ramp) its seed draws, with
// every true property. The same seed gives the same trial on every machine and instance.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace affordances {

/// The affordances of the seed that a trial can test.
enum class Affordance { Lift, Push, Climb };
/// How objects are drawn. Material: liftability follows from mass and magnetizability (each
/// material has its colour, density and friction; sizes vary). Figure11: the seed's Figure 11,
/// heavy objects are blue, every other colour is light, all magnetizable.
enum class Generator { Material, Figure11 };
enum class Shape { Box, Cylinder, LyingCylinder, Sphere, Ramp };

const char* name(Affordance affordance);
const char* name(Generator generator);
const char* name(Shape shape);
std::optional<Affordance> affordance_from_name(const std::string& name);
std::optional<Generator> generator_from_name(const std::string& name);

/// A material of the trials (worlds/AffordanceEnvironment/materials.xml) and how it looks.
struct Material {
  const char* name;
  std::array<float, 3> colour;  ///< rgb in [0, 1]
  double density;               ///< kg/m^3
  double friction;              ///< Coulomb mu against the floor (as in the world file)
  bool magnetizable;
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

  /// Height of its top above the floor, m.
  double height() const;
  /// Volume, m^3 (0 for ramps).
  double volume() const;
};

/// The trial of that affordance, generator and seed.
TrialSpec make_trial(Affordance affordance, Generator generator, uint64_t seed);

/// The trials' materials.
const std::array<Material, 7>& materials();

}  // namespace affordances
