// A replay's reader of the servers' requests a session recorded: each record's name and bytes
// give back the typed request its server had queued, or nothing for what is no such request.
#include "recorded_requests.h"

#include <gtest/gtest.h>

#include "macsim/dds/wire.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "sim_interfaces/sim_interfaces_dispatch.h"
#include "supervisor/supervisor_dispatch.h"

namespace macsim {
namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;

/// A command as a session file holds it: its source, the operation's name and the bytes.
Command recorded(CommandSource source, const std::string& name, std::vector<uint8_t> bytes) {
  auto wire = std::make_shared<WireRequest>();
  wire->operation = name;
  wire->bytes = std::move(bytes);
  Command c;
  c.source = source;
  c.request = std::move(wire);
  return c;
}

TEST(RecordedRequests, ASupervisorRequestComesBackAsTheRequestItsServerQueued) {
  mm::SupervisorRequest_ q;
  q.client_id("client-7");
  q.sequence_number(12);
  mm::SetDensity_ density;
  density.object_id(3);
  density.density(450.0);
  q.operation().set_density(density);
  const Command live = supervisor_command(q);
  const auto typed =
      read_recorded_request(recorded(CommandSource::Supervisor, "set_density", wire_of(live)));
  ASSERT_NE(typed, nullptr);
  const auto* call = dynamic_cast<const SupervisorCall*>(typed.get());
  ASSERT_NE(call, nullptr);
  EXPECT_EQ(call->name(), "set_density");
  EXPECT_EQ(call->message().client_id(), "client-7");
  EXPECT_EQ(call->message().sequence_number(), 12u);
  EXPECT_EQ(call->message().operation()._d(), mm::OP_SET_DENSITY);
  EXPECT_DOUBLE_EQ(call->message().operation().set_density().density(), 450.0);
  EXPECT_EQ(call->wire(), wire_of(live));  // written again, the same bytes
}

TEST(RecordedRequests, AServiceThatChangesTheWorldComesBackAsItsOwnTypeAndNoOtherDoes) {
  ss::DeleteEntity_Request_ q;
  q.entity("box_1");
  const auto bytes = dds::to_wire<ss::DeleteEntity_Request_PubSubType>(q);
  const auto typed =
      read_recorded_request(recorded(CommandSource::Ros2Service, "delete_entity", bytes));
  using Delete = sim_interfaces::ServiceRequest<ss::DeleteEntity_Request_PubSubType>;
  const auto* call = dynamic_cast<const Delete*>(typed.get());
  ASSERT_NE(call, nullptr);
  EXPECT_EQ(call->message().entity(), "box_1");
  // A service that changes no world is never recorded, so never read back.
  EXPECT_EQ(read_recorded_request(recorded(CommandSource::Ros2Service, "get_entities", bytes)),
            nullptr);
}

TEST(RecordedRequests, BytesThatAreNoRequestOrASourceWithoutRecordsGiveNothing) {
  EXPECT_EQ(read_recorded_request(
                recorded(CommandSource::Supervisor, "set_density", {0x00, 0x01, 0x02, 0xff})),
            nullptr);
  EXPECT_EQ(read_recorded_request(recorded(CommandSource::Pictures, "take_picture", {})), nullptr);
  Command typed_already = request_command<KeepRobotCommands>(CommandSource::Simulation);
  EXPECT_EQ(read_recorded_request(typed_already), nullptr);  // no WireRequest: nothing to read
}

}  // namespace
}  // namespace macsim
