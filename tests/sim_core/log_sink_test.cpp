// sim_core's one voice: a sink set for the process receives every message with its level, a
// scoped sink gives the one before back, and messages from several threads all arrive.
#include "macsim/sim_core/log_sink.h"

#include <gtest/gtest.h>

#include <mutex>
#include <thread>
#include <vector>

#include "macsim/sim_core/world_loader.h"

namespace macsim::test {
namespace {

TEST(LogSink, ASinkReceivesEachMessageWithItsLevelAndAScopedOneGivesThePreviousBack) {
  std::vector<std::pair<LogLevel, std::string>> outer, inner;
  const ScopedLogSink first([&](LogLevel l, const std::string& m) { outer.emplace_back(l, m); });
  log_message(LogLevel::Info, "one");
  {
    const ScopedLogSink second([&](LogLevel l, const std::string& m) { inner.emplace_back(l, m); });
    log_message(LogLevel::Error, "two");
    // What sim_core's libraries say reaches the sink too: here the loader's warning.
    load_world_string("<WORLD>\n<GADGET/>\n</WORLD>", "gadget.xml");
  }
  log_message(LogLevel::Warning, "three");
  ASSERT_EQ(outer.size(), 2u);
  EXPECT_EQ(outer[0], std::make_pair(LogLevel::Info, std::string("one")));
  EXPECT_EQ(outer[1], std::make_pair(LogLevel::Warning, std::string("three")));
  ASSERT_EQ(inner.size(), 2u);
  EXPECT_EQ(inner[0], std::make_pair(LogLevel::Error, std::string("two")));
  EXPECT_EQ(inner[1].first, LogLevel::Warning);
  EXPECT_EQ(inner[1].second.rfind("gadget.xml:2: warning: unknown element <GADGET>", 0), 0u)
      << inner[1].second;
}

TEST(LogSink, MessagesFromSeveralThreadsAllArrive) {
  std::mutex mutex;
  std::vector<std::string> got;
  const ScopedLogSink capture([&](LogLevel, const std::string& m) {
    std::lock_guard<std::mutex> lock(mutex);
    got.push_back(m);
  });
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([t] {
      for (int i = 0; i < 250; ++i) log_message(LogLevel::Debug, std::to_string(t * 1000 + i));
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(got.size(), 1000u);
}

}  // namespace
}  // namespace macsim::test
