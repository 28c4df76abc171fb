// The progress replies every request/reply service sends (no DDS): a request answered at once
// gets none; one left waiting gets ERR_IN_PROGRESS replies with its ids and what it did so far,
// none after it was answered; a repeat of one still followed must not run again and, once the
// first progress is due, is answered with it at once; beyond the cap requests are served
// without progress.
#include "request_progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <thread>
#include <vector>

namespace macsim {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;
using Reply = mm::SimulationReply_;

/// What a server wrote, as its writer would have sent it.
struct Written {
  std::mutex mutex;
  std::vector<Reply> replies;
  std::size_t count(uint64_t sequence_number) {
    std::lock_guard<std::mutex> lock(mutex);
    return std::count_if(replies.begin(), replies.end(), [&](const Reply& r) {
      return r.sequence_number() == sequence_number;
    });
  }
  /// Waits (up to 5 s) until `n` replies of this request were written.
  bool wait_for(uint64_t sequence_number, std::size_t n) {
    for (int i = 0; i < 500 && count(sequence_number) < n; ++i) std::this_thread::sleep_for(10ms);
    return count(sequence_number) >= n;
  }
};

mm::SimulationRequest_ request(uint64_t sequence_number, const std::string& client = "client") {
  mm::SimulationRequest_ q;
  q.client_id(client);
  q.sequence_number(sequence_number);
  return q;
}

TEST(RequestProgress, AWaitingRequestGetsProgressWithWhatItDidAndNoneOnceAnswered) {
  Written written;
  RequestProgress<Reply> progress([&](const Reply& r) {
    std::lock_guard<std::mutex> lock(written.mutex);
    written.replies.push_back(r);
  });
  ASSERT_TRUE(progress.begin(request(1), "answered at once"));
  progress.end("client", 1);
  ASSERT_TRUE(progress.begin(request(2), "waiting"));
  progress.update("client", 2, "stepping", [](Reply& r) {
    r.steps_done(7);
    r.steps_asked(9);
  });
  ASSERT_TRUE(written.wait_for(2, 2));
  progress.end("client", 2);
  const std::size_t sent = written.count(2);
  std::this_thread::sleep_for(RequestProgress<Reply>::kEvery * 2);
  EXPECT_EQ(written.count(2), sent) << "progress after the request was answered";
  EXPECT_EQ(written.count(1), 0u);
  std::lock_guard<std::mutex> lock(written.mutex);
  for (const Reply& r : written.replies) {
    EXPECT_EQ(r.client_id(), "client");
    EXPECT_EQ(r.code(), mm::ERR_IN_PROGRESS);
    EXPECT_EQ(r.message().rfind("stepping, ", 0), 0u) << r.message();
    EXPECT_NE(r.message().find(" s after it came"), std::string::npos) << r.message();
    EXPECT_EQ(r.steps_done(), 7u);
    EXPECT_EQ(r.steps_asked(), 9u);
  }
}

TEST(RequestProgress, ARepeatOfAFollowedRequestIsNotRunAgainAndHearsItsProgress) {
  Written written;
  RequestProgress<Reply> progress([&](const Reply& r) {
    std::lock_guard<std::mutex> lock(written.mutex);
    written.replies.push_back(r);
  });
  ASSERT_TRUE(progress.begin(request(5), "loading"));
  EXPECT_FALSE(progress.begin(request(5), "loading"));  // the caller must not run it again
  EXPECT_EQ(written.count(5), 0u);                       // too young: its progress comes later
  ASSERT_TRUE(written.wait_for(5, 1));
  const std::size_t before = written.count(5);
  EXPECT_FALSE(progress.begin(request(5), "loading"));
  EXPECT_EQ(written.count(5), before + 1);  // written before begin() returned
  EXPECT_TRUE(progress.begin(request(5, "another client"), "loading"));
  EXPECT_TRUE(progress.begin(request(6), "loading"));
  progress.end("client", 5);
  EXPECT_TRUE(progress.begin(request(5), "loading"));  // answered: a new run is the caller's call
}

TEST(RequestProgress, RequestsBeyondTheCapAreServedWithoutProgress) {
  Written written;
  RequestProgress<Reply> progress([&](const Reply& r) {
    std::lock_guard<std::mutex> lock(written.mutex);
    written.replies.push_back(r);
  });
  const uint64_t cap = RequestProgress<Reply>::kMaxFollowed;
  for (uint64_t n = 1; n <= cap + 1; ++n) ASSERT_TRUE(progress.begin(request(n), "waiting"));
  ASSERT_TRUE(written.wait_for(cap, 1));
  EXPECT_EQ(written.count(cap + 1), 0u);
  EXPECT_TRUE(progress.begin(request(cap + 1), "waiting"));  // not followed: no repeat either
}

}  // namespace
}  // namespace macsim
