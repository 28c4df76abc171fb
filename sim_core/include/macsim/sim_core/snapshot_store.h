// The named snapshots of one world, within caps on their count and their bytes: a client saving
// under new names cannot make the simulator keep more than the caps allow.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "macsim/sim_core/world.h"

namespace macsim {

/// How many named snapshots, and how many bytes of them, a world keeps at most.
struct SnapshotLimits {
  std::size_t max_count = 256;                ///< macsim --max-snapshots
  std::size_t max_bytes = std::size_t{256} << 20;  ///< 256 MiB; macsim --max-snapshot-bytes
};

/// Named snapshots within SnapshotLimits; every refusal leaves the store unchanged.
class SnapshotStore {
 public:
  explicit SnapshotStore(SnapshotLimits limits = {}) : limits_(limits) {}

  /// Keeps `snapshot` under `name`, replacing the one of that name (always allowed when the new
  /// one fits the byte cap once the old one is gone); LimitReached naming the cap when full.
  Status save(const std::string& name, WorldSnapshot snapshot);
  /// The snapshot of that name, or nullptr.
  const WorldSnapshot* find(const std::string& name) const;
  /// Removes the snapshot of that name; InvalidArgument naming it when there is none.
  Status remove(const std::string& name);
  /// The names, in order.
  std::vector<std::string> names() const;
  void clear();

  std::size_t size() const { return snapshots_.size(); }
  bool empty() const { return snapshots_.empty(); }
  /// The bytes the kept snapshots take, as counted against SnapshotLimits::max_bytes.
  std::size_t bytes() const { return bytes_; }
  const SnapshotLimits& limits() const { return limits_; }
  /// New caps; snapshots already kept stay (a later save is checked against the new caps).
  void set_limits(SnapshotLimits limits) { limits_ = limits; }

  /// What one snapshot kept under `name` takes: its state bytes, its name and the bookkeeping.
  static std::size_t footprint(const std::string& name, const WorldSnapshot& snapshot);

 private:
  SnapshotLimits limits_;
  std::map<std::string, WorldSnapshot> snapshots_;
  std::size_t bytes_ = 0;
};

}  // namespace macsim
