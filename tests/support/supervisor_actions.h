// Random supervisor operations for property tests, and the shrinker that finds the shortest
// failing sequence of them.
#pragma once

#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "macsim/client/supervisor_requests.h"
#include "macsim/sim_core/world.h"

namespace macsim::test {

namespace mm = macsim_msgs::msg::dds_;
namespace rq = client::supervisor;

/// One operation, drawn from its own seed when it runs: objects are picked among those there
/// then, so any subsequence of a sequence is a valid sequence too (what shrinking needs).
struct Action {
  int kind;
  uint32_t seed;
};
inline constexpr int kKinds = 12;

/// The request of operation `a` on the world as it is now; `said` names it for a report.
inline mm::SupervisorRequest_ request_for(const Action& a, const World& world, std::string& said) {
  std::mt19937 rng(a.seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<>(lo, hi)(rng);
  };
  const auto ids = world.objects().object_ids();
  const uint32_t id = ids.empty() ? 0 : ids[rng() % ids.size()];
  const rq::Vec3 place{uniform(-1.5, 1.5), uniform(-1.5, 1.5), uniform(0.05, 1.0)};
  std::ostringstream text;
  mm::SupervisorRequest_ r;
  switch (a.kind) {
    case 0: {
      mm::Object_ o;
      mm::Component_ c;
      c.shape(rng() % 2 ? mm::SHAPE_SPHERE : mm::SHAPE_BOX);
      c.size({uniform(0.02, 0.2), uniform(0.02, 0.2), uniform(0.02, 0.2)});
      c.pose().orientation().w(1.0);
      c.color({0.5f, 0.5f, 0.5f, 1.0f});
      o.components().push_back(c);
      o.kind(mm::KIND_OBJECT);
      o.portable(true);
      o.pose().position().x(place[0]);
      o.pose().position().y(place[1]);
      o.pose().position().z(place[2]);
      o.pose().orientation().w(1.0);
      o.density(uniform(10, 5000));
      r = rq::create_object(o, rng() % 2);
      text << "create";
      break;
    }
    case 1:
      r = rq::destroy_object(id);
      text << "destroy";
      break;
    case 2:
      r = rq::set_position(id, place, rng() % 2);
      text << "set_position";
      break;
    case 3:
      r = rq::set_box_size(id, 0, {uniform(0.01, 0.4), uniform(0.01, 0.4), uniform(0.01, 0.4)},
                           rng() % 2);
      text << "set_box_size";
      break;
    case 4:
      r = rq::set_sphere_size(id, 0, uniform(0.01, 0.3), rng() % 2);
      text << "set_sphere_size";
      break;
    case 5:
      r = rq::set_mass(id, uniform(0.01, 50));
      text << "set_mass";
      break;
    case 6:
      r = rq::set_density(id, uniform(10, 20000));
      text << "set_density";
      break;
    case 7:
      r = rq::set_magnetizable(id, rng() % 2);
      text << "set_magnetizable";
      break;
    case 8:
      r = rq::add_force(id, {uniform(-100, 100), uniform(-100, 100), uniform(-100, 100)});
      text << "add_force";
      break;
    case 9:
      r = rq::save_snapshot("s");
      text << "save_snapshot";
      break;
    case 10:
      r = rq::restore_snapshot("s");
      text << "restore_snapshot";
      break;
    default:
      r = rq::reset(int32_t(rng() % 3));
      text << "reset";
      break;
  }
  text << " (object " << id << ", seed " << a.seed << ")";
  said = text.str();
  return r;
}

/// Drops operations one at a time while the sequence still `fails` (a callable taking the
/// sequence).
template <class T, class Fails>
std::vector<T> shrink(std::vector<T> actions, const Fails& fails) {
  for (std::size_t i = 0; i < actions.size();) {
    std::vector<T> shorter = actions;
    shorter.erase(shorter.begin() + long(i));
    if (fails(shorter)) {
      actions = std::move(shorter);
    } else {
      ++i;
    }
  }
  return actions;
}

}  // namespace macsim::test
