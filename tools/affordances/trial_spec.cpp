#include "trial_spec.h"

#include <array>
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

/// Uniform in [lo, hi), m; a range of one value is that value and draws nothing.
struct Range {
  double lo = 0, hi = 0;
};

/// The ranges one kind is sized by: a box's (a joist's, a step's) x, y and z; a cylinder's
/// diameter (x) and length (z); a sphere's diameter (x).
struct KindSizes {
  Shape shape;
  Range x, y, z;
};

double draw_in(Draw& d, Range r) { return r.lo == r.hi ? r.lo : d.uniform(r.lo, r.hi); }

/// Sizes `t` (its shape drawn already) by its kind's row of `table`, drawing x, y and z in that
/// order (a round kind: its diameter, then a cylinder's length).
template <std::size_t N>
void draw_size(TrialSpec& t, Draw& d, const std::array<KindSizes, N>& table) {
  const KindSizes* row = &table.front();
  for (const auto& k : table) {
    if (k.shape == t.shape) row = &k;
  }
  switch (t.shape) {
    case Shape::Cylinder:
    case Shape::LyingCylinder: {
      const double diameter = draw_in(d, row->x);
      t.size = {diameter, diameter, draw_in(d, row->z)};
      break;
    }
    case Shape::Sphere: {
      const double diameter = draw_in(d, row->x);
      t.size = {diameter, diameter, diameter};
      break;
    }
    default: {
      const double x = draw_in(d, row->x), y = draw_in(d, row->y);
      t.size = {x, y, draw_in(d, row->z)};
    }
  }
}

/// A random solid of `lo`..`hi` m across; lying cylinders only where rolling matters.
void draw_solid(TrialSpec& t, Draw& d, double lo, double hi, bool lying) {
  static constexpr Shape kSolids[] = {Shape::Box, Shape::Cylinder, Shape::Sphere,
                                      Shape::LyingCylinder};
  t.shape = kSolids[d.index(lying ? 4 : 3)];
  const Range any{lo, hi};
  draw_size(t, d,
            std::array<KindSizes, 4>{{{Shape::Box, any, any, any},
                                      {Shape::Cylinder, any, {}, any},
                                      {Shape::LyingCylinder, any, {}, any},
                                      {Shape::Sphere, any, {}, {}}}});
}

/// The stack trials' bases, m.
constexpr std::array<KindSizes, 4> kStackBases{{
    {Shape::Box, {0.08, 0.25}, {0.08, 0.25}, {0.04, 0.22}},
    {Shape::Cylinder, {0.06, 0.25}, {}, {0.04, 0.22}},
    {Shape::LyingCylinder, {0.06, 0.22}, {}, {0.15, 0.35}},
    {Shape::Sphere, {0.08, 0.25}, {}, {}},
}};

/// The traverse trials' obstacles sized by ranges alone, m (a joist and a step span 1 m
/// across); doorsteps, passages and ramps are drawn by their own rules (draw_traverse).
constexpr std::array<KindSizes, 6> kTraverseSizes{{
    {Shape::Box, {0.1, 0.4}, {0.15, 0.6}, {0.02, 0.3}},
    {Shape::Cylinder, {0.06, 0.3}, {}, {0.02, 0.4}},
    {Shape::LyingCylinder, {0.05, 0.25}, {}, {0.15, 0.5}},
    {Shape::Sphere, {0.05, 0.3}, {}, {}},
    {Shape::Joist, {0.03, 0.08}, {1.0, 1.0}, {0.01, 0.12}},
    {Shape::Step, {0.2, 0.4}, {1.0, 1.0}, {0.02, 0.15}},
}};

/// A base to stack onto (Stack): a box, upright or lying cylinder or sphere of any material,
/// standing in the laser's plane; and beside the robot, the light magnetizable object the crane
/// carries onto it. `balanced` draws a third each of bases that hold a load, lying cylinders
/// and small light spheres (below).
void draw_stack(TrialSpec& t, Draw& d, bool balanced) {
  static constexpr Shape kBases[] = {Shape::Box, Shape::Cylinder, Shape::LyingCylinder,
                                     Shape::Sphere};
  // Balanced: a third boxes and upright cylinders (which mostly hold), a third lying cylinders
  // (the load slides off), a third spheres light and small enough to roll away under a load
  // set off their top (plastic or wood, 6-12 cm: 1,000 trials rolled all of 8-11 cm, half of
  // 14-16 cm).
  static constexpr std::size_t kBalanced[] = {0, 0, 1, 2, 2, 2, 3, 3, 3};
  t.shape = kBases[balanced ? kBalanced[d.index(9)] : d.index(4)];
  draw_size(t, d, kStackBases);
  if (balanced && t.shape == Shape::Sphere) {
    set_material(t, material_named(d.index(2) == 0 ? "plastic" : "wood"));
    t.size[0] = t.size[1] = t.size[2] = d.uniform(0.06, 0.12);
  } else {
    set_material(t, kMaterials[d.index(kMaterials.size())]);
  }
  t.x = d.uniform(0.95, 1.1);
  t.y = d.uniform(-0.015, 0.015);
  // The carried object: tin, 4-8 cm across and 3-8 cm high (at most about 0.3 kg: the hoist
  // lifts about 0.5 kg), on the floor to the robot's left where the boom reaches level
  // (0.5 m from the slew axis, 1.3 rad from ahead): out of the cameras' and the laser's view.
  Carried& c = t.carried;
  c.shape = d.index(2) == 0 ? Shape::Box : Shape::Cylinder;
  const double across = d.uniform(0.04, 0.08);
  c.size = {across, c.shape == Shape::Box ? d.uniform(0.04, 0.08) : across, d.uniform(0.03, 0.08)};
  const Material& tin = material_named("tin");
  c.material = tin.name;
  c.colour = tin.colour;
  c.density = tin.density;
  c.mass = c.density * c.size[2] *
           (c.shape == Shape::Box ? c.size[0] * c.size[1] : M_PI * across * across / 4);
  c.x = 0.05 + 0.5 * std::cos(1.3);
  c.y = 0.5 * std::sin(1.3);
}

/// An obstacle or passage ahead (Traverse), its near edge 0.62-0.75 m ahead of the robot's
/// middle: fixed boxes, upright cylinders, joists, steps, doorsteps, passages and ramps;
/// portable lying cylinders (any yaw) and spheres. `balanced` draws passages around the
/// robot's width more often.
void draw_traverse(TrialSpec& t, Draw& d, bool balanced) {
  static constexpr Shape kKinds[] = {Shape::Box,      Shape::Cylinder, Shape::LyingCylinder,
                                     Shape::Sphere,   Shape::Joist,    Shape::Step,
                                     Shape::Doorstep, Shape::Passage,  Shape::Ramp};
  t.shape = kKinds[d.index(9)];
  set_material(t, kMaterials[d.index(kMaterials.size())]);
  t.fixed = t.shape != Shape::LyingCylinder && t.shape != Shape::Sphere;
  switch (t.shape) {
    case Shape::Box:
    case Shape::Cylinder:
    case Shape::Sphere:
    case Shape::Joist:
    case Shape::Step:
      draw_size(t, d, kTraverseSizes);
      break;
    case Shape::LyingCylinder:  // at any yaw: it rolls away when pushed, or does not
      draw_size(t, d, kTraverseSizes);
      t.yaw = d.uniform(-M_PI / 2, M_PI / 2);
      break;
    case Shape::Doorstep:  // a bar between two walls 0.4 m high, 0.15 m deep
      t.gap = d.uniform(0.3, 0.7);
      t.size = {d.uniform(0.03, 0.08), t.gap, d.uniform(0.01, 0.08)};
      break;
    case Shape::Passage:  // two walls 0.4 m high; balanced: half of them around the robot's
                          // width (0.325 m), where the laser must tell them apart
      t.gap = balanced && d.index(2) == 0 ? d.uniform(0.26, 0.42) : d.uniform(0.2, 0.6);
      t.size = {d.uniform(0.15, 0.5), t.gap, 0.4};
      break;
    default: {  // a ramp as the climb trials draw them, its foot the near edge
      t.ramp_width = d.uniform(0.4, 1.0);
      t.ramp_angle = d.uniform(5, 40) * M_PI / 180;
      t.ramp_height = std::min(d.uniform(0.04, 0.2), 0.8 * std::tan(t.ramp_angle));
      t.size = {t.ramp_height / std::tan(t.ramp_angle), t.ramp_width, t.ramp_height};
    }
  }
  // Beyond the magnet, which hangs 0.55 m ahead at the reset.
  const double near = d.uniform(0.62, 0.75);
  t.x = t.shape == Shape::Ramp ? near : near + t.reach_ahead();
  t.y = t.shape == Shape::Passage || t.shape == Shape::Doorstep ? d.uniform(-0.01, 0.01)
                                                                : d.uniform(-0.02, 0.02);
}

}  // namespace

const std::array<Material, 7>& materials() { return kMaterials; }

const char* name(Generator g) {
  switch (g) {
    case Generator::Material:
      return "material";
    case Generator::Figure11:
      return "figure11";
    default:
      return "balanced";
  }
}
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
    case Shape::Ramp:
      return "ramp";
    case Shape::Joist:
      return "joist";
    case Shape::Step:
      return "step";
    case Shape::Doorstep:
      return "doorstep";
    default:
      return "passage";
  }
}

std::optional<Generator> generator_from_name(const std::string& n) {
  for (auto g : {Generator::Material, Generator::Figure11, Generator::Balanced}) {
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
  if (fixed) return 0;
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

double TrialSpec::reach_ahead() const {
  switch (shape) {
    case Shape::Cylinder:
    case Shape::Sphere:
      return size[0] / 2;
    case Shape::LyingCylinder:  // its axis along y turned by yaw: (-sin yaw, cos yaw, 0)
      return size[2] / 2 * std::fabs(std::sin(yaw)) + size[0] / 2 * std::fabs(std::cos(yaw));
    case Shape::Ramp:  // x is its foot
      return size[0];
    default:
      return size[0] / 2;
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
      // (up to 90 kg). Balanced: a third of them big lead boxes or upright cylinders (14-20 cm,
      // 24-90 kg: what the robot cannot move), as `material` stalls about 4 % of its trials.
      if (generator == Generator::Balanced && d.index(3) == 0) {
        draw_solid(t, d, 0.14, 0.2, false);
        if (t.shape == Shape::Sphere) t.shape = Shape::Box, t.size[1] = t.size[2] = t.size[0];
        set_material(t, material_named("lead"));
      } else {
        draw_solid(t, d, 0.06, 0.2, true);
        set_material(t, kMaterials[d.index(7)]);
      }
      t.x = d.uniform(0.95, 1.1);
      t.y = d.uniform(-0.015, 0.015);
      break;
    case Affordance::Climb: {
      // A ramp 0.3-1.0 m wide, sloping 5-50 degrees up to 4-30 cm, at most 1.2 m long.
      t.shape = Shape::Ramp;
      set_material(t, kMaterials[d.index(6)]);
      t.ramp_width = d.uniform(0.3, 1.0);
      t.ramp_angle = d.uniform(5, 50) * M_PI / 180;
      if (generator == Generator::Balanced) {
        // `material` climbs about 70 % of its ramps: balanced draws a quarter each of gentle
        // ramps (5-30 degrees, not ice), gentle ice (14-22: it slides back), steep ice (30-50:
        // it stalls) and steep ramps (40-50, not ice).
        const std::size_t kind = d.index(4);
        const bool ice = kind == 1 || kind == 2;
        set_material(t, ice ? material_named("ice") : kMaterials[d.index(5)]);  // 0-4: not ice
        static constexpr double kFrom[] = {5, 14, 30, 40}, kTo[] = {30, 22, 50, 50};
        t.ramp_angle = d.uniform(kFrom[kind], kTo[kind]) * M_PI / 180;
      }
      t.ramp_height = std::min(d.uniform(0.04, 0.3), 1.2 * std::tan(t.ramp_angle));
      t.x = d.uniform(0.75, 0.9);  // the foot
      t.y = d.uniform(-0.03, 0.03);
      t.size = {t.ramp_height / std::tan(t.ramp_angle), t.ramp_width, t.ramp_height};
      break;
    }
    case Affordance::Stack:
      draw_stack(t, d, generator == Generator::Balanced);
      break;
    case Affordance::Traverse:
      draw_traverse(t, d, generator == Generator::Balanced);
      break;
  }
  t.mass = t.density * t.volume();
  return t;
}

}  // namespace affordances
