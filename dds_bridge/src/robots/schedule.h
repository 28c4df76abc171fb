// Instants of sim time a bridge publishes at (camera frames, the clock): counted from an
// epoch, not summed, so which steps a run reaches them at does not drift, and a resumed run
// reaches the same ones as the run it took over from.
#pragma once

#include <cmath>
#include <cstdint>

namespace macsim {

/// Instants epoch + k / rate (s of sim time), k = 0, 1, ...; one is due at the first step whose
/// time reaches it.
class Schedule {
 public:
  explicit Schedule(double rate) : rate_(rate) {}
  /// Starts again at `epoch`; the instants already due at time `served` count as done (a
  /// resumed run: the killed process published them).
  void start(double epoch, double served) {
    epoch_ = epoch;
    next_ = 0;
    if (!(served + kSlack >= epoch)) return;
    next_ = static_cast<uint64_t>(std::floor((served + kSlack - epoch) * rate_));
    while (next_ > 0 && !reached(next_ - 1, served)) --next_;
    while (reached(next_, served)) ++next_;
  }
  /// True if the next instant is due at `time`, and the schedule goes on to the one after.
  bool due(double time) {
    if (!reached(next_, time)) return false;
    ++next_;
    return true;
  }
  /// The instants done so far.
  uint64_t done() const { return next_; }

 private:
  static constexpr double kSlack = 1e-9;  // s: a step's time ends on an instant up to rounding
  bool reached(uint64_t k, double time) const {
    return time + kSlack >= epoch_ + static_cast<double>(k) / rate_;
  }

  double rate_;
  double epoch_ = 0.0;
  uint64_t next_ = 0;
};

}  // namespace macsim
