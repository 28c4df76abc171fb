// What a process sent to robots, as requests name it: the last command of each writer on the
// request's domain, at most 64 writers (the longest unheard give way), and only on the requests
// that put the world back or step. (Over DDS, a late command dropped: integration/commands_sent_test.cpp.)
#include "macsim/client/commands_sent.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace macsim::client {
namespace {

namespace mm = macsim_msgs::msg::dds_;

dds::SampleId sent(uint8_t writer, uint8_t tag, uint64_t sequence) {
  dds::SampleId id;
  id.writer[0] = writer;
  id.writer[15] = tag;  // apart from any other test's writers in this process
  id.sequence = sequence;
  return id;
}

/// The sequence number the requests (on `domain`, if given) name for that writer, or nothing.
std::optional<uint64_t> named(uint8_t writer, uint8_t tag, std::optional<int> domain = std::nullopt) {
  for (const auto& s : commands_sent(domain)) {
    if (s.writer_guid()[0] == writer && s.writer_guid()[15] == tag) return s.sequence_number();
  }
  return std::nullopt;
}

TEST(CommandsSent, TheLastCommandOfEachWriterIsNamedAndTheLongestUnheardGiveWay) {
  note_command_sent(sent(1, 0xa7, 5), 3);
  note_command_sent(sent(1, 0xa7, 6), 3);
  note_command_sent(sent(1, 0xa7, 4), 3);  // a number never goes back
  note_command_sent(sent(2, 0xa7, 1), 3);
  EXPECT_EQ(named(1, 0xa7), 6u);
  EXPECT_EQ(named(2, 0xa7), 1u);
  // 70 more writers: only 64 fit a request; writer 1 and 2 were heard of longest ago.
  for (uint8_t w = 10; w < 80; ++w) note_command_sent(sent(w, 0xa7, w), 3);
  EXPECT_EQ(commands_sent().size(), 64u);
  EXPECT_FALSE(named(1, 0xa7).has_value());
  EXPECT_FALSE(named(2, 0xa7).has_value());
  EXPECT_EQ(named(79, 0xa7), 79u);
  // A writer heard of again moves to the front.
  note_command_sent(sent(16, 0xa7, 100), 3);
  note_command_sent(sent(90, 0xa7, 1), 3);
  EXPECT_EQ(named(16, 0xa7), 100u);
  EXPECT_FALSE(named(17, 0xa7).has_value());
}

TEST(CommandsSent, ARequestNamesTheWritersOnItsOwnDomainOnly) {
  // Two simulators driven from one process (the trial pool): each on a domain of its own.
  note_command_sent(sent(1, 0xb3, 7), 41);
  note_command_sent(sent(2, 0xb3, 9), 42);
  EXPECT_EQ(named(1, 0xb3, 41), 7u);
  EXPECT_FALSE(named(2, 0xb3, 41).has_value());
  EXPECT_EQ(named(2, 0xb3, 42), 9u);
  EXPECT_FALSE(named(1, 0xb3, 42).has_value());
}

TEST(CommandsSent, AWriterDeletedIsNamedNoMore) {
  // A controller's writer gone (its run ended): a later run's steps on the same domain must
  // not wait for samples that can arrive nowhere.
  note_command_sent(sent(3, 0xc1, 42), 43);
  EXPECT_EQ(named(3, 0xc1, 43), 42u);
  forget_commands_of(sent(3, 0xc1, 0).writer);
  EXPECT_FALSE(named(3, 0xc1, 43).has_value());
}

TEST(CommandsSent, RequestsThatPutTheWorldBackOrStepNameThem) {
  mm::SupervisorRequest_ supervisor;
  for (const auto& [op, back] : {std::pair{mm::OP_RESET, true},
                                 {mm::OP_RESTORE_SNAPSHOT, true},
                                 {mm::OP_SAVE_SNAPSHOT, false},
                                 {mm::OP_STATE_HASH, false}}) {
    mm::SupervisorOperation_ operation;
    if (op == mm::OP_RESET) {
      operation.reset(mm::Reset_{});
    } else if (op == mm::OP_STATE_HASH) {
      operation.no_arguments(true);
      operation._d(op);
    } else {
      operation.snapshot(mm::SnapshotName_{});
      operation._d(op);
    }
    supervisor.operation(operation);
    EXPECT_EQ(puts_world_back(supervisor), back) << op;
  }
  mm::SimulationRequest_ simulation;
  for (const auto& [command, back] :
       {std::pair{mm::SIM_LOAD_WORLD, true}, {mm::SIM_STEP, false}, {mm::SIM_PAUSE, false}}) {
    simulation.command(command);
    EXPECT_EQ(puts_world_back(simulation), back) << command;
    // A step waits for them before its first step.
    EXPECT_EQ(names_commands_sent(simulation), back || command == mm::SIM_STEP) << command;
  }
  EXPECT_TRUE(names_commands_sent(supervisor) == puts_world_back(supervisor));
}

}  // namespace
}  // namespace macsim::client
