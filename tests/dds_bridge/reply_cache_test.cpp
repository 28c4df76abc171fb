// The repeated-request check: the same client and sequence number get the reply sent before.
#include "reply_cache.h"

#include <gtest/gtest.h>

#include "macsim/msg/macsim_msgs.h"

namespace macsim {
namespace {

namespace mm = macsim_msgs::msg::dds_;

mm::SimulationRequest_ request(const std::string& client, uint64_t sequence) {
  mm::SimulationRequest_ r;
  r.client_id(client);
  r.sequence_number(sequence);
  return r;
}

TEST(ReplyCache, ARequestSentAgainFindsItsReplyANewOneDoesNot) {
  ReplyCache<mm::SimulationReply_> cache;
  EXPECT_EQ(cache.find(request("a", 1)), nullptr);
  mm::SimulationReply_ reply;
  reply.client_id("a");
  reply.sequence_number(1);
  reply.message("first");
  cache.remember(reply);
  ASSERT_NE(cache.find(request("a", 1)), nullptr);
  EXPECT_EQ(cache.find(request("a", 1))->message(), "first");
  EXPECT_EQ(cache.find(request("a", 2)), nullptr);  // the next request is new
  EXPECT_EQ(cache.find(request("b", 1)), nullptr);  // another client's is new
  reply.sequence_number(2);
  cache.remember(reply);
  EXPECT_EQ(cache.find(request("a", 1)), nullptr);  // only the last reply is kept
}

}  // namespace
}  // namespace macsim
