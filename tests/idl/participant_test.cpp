// Participants: several made at once from threads of one process (as affordance_trials makes one
// per simulator it attaches to) all come up with the shipped profile.
// (ctest runs each test in a process of its own, so Fast DDS loads its profiles here first.)
#include "macsim/dds/participant.h"

#include <gtest/gtest.h>

#include <atomic>
#include <fastdds/dds/log/Log.hpp>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

namespace fdds = eprosima::fastdds::dds;

/// Counts the errors Fast DDS logs (its XML parser's among them), for as long as it is registered.
class ErrorCounter : public fdds::LogConsumer {
 public:
  explicit ErrorCounter(std::atomic<int>& errors) : errors_(errors) {}
  void Consume(const fdds::Log::Entry& entry) override {
    if (entry.kind == fdds::Log::Kind::Error) ++errors_;
  }

 private:
  std::atomic<int>& errors_;
};

TEST(Participant, NeverTakesThePortsAKilledParticipantLeftBehind) {
  // A killed participant's port segments stay in /dev/shm while another process maps them;
  // Fast DDS 2.9 would take that id again and make new segments the others never write to.
  // Here id 0's two segments are left behind: the participant takes id 1's ports.
  if (!std::filesystem::is_directory("/dev/shm")) GTEST_SKIP() << "no /dev/shm here";
  const int domain = unique_test_domain();
  const int port = 7400 + 250 * domain + 10;
  const auto segment = [](int p) { return "/dev/shm/fastrtps_port" + std::to_string(p); };
  for (int p : {port, port + 1}) {
    ASSERT_FALSE(std::filesystem::exists(segment(p))) << segment(p);
    std::ofstream(segment(p)) << "left behind";
  }
  {
    dds::Participant participant({domain, source("deploy/dds/localhost.xml"), "port_test"});
    EXPECT_TRUE(std::filesystem::exists(segment(port + 2))) << "id 1's ports not taken";
    std::ifstream left(segment(port));
    std::string text;
    std::getline(left, text);
    EXPECT_EQ(text, "left behind") << "the segment left behind was made anew";
  }
  for (int p : {port, port + 1}) std::filesystem::remove(segment(p));
}

TEST(Participant, ManyMadeAtOnceFromThreadsAllComeUpWithTheProfile) {
  constexpr int kThreads = 6;
  const int first = unique_test_domains(kThreads);
  std::atomic<int> ready{0};
  std::vector<std::unique_ptr<dds::Participant>> made(kThreads);
  std::vector<std::string> errors(kThreads);
  std::atomic<int> dds_errors{0};
  fdds::Log::RegisterConsumer(std::make_unique<ErrorCounter>(dds_errors));
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i) {
    threads.emplace_back([&, i] {
      ++ready;
      while (ready.load() < kThreads) std::this_thread::yield();  // all start together
      try {
        made[i] = std::make_unique<dds::Participant>(
            dds::ParticipantOptions{first + i, source("deploy/dds/localhost.xml"),
                                    "participant_test_" + std::to_string(i)});
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  }
  for (auto& t : threads) t.join();
  fdds::Log::Flush();
  // Loading the profiles at once from several threads made Fast DDS 2.9 log "Error adding
  // profile" for each one loaded twice, and now and then crash inside its XML parser.
  EXPECT_EQ(dds_errors.load(), 0);
  for (int i = 0; i < kThreads; ++i) {
    ASSERT_NE(made[i], nullptr) << "participant " << i << ": " << errors[i];
    EXPECT_EQ(made[i]->domain(), first + i);
    // Every one has the shipped profile's QoS families, not Fast DDS's defaults.
    const auto latched = dds::writer_qos(dds::QosFamily::Latched, made[i]->publisher());
    EXPECT_EQ(latched.resource_limits().max_instances, 10000) << "participant " << i;
  }
}

}  // namespace
}  // namespace macsim::test
