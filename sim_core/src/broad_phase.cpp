#include "broad_phase.h"

#include <algorithm>
#include <cmath>

namespace macsim::detail {

namespace {

constexpr int kMaxFiledCells = 64;   // a still geom over more cells is tested against every mover
constexpr int kMaxQueryCells = 512;  // a mover over more cells is tested against every still geom

std::array<double, 6> aabb_of(dGeomID geom) {
  std::array<double, 6> box;
  dGeomGetAABB(geom, box.data());
  return box;
}

bool unbounded(const std::array<double, 6>& box) {
  for (const double v : box) {
    if (!std::isfinite(v) || std::fabs(v) >= 1e30) return true;
  }
  return false;
}

bool overlap(const std::array<double, 6>& a, const std::array<double, 6>& b) {
  return a[0] <= b[1] && b[0] <= a[1] && a[2] <= b[3] && b[2] <= a[3] && a[4] <= b[5] &&
         b[4] <= a[5];
}

long cell_count(const std::array<int, 6>& r) {
  return static_cast<long>(r[1] - r[0] + 1) * (r[3] - r[2] + 1) * (r[5] - r[4] + 1);
}

}  // namespace

void BroadPhase::track(const std::vector<dGeomID>& geoms) {
  entries_.clear();
  planes_.clear();
  grid_.clear();
  big_.clear();
  entries_.reserve(geoms.size());
  std::vector<double> extents;
  for (dGeomID geom : geoms) {
    Entry e;
    e.geom = geom;
    e.body = dGeomGetBody(geom);
    e.box = aabb_of(geom);
    e.plane = unbounded(e.box);
    if (e.plane) {
      planes_.push_back(static_cast<std::uint32_t>(entries_.size()));
    } else {
      extents.push_back(std::max({e.box[1] - e.box[0], e.box[3] - e.box[2], e.box[5] - e.box[4]}));
    }
    entries_.push_back(e);
  }
  // Cells twice the typical geom: most geoms lie in one to eight of them.
  if (!extents.empty()) {
    std::nth_element(extents.begin(), extents.begin() + extents.size() / 2, extents.end());
    cell_ = std::clamp(2.0 * extents[extents.size() / 2], 0.05, 10.0);
  }
  stamp_.assign(entries_.size(), 0);
  query_ = 0;
  still_count_ = 0;
}

bool BroadPhase::moving(const Entry& e) const { return e.body && dBodyIsEnabled(e.body); }

std::uint64_t BroadPhase::key(int x, int y, int z) {
  constexpr std::uint64_t kMask = (1u << 21) - 1;
  return ((static_cast<std::uint64_t>(x) & kMask) << 42) |
         ((static_cast<std::uint64_t>(y) & kMask) << 21) | (static_cast<std::uint64_t>(z) & kMask);
}

std::array<int, 6> BroadPhase::cell_range(const std::array<double, 6>& box) const {
  std::array<int, 6> r;
  for (int k = 0; k < 6; ++k) {
    const double c = std::floor(box[k] / cell_);
    r[k] = static_cast<int>(std::clamp(c, -1e9, 1e9));
  }
  return r;
}

void BroadPhase::file(std::uint32_t index) {
  Entry& e = entries_[index];
  e.filed = true;
  const bool finite =
      std::all_of(e.box.begin(), e.box.end(), [](double v) { return std::isfinite(v); });
  e.cells = finite ? cell_range(e.box) : std::array<int, 6>{};
  e.big = !finite || cell_count(e.cells) > kMaxFiledCells;
  if (e.big) {
    big_.push_back(index);
    return;
  }
  for (int x = e.cells[0]; x <= e.cells[1]; ++x)
    for (int y = e.cells[2]; y <= e.cells[3]; ++y)
      for (int z = e.cells[4]; z <= e.cells[5]; ++z) grid_[key(x, y, z)].push_back(index);
}

void BroadPhase::unfile(std::uint32_t index) {
  Entry& e = entries_[index];
  e.filed = false;
  auto drop = [index](std::vector<std::uint32_t>& list) {
    auto it = std::find(list.begin(), list.end(), index);
    if (it == list.end()) return;
    *it = list.back();
    list.pop_back();
  };
  if (e.big) {
    drop(big_);
    return;
  }
  for (int x = e.cells[0]; x <= e.cells[1]; ++x)
    for (int y = e.cells[2]; y <= e.cells[3]; ++y)
      for (int z = e.cells[4]; z <= e.cells[5]; ++z) {
        auto cell = grid_.find(key(x, y, z));
        if (cell == grid_.end()) continue;
        drop(cell->second);
        if (cell->second.empty()) grid_.erase(cell);
      }
}

void BroadPhase::candidate(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  pairs_.push_back((static_cast<std::uint64_t>(a) << 32) | b);
}

void BroadPhase::collide(void* data, dNearCallback* callback) {
  // Sort the geoms into moving and still; file those that stopped, unfile those that started.
  // A body asleep stays where it is: ODE moves only awake ones, and whoever puts a sleeping
  // body elsewhere calls track() again.
  moving_.clear();
  still_count_ = 0;
  for (std::uint32_t i = 0; i < entries_.size(); ++i) {
    Entry& e = entries_[i];
    if (e.plane) continue;
    if (moving(e)) {
      if (e.filed) unfile(i);
      e.box = aabb_of(e.geom);
      moving_.push_back(i);
      continue;
    }
    if (!e.filed) {
      e.box = aabb_of(e.geom);
      file(i);
    }
    ++still_count_;
  }

  pairs_.clear();
  // Moving against moving: the cells each covers, hashed into twice as many buckets as there
  // are (cell, mover) entries and grouped by a counting sort (linear: a comparison sort of
  // them was a quarter of the broad phase with 20,000 movers); movers sharing a bucket are
  // tested pairwise (a bucket may hold several cells: the box test sorts them out).
  cell_members_.clear();
  huge_movers_.clear();
  for (const std::uint32_t m : moving_) {
    const std::array<int, 6> r = cell_range(entries_[m].box);
    if (cell_count(r) > kMaxQueryCells) {
      huge_movers_.push_back(m);
      continue;
    }
    for (int x = r[0]; x <= r[1]; ++x)
      for (int y = r[2]; y <= r[3]; ++y)
        for (int z = r[4]; z <= r[5]; ++z) cell_members_.push_back({key(x, y, z), m});
  }
  int bits = 1;
  while ((std::size_t{1} << bits) < 2 * cell_members_.size()) ++bits;
  const std::size_t buckets = std::size_t{1} << bits;
  auto bucket_of = [bits](std::uint64_t cell) {  // Fibonacci hashing
    return static_cast<std::size_t>((cell * 0x9E3779B97F4A7C15ull) >> (64 - bits));
  };
  bucket_start_.assign(buckets + 1, 0);
  for (const auto& [cell, m] : cell_members_) ++bucket_start_[bucket_of(cell) + 1];
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  by_bucket_.resize(cell_members_.size());
  for (const auto& [cell, m] : cell_members_) by_bucket_[bucket_start_[bucket_of(cell)]++] = m;
  // Each bucket's start moved to its end: bucket b now spans [start of b, bucket_start_[b]).
  for (std::size_t b = 0, begin = 0; b < buckets; ++b) {
    const std::size_t end = bucket_start_[b];
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t j = i + 1; j < end; ++j) {
        const std::uint32_t ia = by_bucket_[i], ib = by_bucket_[j];
        if (ia != ib && overlap(entries_[ia].box, entries_[ib].box)) candidate(ia, ib);
      }
    begin = end;
  }
  for (const std::uint32_t big : huge_movers_) {  // huge movers: every mover
    for (const std::uint32_t m : moving_) {
      if (m != big && overlap(entries_[big].box, entries_[m].box)) candidate(big, m);
    }
  }
  // Moving against still: the grid's cells each mover covers, the big ones, the planes.
  for (const std::uint32_t m : moving_) {
    const auto& box = entries_[m].box;
    if (++query_ == 0) {  // the stamps wrapped around
      std::fill(stamp_.begin(), stamp_.end(), 0);
      query_ = 1;
    }
    const std::array<int, 6> r = cell_range(box);
    if (cell_count(r) > kMaxQueryCells) {
      for (std::uint32_t s = 0; s < entries_.size(); ++s) {
        const Entry& e = entries_[s];
        if (e.filed && !e.big && overlap(box, e.box)) candidate(m, s);
      }
    } else {
      for (int x = r[0]; x <= r[1]; ++x)
        for (int y = r[2]; y <= r[3]; ++y)
          for (int z = r[4]; z <= r[5]; ++z) {
            auto cell = grid_.find(key(x, y, z));
            if (cell == grid_.end()) continue;
            for (const std::uint32_t s : cell->second) {
              if (stamp_[s] == query_) continue;
              stamp_[s] = query_;
              if (overlap(box, entries_[s].box)) candidate(m, s);
            }
          }
    }
    for (const std::uint32_t s : big_) {
      if (overlap(box, entries_[s].box)) candidate(m, s);
    }
    for (const std::uint32_t p : planes_) candidate(m, p);
  }

  // In list order, with the checks ODE's spaces make before calling back.
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());  // met in several cells
  for (const std::uint64_t pair : pairs_) {
    dGeomID a = entries_[pair >> 32].geom;
    dGeomID b = entries_[pair & 0xffffffffu].geom;
    if (!dGeomIsEnabled(a) || !dGeomIsEnabled(b)) continue;
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (ba && ba == bb) continue;
    if (!(dGeomGetCategoryBits(a) & dGeomGetCollideBits(b)) &&
        !(dGeomGetCategoryBits(b) & dGeomGetCollideBits(a)))
      continue;
    callback(data, a, b);
  }
}

}  // namespace macsim::detail
