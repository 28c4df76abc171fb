// The instants a bridge publishes at: counted from their epoch, and the same for a run resumed
// at any step as for the run it took over from.
#include "robots/schedule.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace macsim::test {
namespace {

constexpr double kStep = 0.001;  // s, as the worlds step

double time_of(uint64_t step) { return static_cast<double>(step) * kStep; }

/// The steps (1 .. last) an instant was due at, the schedule started at `from` (0: the first).
std::vector<uint64_t> due_steps(double rate, uint64_t from, uint64_t last) {
  Schedule schedule(rate);
  schedule.start(0.0, from == 0 ? -kStep : time_of(from));
  std::vector<uint64_t> due;
  for (uint64_t s = from + 1; s <= last; ++s)
    if (schedule.due(time_of(s))) due.push_back(s);
  return due;
}

TEST(Schedule, AnInstantIsDueAtTheFirstStepThatReachesItWithoutDrift) {
  // 15 Hz over 100 s of 1 ms steps: instant k at the first step at or after k / 15 s, the
  // last (k = 1500, on 100 s exactly) too: a sum of 1/15 would have drifted by then.
  const auto due = due_steps(15.0, 0, 100000);
  ASSERT_EQ(due.size(), 1501u);
  EXPECT_EQ(due.back(), 100000u);
  for (std::size_t k = 0; k < due.size(); ++k) {
    const double instant = static_cast<double>(k) / 15.0;
    EXPECT_GE(time_of(due[k]) + 1e-9, instant) << k;
    if (k > 0) EXPECT_LT(time_of(due[k] - 1) + 1e-9, instant) << k;  // 0: the first step
  }
  // On exact instants (20 Hz: every 50th step) the step that lands on one takes it.
  const auto exact = due_steps(20.0, 0, 1000);
  ASSERT_EQ(exact.size(), 21u);
  EXPECT_EQ(exact[0], 1u);  // instant 0, due at the first step
  EXPECT_EQ(exact[1], 50u);
  EXPECT_EQ(exact[20], 1000u);
}

TEST(Schedule, AScheduleResumedAtAnyStepReachesTheInstantsOfTheRunItTookOver) {
  for (const double rate : {15.0, 20.0, 100.0}) {
    const auto whole = due_steps(rate, 0, 3000);
    for (uint64_t from : {1u, 49u, 50u, 51u, 66u, 67u, 1234u, 2999u}) {
      std::vector<uint64_t> after;
      for (uint64_t s : whole)
        if (s > from) after.push_back(s);
      EXPECT_EQ(due_steps(rate, from, 3000), after) << rate << " Hz, resumed after step " << from;
    }
  }
}

TEST(Schedule, StartingAgainAtANewEpochCountsFromIt) {
  Schedule schedule(10.0);
  schedule.start(0.0, -kStep);
  for (uint64_t s = 1; s <= 250; ++s) schedule.due(time_of(s));
  EXPECT_EQ(schedule.done(), 3u);  // 0, 0.1, 0.2 s
  // Put back to 5 s (a snapshot restored): its first instant at the first step after.
  schedule.start(5.0, 5.0 - kStep);
  EXPECT_EQ(schedule.done(), 0u);
  EXPECT_FALSE(schedule.due(4.9));
  EXPECT_TRUE(schedule.due(5.001));
  EXPECT_FALSE(schedule.due(5.002));
  EXPECT_TRUE(schedule.due(5.1));
}

}  // namespace
}  // namespace macsim::test
