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

mm::SimulationReply_ reply_to(const std::string& client, uint64_t sequence) {
  mm::SimulationReply_ r;
  r.client_id(client);
  r.sequence_number(sequence);
  r.message(client);
  return r;
}

TEST(ReplyCache, ClientsInventingIdsPushOutTheOldestNotMemory) {
  ReplyCache<mm::SimulationReply_> cache(3);
  for (const char* client : {"a", "b", "c"}) cache.remember(reply_to(client, 1));
  cache.remember(reply_to("a", 2));  // a heard from again: b is now the oldest
  cache.remember(reply_to("d", 1));
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_EQ(cache.find(request("b", 1)), nullptr);
  ASSERT_NE(cache.find(request("a", 2)), nullptr);
  EXPECT_NE(cache.find(request("c", 1)), nullptr);
  EXPECT_NE(cache.find(request("d", 1)), nullptr);
  for (int i = 0; i < 10000; ++i) cache.remember(reply_to("invented" + std::to_string(i), 1));
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_EQ(cache.find(request("a", 2)), nullptr);
  ASSERT_NE(cache.find(request("invented9999", 1)), nullptr);
  EXPECT_EQ(cache.find(request("invented9999", 1))->message(), "invented9999");
}

TEST(ReplyCache, TheDefaultCapKeepsOneThousandAndTwentyFourClients) {
  ReplyCache<mm::SimulationReply_> cache;
  EXPECT_EQ(cache.max_clients(), 1024u);
  for (int i = 0; i < 3000; ++i) cache.remember(reply_to(std::to_string(i), 7));
  EXPECT_EQ(cache.size(), 1024u);
  EXPECT_EQ(cache.find(request("1975", 7)), nullptr);
  EXPECT_NE(cache.find(request("1976", 7)), nullptr);
}

}  // namespace
}  // namespace macsim
