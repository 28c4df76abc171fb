#include "trial_spec.h"

#include <cmath>

namespace affordances {

namespace {

/// SplitMix64: a seed's stream of 64-bit numbers, the same on every platform (the standard
/// distributions are not).
class Draw {
 public:
  // The seed is mixed first: seed s + 1's stream is not seed s's shifted by one draw.
  explicit Draw(uint64_t seed) : state_(mix(seed ^ 0x632BE59BD9B4E019ull)) {}
  uint64_t next() { return mix(state_ += 0x9E3779B97F4A7C15ull); }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }
  /// Uniform in log space: as many objects of 0.1-1 kg as of 1-10 kg.
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  std::size_t index(std::size_t n) { return static_cast<std::size_t>(next() % n); }

 private:
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

constexpr std::array<Material, 7> kMaterials{{
    {"tin", {0.9f, 0.1f, 0.1f}, 600, 0.5, true},
    {"steel", {0.1f, 0.2f, 0.9f}, 7800, 0.6, true},
    {"plastic", {0.1f, 0.8f, 0.2f}, 300, 0.35, false},
    {"wood", {0.95f, 0.85f, 0.1f}, 600, 0.7, false},
    {"rubber", {0.85f, 0.1f, 0.8f}, 1100, 1.2, false},
    {"ice", {0.1f, 0.85f, 0.9f}, 900, 0.05, false},
    {"lead", {0.1f, 0.2f, 0.9f}, 11300, 0.6, true},
}};

const Material& material_named(const std::string& n) {
  for (const auto& m : kMaterials) {
    if (n == m.name) return m;
  }
  return kMaterials[0];
}

void set_material(TrialSpec& t, const Material& m) {
  t.material = m.name;
  t.colour = m.colour;
  t.density = m.density;
  t.friction = m.friction;
  t.magnetizable = m.magnetizable;
}

/// A random solid of `lo`..`hi` m across; lying cylinders only where rolling matters.
void draw_solid(TrialSpec& t, Draw& d, double lo, double hi, bool lying) {
  static constexpr Shape kSolids[] = {Shape::Box, Shape::Cylinder, Shape::Sphere,
                                      Shape::LyingCylinder};
  t.shape = kSolids[d.index(lying ? 4 : 3)];
  switch (t.shape) {
    case Shape::Box:
      t.size = {d.uniform(lo, hi), d.uniform(lo, hi), d.uniform(lo, hi)};
      break;
    case Shape::Cylinder:
    case Shape::LyingCylinder: {
      const double diameter = d.uniform(lo, hi);
      t.size = {diameter, diameter, d.uniform(lo, hi)};
      break;
    }
    default: {
      const double diameter = d.uniform(lo, hi);
      t.size = {diameter, diameter, diameter};
    }
  }
}

}  // namespace

const std::array<Material, 7>& materials() { return kMaterials; }

const char* name(Affordance a) {
  switch (a) {
    case Affordance::Lift:
      return "lift";
    case Affordance::Push:
      return "push";
    default:
      return "climb";
  }
}
const char* name(Generator g) { return g == Generator::Material ? "material" : "figure11"; }
const char* name(Shape s) {
  switch (s) {
    case Shape::Box:
      return "box";
    case Shape::Cylinder:
      return "cylinder";
    case Shape::LyingCylinder:
      return "lying_cylinder";
    case Shape::Sphere:
      return "sphere";
    default:
      return "ramp";
  }
}

std::optional<Affordance> affordance_from_name(const std::string& n) {
  for (auto a : {Affordance::Lift, Affordance::Push, Affordance::Climb}) {
    if (n == name(a)) return a;
  }
  return std::nullopt;
}
std::optional<Generator> generator_from_name(const std::string& n) {
  for (auto g : {Generator::Material, Generator::Figure11}) {
    if (n == name(g)) return g;
  }
  return std::nullopt;
}

double TrialSpec::height() const {
  switch (shape) {
    case Shape::LyingCylinder:
      return size[0];
    case Shape::Ramp:
      return ramp_height;
    default:
      return size[2];
  }
}

double TrialSpec::volume() const {
  switch (shape) {
    case Shape::Box:
      return size[0] * size[1] * size[2];
    case Shape::Cylinder:
    case Shape::LyingCylinder:
      return M_PI * size[0] * size[0] / 4 * size[2];
    case Shape::Sphere:
      return M_PI / 6 * size[0] * size[0] * size[0];
    default:
      return 0;
  }
}

TrialSpec make_trial(Affordance affordance, Generator generator, uint64_t seed) {
  TrialSpec t;
  t.affordance = affordance;
  t.generator = generator;
  t.seed = seed;
  Draw d(seed);
  switch (affordance) {
    case Affordance::Lift:
      if (generator == Generator::Figure11) {
        // Figure 11: blue objects are lead; red, green, yellow, magenta and cyan ones are light
        // tin, all magnetizable, 5-8 cm: the colour alone says what comes up.
        draw_solid(t, d, 0.05, 0.08, false);
        // The colours of the first six materials, blue (the heavy one) drawn as 0.
        static constexpr std::size_t kColourOf[6] = {1, 0, 2, 3, 4, 5};
        const std::size_t colour = d.index(6);
        const bool heavy = colour == 0;
        set_material(t, material_named(heavy ? "lead" : "tin"));
        t.colour = kMaterials[kColourOf[colour]].colour;
        t.density = heavy ? 11300 : d.uniform(100, 400);
        t.magnetizable = true;
      } else {
        // Each material its colour, density and magnet; sizes 4-11 cm, so the hoist's limit
        // (about 0.5 kg) falls inside the tin and steel ranges.
        // Half of them magnetizable (tin or steel).
        draw_solid(t, d, 0.04, 0.11, false);
        const std::size_t pick = d.index(8);
        set_material(t, kMaterials[pick < 4 ? pick / 2 : pick - 2]);
      }
      // Across the laser's plane (it looks straight ahead): within 1.5 cm of the robot's axis.
      t.x = d.uniform(0.95, 1.15);
      t.y = d.uniform(-0.015, 0.015);
      break;
    case Affordance::Push:
      // A solid 6-20 cm across of any material, lead too; masses from the material's density
      // (up to 90 kg).
      draw_solid(t, d, 0.06, 0.2, true);
      set_material(t, kMaterials[d.index(7)]);
      t.x = d.uniform(0.95, 1.1);
      t.y = d.uniform(-0.015, 0.015);
      break;
    case Affordance::Climb: {
      // A ramp 0.3-1.0 m wide, sloping 5-50 degrees up to 4-30 cm, at most 1.2 m long.
      t.shape = Shape::Ramp;
      set_material(t, kMaterials[d.index(6)]);
      t.ramp_width = d.uniform(0.3, 1.0);
      t.ramp_angle = d.uniform(5, 50) * M_PI / 180;
      t.ramp_height = std::min(d.uniform(0.04, 0.3), 1.2 * std::tan(t.ramp_angle));
      t.x = d.uniform(0.75, 0.9);  // the foot
      t.y = d.uniform(-0.03, 0.03);
      t.size = {t.ramp_height / std::tan(t.ramp_angle), t.ramp_width, t.ramp_height};
      break;
    }
  }
  t.mass = t.density * t.volume();
  return t;
}

}  // namespace affordances
