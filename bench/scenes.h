// Scenes the benchmarks share: piles of falling objects and grids of resting boxes, built in
// code so their rest poses are known.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim::bench {

/// A world with only the default material and the floor.
inline WorldSpec empty_world(const std::string& name) {
  WorldSpec spec;
  spec.name = name;
  MaterialSpec fallback;
  fallback.name = "default";
  spec.materials.push_back(fallback);
  return spec;
}

/// `n` objects dropped in columns 0.25 m apart: two 10 cm boxes stacked, two upright cylinders
/// (r 5 cm, h 10 cm) stacked, or one sphere (r 5 cm), in turn; each starts 2 cm above where it
/// comes to rest. `rest` receives the position each comes to rest at, in spec order.
inline WorldSpec pile(int n, std::vector<Eigen::Vector3d>* rest = nullptr) {
  WorldSpec spec = empty_world("pile_" + std::to_string(n));
  const int columns = (n + 1) / 2;  // at most two objects per column
  const int side = static_cast<int>(std::ceil(std::sqrt(columns)));
  int placed = 0;
  for (int column = 0; placed < n; ++column) {
    const double x = (column % side) * 0.25 - side * 0.125;
    const double y = (column / side) * 0.25 - side * 0.125;
    const int kind = column % 3;
    for (int level = 0; level < (kind == 2 ? 1 : 2) && placed < n; ++level, ++placed) {
      const Eigen::Vector3d at(x, y, 0.05 + 0.1 * level);
      const Eigen::Vector3d drop = at + Eigen::Vector3d(0, 0, 0.02 * (level + 1));
      spec.objects.push_back(kind == 0   ? box_object(drop, {0.1, 0.1, 0.1})
                             : kind == 1 ? cylinder_object(drop, 0.05, 0.1)
                                         : sphere_object(drop, 0.05));
      spec.objects.back().name = "o" + std::to_string(placed);
      if (rest) rest->push_back(at);
    }
  }
  return spec;
}

/// `n` boxes of 10 cm on a grid 0.25 m apart, resting on the floor.
inline WorldSpec resting_boxes(int n) {
  WorldSpec spec = empty_world("resting_boxes_" + std::to_string(n));
  const int side = static_cast<int>(std::ceil(std::sqrt(n)));
  for (int i = 0; i < n; ++i) {
    spec.objects.push_back(
        box_object({(i % side) * 0.25 - side * 0.125, (i / side) * 0.25 - side * 0.125, 0.0499},
                   {0.1, 0.1, 0.1}));
    spec.objects.back().name = "box_" + std::to_string(i);
  }
  return spec;
}

}  // namespace macsim::bench
