// The world's broad phase: which pairs of geoms may touch, at a cost that grows with the geoms
// that move, not with the square of all of them.
#pragma once

#include <ode/ode.h>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace macsim::detail {

/// Pairs of geoms whose bounding boxes overlap and of which at least one is on an awake body.
/// Geoms that lie still (no body, or a sleeping one) wait in a uniform grid and are filed again
/// only when they start or stop moving (a sleeping body put elsewhere, or a geom added or removed,
/// needs track() again); moving geoms are sorted into the same cells each step, paired with
/// those that share a cell and looked up in the grid. Planes pair with every moving geom. Pairs
/// come in an order given by the tracked list alone (never by addresses or history), each as
/// (earlier, later) in that list, so a world restored anywhere collides as the original did.
class BroadPhase {
 public:
  /// The geoms to consider, in a fixed order (the world's); resets the grid.
  void track(const std::vector<dGeomID>& geoms);
  /// Calls `callback(data, a, b)` for every candidate pair, as ODE's spaces do. AABBs must be
  /// current (dSpaceClean of the geoms' space).
  void collide(void* data, dNearCallback* callback);
  /// Tracked geoms filed as still after the last collide().
  std::size_t still_count() const { return still_count_; }

 private:
  struct Entry {
    dGeomID geom = nullptr;
    dBodyID body = nullptr;
    std::array<double, 6> box{};  // min x, max x, min y, max y, min z, max z
    std::array<int, 6> cells{};   // the cell range filed under
    bool plane = false;           // unbounded: paired with every moving geom
    bool filed = false;           // in the grid or among the big ones
    bool big = false;             // spans too many cells: tested against every moving geom
  };

  bool moving(const Entry& e) const;
  void file(std::uint32_t index);
  void unfile(std::uint32_t index);
  std::array<int, 6> cell_range(const std::array<double, 6>& box) const;
  static std::uint64_t key(int x, int y, int z);
  void candidate(std::uint32_t a, std::uint32_t b);

  std::vector<Entry> entries_;
  std::vector<std::uint32_t> planes_;  // unbounded geoms
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;
  std::vector<std::uint32_t> big_;
  std::vector<std::uint32_t> moving_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cell_members_;  // (cell, mover)
  std::vector<std::uint32_t> bucket_start_;  // of each bucket in by_bucket_ (counting sort)
  std::vector<std::uint32_t> by_bucket_;     // movers, bucket by bucket
  std::vector<std::uint32_t> huge_movers_;   // movers over more than kMaxQueryCells cells
  std::vector<std::uint32_t> stamp_;  // last query that met each entry
  std::uint32_t query_ = 0;
  std::vector<std::uint64_t> pairs_;  // (lower index << 32) | higher index
  std::size_t still_count_ = 0;
  double cell_ = 0.25;
};

}  // namespace macsim::detail
