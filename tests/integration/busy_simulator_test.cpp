// A busy simulator says it is busy: a request not answered at once gets progress replies
// (ERR_IN_PROGRESS, with a step request's steps done), so a client's timeout tells apart no
// simulator, a simulator still working on the request, and one that stopped answering; the
// requester of a long step request cancels it (SIM_CANCEL). Against real macsim processes.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <future>
#include <mutex>
#include <optional>
#include <vector>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/topics.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;
using client::CallOutcome;

constexpr uint64_t kLong = uint64_t{1} << 31;  // steps no test waits for

/// Polls SIM_STATUS (up to 60 s: a bound, not an expectation) until the world has taken more
/// than `steps` steps.
bool steps_grow_past(client::SimulationClient& sim, uint64_t steps) {
  for (int i = 0; i < 600; ++i) {
    const auto status = sim.call(client::SimulationClient::request(mm::SIM_STATUS), 10s);
    if (status && status->steps() > steps) return true;
    std::this_thread::sleep_for(100ms);
  }
  return false;
}

std::vector<std::string> lockstep_macsim(int domain) {
  return {bin("macsim"), "--world",    source("worlds/small_room.xml"), "--domain",
          std::to_string(domain),      "--lockstep", "--cameras", "off"};
}

TEST(BusySimulator, ALongStepIsReportedBusyWithItsProgressAndItsRequesterCancelsIt) {
  const int domain = unique_test_domain();
  ChildProcess macsim(lockstep_macsim(domain));
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "busy_simulator_test"});
  client::SimulationClient sim(p);
  client::SupervisorClient supervisor(p);
  ASSERT_TRUE(sim.wait_for_server(20s));
  ASSERT_TRUE(supervisor.wait_for_server(20s));

  // A short timeout on a long step: busy, with its progress.
  CallOutcome outcome;
  EXPECT_FALSE(sim.call(client::step_until::request(kLong, 1), 2s, {}, &outcome));
  EXPECT_EQ(outcome.kind, CallOutcome::Kind::Busy);
  EXPECT_TRUE(outcome.acknowledged);
  EXPECT_EQ(outcome.steps_asked, kLong);
  EXPECT_GT(outcome.steps_done, 0u);
  EXPECT_LT(outcome.since_heard, 1.0);
  const std::string said = client::describe(outcome, "simulation control");
  EXPECT_NE(said.find("busy with this request"), std::string::npos) << said;
  EXPECT_NE(said.find("of 2,147,483,648 steps done"), std::string::npos) << said;
  EXPECT_EQ(sim.last_outcome().kind, CallOutcome::Kind::Busy);

  // Another step request is refused while it runs; the supervisor is served between steps.
  auto refused = sim.step(1, 5s);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->code(), mm::ERR_INVALID_ARGUMENT);
  EXPECT_NE(refused->message().find("SIM_CANCEL"), std::string::npos) << refused->message();
  auto hash = supervisor.call(client::supervisor::state_hash(), 5s);
  ASSERT_TRUE(hash);
  EXPECT_EQ(hash->code(), mm::ERR_OK);

  // Its requester cancels it: the cancel's reply names how far it got.
  auto cancelled = sim.cancel(0, 5s);
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->code(), mm::ERR_OK) << cancelled->message();
  EXPECT_EQ(cancelled->ended_by(), mm::STEP_CANCELLED);
  EXPECT_EQ(cancelled->steps_asked(), kLong);
  EXPECT_GT(cancelled->steps_done(), outcome.steps_done);
  EXPECT_EQ(cancelled->steps(), cancelled->steps_done());  // the world's steps: all of it
  EXPECT_TRUE(cancelled->paused());  // lock-step stays paused

  // Nothing is left to cancel, and the simulator answers the next request.
  auto nothing = sim.cancel();
  ASSERT_TRUE(nothing);
  EXPECT_EQ(nothing->code(), mm::ERR_NOT_APPLICABLE);
  auto next = sim.step(10, 5s);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->code(), mm::ERR_OK);
  EXPECT_EQ(next->steps(), cancelled->steps() + 10);
  EXPECT_EQ(next->steps_done(), 10u);

  // A step another thread waits on ends with a cancelled reply when its client cancels it by
  // its sequence number (0: whichever runs).
  auto waiting = std::async(std::launch::async, [&] {
    CallOutcome o;
    auto r = sim.call(client::step_until::request(kLong, 1), 60s, {}, &o);
    return std::make_pair(r, o);
  });
  // The simulation thread has taken it once the world's step count grows (lock-step: nothing
  // else steps it).
  ASSERT_TRUE(steps_grow_past(sim, next->steps()));
  auto stop = client::SimulationClient::request(mm::SIM_CANCEL);
  stop.cancel_sequence_number(1000);  // no such request
  auto wrong = sim.call(stop, 5s);
  ASSERT_TRUE(wrong);
  EXPECT_EQ(wrong->code(), mm::ERR_NOT_APPLICABLE);
  stop.cancel_sequence_number(0);
  auto stopped = sim.call(stop, 5s);
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->code(), mm::ERR_OK) << stopped->message();
  ASSERT_EQ(waiting.wait_for(5s), std::future_status::ready);
  const auto [ended, how] = waiting.get();
  ASSERT_TRUE(ended) << client::describe(how, "simulation control");
  EXPECT_EQ(ended->code(), mm::ERR_NOT_APPLICABLE);
  EXPECT_EQ(ended->ended_by(), mm::STEP_CANCELLED);
  EXPECT_NE(ended->message().find("cancelled by its client"), std::string::npos)
      << ended->message();
  EXPECT_GT(ended->steps_done(), 0u);
  EXPECT_EQ(ended->steps_done(), stopped->steps_done());
  EXPECT_EQ(ended->steps(), next->steps() + ended->steps_done());
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0);
}

TEST(BusySimulator, ARepeatOfARequestStillRunningGetsItsProgressAndRunsOnce) {
  const int domain = unique_test_domain();
  ChildProcess macsim(lockstep_macsim(domain));
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "busy_simulator_test"});
  std::mutex mutex;
  std::vector<mm::SimulationReply_> heard;
  dds::Writer<mm::SimulationRequest_PubSubType> requests(p, dds::topics::kSimulationRequest,
                                                         dds::QosFamily::Command);
  dds::Reader<mm::SimulationReply_PubSubType> replies(
      p, dds::topics::kSimulationReply, dds::QosFamily::Command,
      [&](const mm::SimulationReply_& r) {
        std::lock_guard<std::mutex> lock(mutex);
        if (r.client_id() == "repeater") heard.push_back(r);
      });
  for (int i = 0; i < 200 && (requests.matched() == 0 || replies.matched() == 0); ++i) {
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GT(requests.matched(), 0);
  const auto count = [&](int code) {
    std::lock_guard<std::mutex> lock(mutex);
    return std::count_if(heard.begin(), heard.end(), [&](const auto& r) {
      return r.sequence_number() == 1 && r.code() == code;
    });
  };
  auto step = client::step_until::request(kLong, 1);
  step.client_id("repeater");
  step.sequence_number(1);
  // Sent every second until its first progress is heard: a reader that matched our writer
  // late loses the first sample (volatile), and a repeat runs nothing twice.
  for (int i = 0; i < 1200 && count(mm::ERR_IN_PROGRESS) == 0; ++i) {
    if (i % 20 == 0) requests.write(step);
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GT(count(mm::ERR_IN_PROGRESS), 0);
  for (int i = 0; i < 3; ++i) requests.write(step);  // sent again, as a client that heard nothing
  // Three more progress replies (whatever they take on this machine): still no second run.
  const auto progressed = count(mm::ERR_IN_PROGRESS) + 3;
  for (int i = 0; i < 1200 && count(mm::ERR_IN_PROGRESS) < progressed; ++i) {
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GE(count(mm::ERR_IN_PROGRESS), progressed);
  // Only progress, with steps counting up: no refusal of a second run, no final reply.
  {
    std::lock_guard<std::mutex> lock(mutex);
    uint64_t last = 0;
    for (const auto& r : heard) {
      EXPECT_EQ(r.code(), mm::ERR_IN_PROGRESS) << r.message();
      EXPECT_EQ(r.steps_asked(), kLong);
      EXPECT_GE(r.steps_done(), last);
      last = r.steps_done();
    }
    EXPECT_GT(last, 0u);
  }
  auto cancel = client::SimulationClient::request(mm::SIM_CANCEL);
  cancel.client_id("repeater");
  cancel.sequence_number(2);
  cancel.cancel_sequence_number(1);
  const auto cancel_answered = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return std::any_of(heard.begin(), heard.end(),
                       [](const auto& r) { return r.sequence_number() == 2; });
  };
  for (int i = 0; i < 1200 && !cancel_answered(); ++i) {
    if (i % 20 == 0) requests.write(cancel);  // as a client does until it hears
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_TRUE(cancel_answered());
  ASSERT_EQ(count(mm::ERR_NOT_APPLICABLE), 1);
  // The step's reply was sent before the cancel's: a client that lost it sends the step again
  // and hears the same reply, although a later request of its (the cancel) was answered since;
  // the 2^31 steps do not start again.
  requests.write(step);
  for (int i = 0; i < 1200 && count(mm::ERR_NOT_APPLICABLE) < 2; ++i) {
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_EQ(count(mm::ERR_NOT_APPLICABLE), 2);
  std::this_thread::sleep_for(700ms);  // a progress reply after the final one would show now
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_FALSE(heard.empty());
  std::size_t finals = 0;
  std::optional<mm::SimulationReply_> first_final;
  for (std::size_t i = 0; i < heard.size(); ++i) {
    if (heard[i].sequence_number() != 1 || heard[i].code() == mm::ERR_IN_PROGRESS) continue;
    ++finals;
    EXPECT_EQ(heard[i].ended_by(), mm::STEP_CANCELLED);
    if (!first_final) first_final = heard[i];
    EXPECT_EQ(heard[i].steps_done(), first_final->steps_done());  // the same reply again
    for (std::size_t j = i + 1; j < heard.size(); ++j) {
      EXPECT_FALSE(heard[j].sequence_number() == 1 && heard[j].code() == mm::ERR_IN_PROGRESS)
          << "progress after the final reply";
    }
  }
  EXPECT_EQ(finals, 2u);
}

TEST(BusySimulator, ASimulatorKilledDuringALongStepIsReportedGoneWithinSeconds) {
  const int domain = unique_test_domain();
  ChildProcess macsim(lockstep_macsim(domain));
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "busy_simulator_test"});
  client::SimulationClient sim(p);
  // The replies as the client hears them: the same participant receives each sample once and
  // hands it to both readers, so once two progress replies arrived here the client has heard
  // at least the first (acknowledged).
  std::mutex mutex;
  int progress_heard = 0;
  dds::Reader<mm::SimulationReply_PubSubType> replies(
      p, dds::topics::kSimulationReply, dds::QosFamily::Command,
      [&](const mm::SimulationReply_& r) {
        std::lock_guard<std::mutex> lock(mutex);
        if (r.client_id() == sim.client_id() && r.code() == mm::ERR_IN_PROGRESS &&
            r.steps_done() > 0) {
          ++progress_heard;
        }
      });
  ASSERT_TRUE(sim.wait_for_server(20s));
  auto waiting = std::async(std::launch::async, [&] {
    CallOutcome o;
    auto r = sim.call(client::step_until::request(kLong, 1), 60s, {}, &o);
    return std::make_pair(r.has_value(), o);
  });
  const auto heard = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return progress_heard;
  };
  for (int i = 0; i < 1200 && heard() < 2; ++i) std::this_thread::sleep_for(50ms);
  ASSERT_GE(heard(), 2) << "no progress of the step request";
  macsim.signal(SIGKILL);
  const auto killed = std::chrono::steady_clock::now();
  ASSERT_EQ(waiting.wait_for(15s), std::future_status::ready) << "waited out the timeout";
  const double after =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  const auto [replied, outcome] = waiting.get();
  EXPECT_FALSE(replied);
  EXPECT_EQ(outcome.kind, CallOutcome::Kind::Gone);
  EXPECT_TRUE(outcome.acknowledged);
  EXPECT_GT(outcome.steps_done, 0u);
  EXPECT_LT(after, 10.0);
  EXPECT_LT(outcome.waited, 20.0);
  const std::string said = client::describe(outcome, "simulation control", domain);
  EXPECT_NE(said.find("stopped answering"), std::string::npos) << said;
  EXPECT_EQ(macsim.wait_for_exit(5s), 128 + SIGKILL);
}

TEST(BusySimulator, RequestsBeyondAFullQueueAreRefusedWithTheCodeAndTheFlagThatSetsIt) {
  // A world of 90,000 boxes takes a second or more to parse: requests sent meanwhile wait
  // behind its load, and with room for 2 (the load and one more) the rest are refused at once
  // with ERR_LIMIT_REACHED naming --max-queued-commands; once served, it takes requests again.
  TempDir dir("macsim_queue_");
  const std::string big = dir.path() + "/big.xml";
  {
    std::ofstream out(big);
    out << "<WORLD><NAME>big</NAME><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>\n";
    for (int i = 0; i < 90000; ++i) {
      out << "<OBJECT><ID>b" << i << "</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE>"
          << "<DIMS>0.1,0.1,0.1</DIMS><POS>" << 2 + (i % 300) * 0.3 << "," << -45 + (i / 300) * 0.3
          << ",0.05</POS></OBJECT>\n";
    }
    out << "</WORLD>\n";
  }
  const int domain = unique_test_domain();
  auto args = lockstep_macsim(domain);
  args.insert(args.end(), {"--max-queued-commands", "2", "--data-path", dir.path()});
  ChildProcess macsim(args);
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "busy_test"});
  client::SimulationClient sim(p);
  client::SupervisorClient supervisor(p);
  ASSERT_TRUE(sim.wait_for_server(20s) && supervisor.wait_for_server(20s));
  auto load = client::SimulationClient::request(mm::SIM_LOAD_WORLD);
  load.world_file(big);
  auto loaded = std::async(std::launch::async, [&] { return sim.call(load, 120s); });
  std::this_thread::sleep_for(300ms);  // the load is parsing
  std::vector<std::future<std::optional<client::SupervisorClient::Reply>>> asked;
  for (int i = 0; i < 4; ++i) {
    asked.push_back(std::async(std::launch::async, [&] {
      return supervisor.call(client::supervisor::state_hash(), 120s);
    }));
  }
  int refused = 0, answered = 0;
  for (auto& a : asked) {
    const auto reply = a.get();
    ASSERT_TRUE(reply.has_value());
    if (reply->code() == mm::ERR_LIMIT_REACHED) {
      ++refused;
      EXPECT_NE(reply->message().find("--max-queued-commands"), std::string::npos)
          << reply->message();
    } else {
      EXPECT_EQ(reply->code(), mm::ERR_OK) << reply->message();
      ++answered;
    }
  }
  const auto done = loaded.get();
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->code(), mm::ERR_OK) << done->message();
  EXPECT_GE(refused, 2) << "the queue had room for the load and one request";
  EXPECT_LE(answered, 2);
  // The queue takes requests again once served.
  const auto after = supervisor.call(client::supervisor::state_hash(), 30s);
  ASSERT_TRUE(after.has_value());
  EXPECT_EQ(after->code(), mm::ERR_OK);
}

TEST(BusySimulator, NoSimulatorIsReportedNotFound) {
  const int domain = unique_test_domain();
  dds::Participant p({domain, "", "busy_simulator_test"});
  client::SimulationClient sim(p);
  CallOutcome outcome;
  EXPECT_FALSE(sim.call(client::SimulationClient::request(mm::SIM_STATUS), 1s, {}, &outcome));
  EXPECT_EQ(outcome.kind, CallOutcome::Kind::NoServer);
  EXPECT_FALSE(outcome.acknowledged);
  const std::string said = client::describe(outcome, "simulation control", domain);
  EXPECT_NE(said.find("is macsim running with the same --domain"), std::string::npos) << said;
  EXPECT_NE(said.find("domain " + std::to_string(domain)), std::string::npos) << said;
}

}  // namespace
}  // namespace macsim::test
