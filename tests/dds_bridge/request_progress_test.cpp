// The progress replies every request/reply service sends (no DDS): a request answered before
// its first progress is due gets none; one left waiting gets ERR_IN_PROGRESS replies with its
// ids and what it did so far, none after it was answered; a repeat of one still followed must
// not run again and, once the first progress is due, is answered with it at once; beyond the
// cap requests are served without progress. The delays are the tests' own (no assumption about
// how fast this machine runs).
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
  /// Waits (up to 60 s: a bound, not an expectation) until `n` replies of this request were
  /// written.
  bool wait_for(uint64_t sequence_number, std::size_t n) {
    for (int i = 0; i < 6000 && count(sequence_number) < n; ++i) std::this_thread::sleep_for(10ms);
    return count(sequence_number) >= n;
  }
};

mm::SimulationRequest_ request(uint64_t sequence_number, const std::string& client = "client") {
  mm::SimulationRequest_ q;
  q.client_id(client);
  q.sequence_number(sequence_number);
  return q;
}

/// A RequestProgress writing into `written`, its first progress `first` after a request came
/// and then one every `every`.
struct Server {
  Written written;
  RequestProgress<Reply> progress;
  Server(std::chrono::milliseconds first, std::chrono::milliseconds every)
      : progress(
            [this](const Reply& r) {
              std::lock_guard<std::mutex> lock(written.mutex);
              written.replies.push_back(r);
            },
            first, every) {}
};

constexpr auto kNever = std::chrono::hours(1);  // no test lives this long

TEST(RequestProgress, ARequestAnsweredBeforeItsFirstProgressIsDueGetsNone) {
  Server server(kNever, 1ms);
  ASSERT_TRUE(server.progress.begin(request(1), "answered at once"));
  server.progress.end("client", 1);
  ASSERT_TRUE(server.progress.begin(request(2), "waiting"));
  // Whatever the machine's load: none before the first is due.
  EXPECT_EQ(server.written.count(1), 0u);
  EXPECT_EQ(server.written.count(2), 0u);
}

TEST(RequestProgress, AWaitingRequestGetsProgressWithWhatItDidAndNoneOnceAnswered) {
  Server server(0ms, 5ms);
  RequestProgress<Reply>& progress = server.progress;
  Written& written = server.written;
  ASSERT_TRUE(progress.begin(request(2), "waiting"));
  progress.update("client", 2, "stepping", [](Reply& r) {
    r.steps_done(7);
    r.steps_asked(9);
  });
  // The first progress may have gone before update(): from the next one on, it says stepping.
  const std::size_t before = written.count(2);
  ASSERT_TRUE(written.wait_for(2, before + 2));
  progress.end("client", 2);
  const std::size_t sent = written.count(2);
  // Another request's progress keeps coming: the loop ran several times since end().
  ASSERT_TRUE(progress.begin(request(3), "waiting"));
  ASSERT_TRUE(written.wait_for(3, 3));
  EXPECT_EQ(written.count(2), sent) << "progress after the request was answered";
  std::lock_guard<std::mutex> lock(written.mutex);
  std::size_t stepping = 0;
  for (const Reply& r : written.replies) {
    EXPECT_EQ(r.client_id(), "client");
    EXPECT_EQ(r.code(), mm::ERR_IN_PROGRESS);
    EXPECT_NE(r.message().find(" s after it came"), std::string::npos) << r.message();
    if (r.sequence_number() != 2 || r.message().rfind("stepping, ", 0) != 0) continue;
    ++stepping;
    EXPECT_EQ(r.steps_done(), 7u);
    EXPECT_EQ(r.steps_asked(), 9u);
  }
  EXPECT_GE(stepping, 2u);
}

TEST(RequestProgress, ARepeatOfAFollowedRequestIsNotRunAgainAndWaitsForItsFirstProgress) {
  Server server(kNever, 1ms);
  ASSERT_TRUE(server.progress.begin(request(5), "loading"));
  EXPECT_FALSE(server.progress.begin(request(5), "loading"));  // must not run again
  EXPECT_EQ(server.written.count(5), 0u);  // too young: its progress comes when it is due
  EXPECT_TRUE(server.progress.begin(request(5, "another client"), "loading"));
  EXPECT_TRUE(server.progress.begin(request(6), "loading"));
  server.progress.end("client", 5);
  EXPECT_TRUE(server.progress.begin(request(5), "loading"));  // answered: the caller decides
}

TEST(RequestProgress, ARepeatOfAFollowedRequestHearsItsProgressAtOnceOnceItIsDue) {
  Server server(0ms, kNever);  // the loop sends the first progress, then none for an hour
  ASSERT_TRUE(server.progress.begin(request(5), "loading"));
  ASSERT_TRUE(server.written.wait_for(5, 1));
  const std::size_t before = server.written.count(5);
  EXPECT_FALSE(server.progress.begin(request(5), "loading"));
  EXPECT_EQ(server.written.count(5), before + 1);  // written before begin() returned
  EXPECT_FALSE(server.progress.begin(request(5), "loading"));
  EXPECT_EQ(server.written.count(5), before + 2);
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
