// Two sessions are the same run when every record is, whatever random identities their clients
// and DDS writers had (numbered as they first appear) and wherever the world file was; else the
// first record where they part is named. (Two lock-step runs of the controllers compared by
// macsim --compare: integration/session_compare_test.cpp.)
#include "simulation/session_compare.h"

#include <gtest/gtest.h>

#include "macsim/dds/wire.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim {
namespace {

namespace mm = macsim_msgs::msg::dds_;

std::array<uint8_t, 16> guid(uint8_t participant, uint8_t entity) {
  std::array<uint8_t, 16> g{};
  g[0] = 0x01;
  g[1] = 0x0f;
  g[5] = participant;
  g[15] = entity;
  return g;
}

mm::SampleIdentity_ sample(const std::array<uint8_t, 16>& writer, uint64_t sequence) {
  mm::SampleIdentity_ s;
  s.writer_guid(writer);
  s.sequence_number(sequence);
  return s;
}

/// A run: a client resets, its robot drives, it steps, with the identities given.
Session run(const std::string& world, const std::string& client,
            const std::vector<mm::SampleIdentity_>& sent, double speed) {
  Session s;
  s.header.world_file = world;
  s.header.seed = 3;
  mm::SupervisorRequest_ reset;
  reset.client_id(client);
  reset.sequence_number(1);
  reset.commands_sent(sent);
  RecordedCommand c;  // as a session file holds it
  auto recorded = std::make_shared<WireRequest>();
  recorded->operation = "reset";
  recorded->bytes = dds::to_wire<mm::SupervisorRequest_PubSubType>(reset);
  c.command.source = CommandSource::Supervisor;
  c.command.request = recorded;
  s.commands.push_back(c);
  s.commands.push_back({10, robot_command("kurt", robot::Twist{speed, 0.0}), 10});
  mm::SimulationRequest_ step;
  step.client_id(client);
  step.sequence_number(2);
  step.command(mm::SIM_STEP);
  step.steps(100);
  step.commands_sent(sent);
  s.requests.push_back({10, RecordedRequest::Kind::Taken, "simulation",
                        dds::to_wire<mm::SimulationRequest_PubSubType>(step), 2});
  mm::SimulationReply_ reply;
  reply.client_id(client);
  reply.sequence_number(2);
  s.requests.push_back({110, RecordedRequest::Kind::Answered, "simulation",
                        dds::to_wire<mm::SimulationReply_PubSubType>(reply), 2});
  s.hashes.push_back({100, 0x1234});
  s.files.push_back({world, "<WORLD/>", 0});
  s.steps = 110;
  return s;
}

TEST(SessionCompare, RunsOfClientsAndWritersOfOtherIdentitiesAreTheSameRun) {
  const Session a = run("elsewhere/room.xml", "kurt_demo-1f2e",
                        {sample(guid(1, 3), 5), sample(guid(1, 4), 2)}, 0.3);
  const Session b =
      run("room.xml", "kurt_demo-77aa01", {sample(guid(9, 3), 5), sample(guid(9, 4), 2)}, 0.3);
  EXPECT_EQ(first_difference(a, b), std::nullopt);
}

TEST(SessionCompare, ACommandChangedIsNamed) {
  const Session a = run("room.xml", "c1", {sample(guid(1, 3), 5)}, 0.3);
  const Session b = run("room.xml", "c2", {sample(guid(2, 3), 5)}, 0.31);
  const auto part = first_difference(a, b);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("A command 2 at step 10: robot twist kurt 0.3 0"), std::string::npos)
      << *part;
  EXPECT_NE(part->find("B command 2 at step 10: robot twist kurt 0.31 0"), std::string::npos)
      << *part;
}

TEST(SessionCompare, WritersNamedInAnotherOrderOrAnotherSampleAreNotTheSameRun) {
  const Session a = run("room.xml", "c1", {sample(guid(1, 3), 5), sample(guid(1, 4), 2)}, 0.3);
  // The same writers, the second named first: another run.
  const Session swapped =
      run("room.xml", "c1", {sample(guid(1, 4), 2), sample(guid(1, 3), 5)}, 0.3);
  const auto part = first_difference(a, swapped);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("command 1 at step 0: supervisor reset (its bytes differ)"),
            std::string::npos)
      << *part;
  // Another sample of a writer.
  const Session later = run("room.xml", "c1", {sample(guid(1, 3), 6), sample(guid(1, 4), 2)}, 0.3);
  EXPECT_TRUE(first_difference(a, later).has_value());
}

TEST(SessionCompare, AHashAFileOrTheEndThatDifferIsNamed) {
  const Session a = run("room.xml", "c1", {}, 0.3);
  Session b = a;
  b.hashes[0].hash = 0x1235;
  auto part = first_difference(a, b);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("state hash after step 100: 0000000000001234"), std::string::npos) << *part;
  b = a;
  b.files[0].bytes = "<WORLD></WORLD>";
  part = first_difference(a, b);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("file 1 read after 0 commands"), std::string::npos) << *part;
  b = a;
  b.commands.pop_back();
  b.requests[0].commands_before = 1;
  b.requests[1].commands_before = 1;
  part = first_difference(a, b);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("B none (it ends before)"), std::string::npos) << *part;
  b = a;
  b.header.seed = 4;
  part = first_difference(a, b);
  ASSERT_TRUE(part.has_value());
  EXPECT_NE(part->find("the headers"), std::string::npos) << *part;
}

}  // namespace
}  // namespace macsim
