// Objects and robots that start inside each other (World::overlaps()), and how to report them.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim {

class World;

/// Depth (m) up to which two things touch (rest on each other) rather than overlap: objects
/// placed on the floor or on each other touch at depth 0 and sink about 1 mm once they rest.
inline constexpr double kOverlapTolerance = 0.005;

/// Distinct pairs an overlap search records at most; what lies beyond is not examined.
inline constexpr std::size_t kMaxOverlapPairs = 10'000;

/// Two things inside each other: objects, robots, or one of them and the ground.
struct Overlap {
  std::string first, second;  ///< object or robot names; "ground" for the floor plane
  double depth = 0.0;         ///< m, how far they are inside each other (the deepest contact)
  SourceLocation source;      ///< where `first` is written (empty for what was built in code)
};

/// What World::overlaps() found.
struct OverlapReport {
  std::vector<Overlap> pairs;  ///< deepest first
  bool truncated = false;      ///< more than kMaxOverlapPairs pairs: the rest were not examined
  bool empty() const { return pairs.empty(); }
};

/// One warning per pair ("FILE:LINE: warning: 'a' and 'b' start inside each other, 0.150 m
/// deep"), at most `max_lines` of them, then one line saying how many pairs were left out.
std::vector<std::string> overlap_warnings(const OverlapReport& report, std::size_t max_lines = 20);

/// One line refusing a world for its overlaps: how many pairs, the deepest `named` of them.
std::string overlap_error(const OverlapReport& report, std::size_t named = 3);

/// Checks a world just built: its overlap_warnings() go to sim_core's log (log_sink.h); then, if
/// `refuse` and there are any, throws WorldFileError at the deepest pair's file and line with
/// overlap_error(). Returns the report.
OverlapReport admit_overlaps(const World& world, bool refuse);

/// Parts what starts deeply inside each other: portable objects and robots whose pair is deeper
/// than a quarter of the smaller one's footprint radius (and than kOverlapTolerance) are moved
/// apart on the floor, each tangled heap spread on a sunflower spiral about where it stood and
/// pushed apart until no two footprints meet. Objects fixed, frozen, jointed or part of a door,
/// and whatever is not deeply tangled, stay where they are; shallower overlaps are the physics'
/// to push apart. Returns a warning per thing moved ("FILE:LINE: warning: 'a' started 0.100 m
/// deep inside 'b': moved 0.310 m apart"), at most `max_lines` of them and a line counting the
/// rest; none if nothing moved. The same spec is always parted the same way.
std::vector<std::string> part_overlaps(WorldSpec& spec, std::size_t max_lines = 20);

}  // namespace macsim
