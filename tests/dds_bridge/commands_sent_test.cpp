// What a process sent to robots, as requests that put the world back name it: the last command
// of each writer, at most 64 writers (the longest unheard give way), and only on the requests
// that put the world back. (Over DDS, a late command dropped: integration/commands_sent_test.cpp.)
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

/// The sequence number the requests name for that writer, or nothing.
std::optional<uint64_t> named(uint8_t writer, uint8_t tag) {
  for (const auto& s : commands_sent()) {
    if (s.writer_guid()[0] == writer && s.writer_guid()[15] == tag) return s.sequence_number();
  }
  return std::nullopt;
}

TEST(CommandsSent, TheLastCommandOfEachWriterIsNamedAndTheLongestUnheardGiveWay) {
  note_command_sent(sent(1, 0xa7, 5));
  note_command_sent(sent(1, 0xa7, 6));
  note_command_sent(sent(1, 0xa7, 4));  // a number never goes back
  note_command_sent(sent(2, 0xa7, 1));
  EXPECT_EQ(named(1, 0xa7), 6u);
  EXPECT_EQ(named(2, 0xa7), 1u);
  // 70 more writers: only 64 fit a request; writer 1 and 2 were heard of longest ago.
  for (uint8_t w = 10; w < 80; ++w) note_command_sent(sent(w, 0xa7, w));
  EXPECT_EQ(commands_sent().size(), 64u);
  EXPECT_FALSE(named(1, 0xa7).has_value());
  EXPECT_FALSE(named(2, 0xa7).has_value());
  EXPECT_EQ(named(79, 0xa7), 79u);
  // A writer heard of again moves to the front.
  note_command_sent(sent(16, 0xa7, 100));
  note_command_sent(sent(90, 0xa7, 1));
  EXPECT_EQ(named(16, 0xa7), 100u);
  EXPECT_FALSE(named(17, 0xa7).has_value());
}

TEST(CommandsSent, OnlyRequestsThatPutTheWorldBackNameThem) {
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
  }
}

}  // namespace
}  // namespace macsim::client
