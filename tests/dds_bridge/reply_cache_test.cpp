// The repeated-request check: the same client and sequence number get the reply sent before,
// for each client's last requests (a window); an older repeat is known as answered; the cache
// is capped in clients and in bytes.
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

mm::SimulationReply_ reply_to(const std::string& client, uint64_t sequence) {
  mm::SimulationReply_ r;
  r.client_id(client);
  r.sequence_number(sequence);
  r.message(client);
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
  reply.message("second");
  cache.remember(reply);
  ASSERT_NE(cache.find(request("a", 1)), nullptr);  // an earlier call's reply is still kept
  EXPECT_EQ(cache.find(request("a", 1))->message(), "first");
  EXPECT_EQ(cache.find(request("a", 2))->message(), "second");
  EXPECT_FALSE(cache.forgotten(request("a", 1)));
  EXPECT_FALSE(cache.forgotten(request("a", 3)));
}

TEST(ReplyCache, CallsInFlightTogetherEachFindTheirReply) {
  // Thread A's call 1 is not acknowledged yet when thread B's call 2 is answered: A's resend
  // of 1 still finds its reply, whatever order the replies went in.
  ReplyCache<mm::SimulationReply_> cache;
  cache.remember(reply_to("a", 2));
  cache.remember(reply_to("a", 1));
  cache.remember(reply_to("a", 3));
  for (uint64_t n : {1, 2, 3}) {
    ASSERT_NE(cache.find(request("a", n)), nullptr) << n;
    EXPECT_EQ(cache.find(request("a", n))->sequence_number(), n);
  }
}

TEST(ReplyCache, ARepeatOlderThanTheWindowIsKnownAsAnsweredNotRunAgain) {
  ReplyCache<mm::SimulationReply_> cache(1024, 4);
  EXPECT_EQ(cache.window(), 4u);
  for (uint64_t n = 1; n <= 10; ++n) cache.remember(reply_to("a", n));
  for (uint64_t n = 1; n <= 6; ++n) {
    EXPECT_EQ(cache.find(request("a", n)), nullptr) << n;
    EXPECT_TRUE(cache.forgotten(request("a", n))) << n;
  }
  for (uint64_t n = 7; n <= 10; ++n) {
    EXPECT_NE(cache.find(request("a", n)), nullptr) << n;
    EXPECT_FALSE(cache.forgotten(request("a", n))) << n;
  }
  EXPECT_FALSE(cache.forgotten(request("a", 11)));  // the next request is new
  EXPECT_FALSE(cache.forgotten(request("b", 1)));   // so is another client's
  const mm::SimulationReply_ answer = cache.forgotten_reply(request("a", 3));
  EXPECT_EQ(answer.client_id(), "a");
  EXPECT_EQ(answer.sequence_number(), 3u);
  EXPECT_EQ(answer.code(), mm::ERR_LIMIT_REACHED);
  EXPECT_NE(answer.message().find("request 3 was already answered; its reply is no longer kept"),
            std::string::npos)
      << answer.message();
  // A request answered late (it ran long) is kept although older ones were pushed out.
  cache.remember(reply_to("a", 5));
  ASSERT_NE(cache.find(request("a", 5)), nullptr);
  EXPECT_FALSE(cache.forgotten(request("a", 5)));
  EXPECT_EQ(cache.find(request("a", 7)), nullptr);  // the oldest remembered went instead
  EXPECT_TRUE(cache.forgotten(request("a", 7)));
}

mm::SimulationReply_ sized_reply(const std::string& client, uint64_t sequence,
                                 std::size_t bytes) {
  mm::SimulationReply_ r = reply_to(client, sequence);
  r.message(std::string(bytes, 'x'));
  return r;
}

TEST(ReplyCache, BigRepliesPushOutTheClientsHeardFromLongestAgoBeyondTheByteBudget) {
  constexpr std::size_t kBudget = 1 << 20;
  ReplyCache<mm::SimulationReply_> cache(1024, 16, kBudget);
  EXPECT_EQ(cache.max_bytes(), kBudget);
  EXPECT_EQ(ReplyCache<mm::SimulationReply_>::kDefaultMaxBytes, std::size_t{64} << 20);
  const std::size_t one = reply_bytes(sized_reply("a", 1, 300000));
  EXPECT_GE(one, 300000u);  // the estimate counts the strings
  EXPECT_LT(one, 301000u);
  cache.remember(sized_reply("a", 1, 300000));
  cache.remember(sized_reply("b", 1, 300000));
  cache.remember(sized_reply("c", 1, 300000));
  EXPECT_NE(cache.find(request("a", 1)), nullptr);
  cache.remember(sized_reply("d", 1, 300000));  // 4 x 300 KB > 1 MiB: a goes
  EXPECT_LE(cache.bytes(), kBudget);
  EXPECT_EQ(cache.find(request("a", 1)), nullptr);
  EXPECT_TRUE(cache.forgotten(request("a", 1)));  // still known as answered, not run again
  for (const char* client : {"b", "c", "d"}) EXPECT_NE(cache.find(request(client, 1)), nullptr);
  // Many invented ids with big replies: the bytes stay within the budget, the newest is kept.
  for (int i = 0; i < 1000; ++i) cache.remember(sized_reply(std::to_string(i), 1, 100000));
  EXPECT_LE(cache.bytes(), kBudget);
  EXPECT_NE(cache.find(request("999", 1)), nullptr);
  EXPECT_EQ(cache.find(request("d", 1)), nullptr);
  // A reply bigger than the whole budget is kept alone, for its repeat.
  cache.remember(sized_reply("huge", 1, 2 * kBudget));
  ASSERT_NE(cache.find(request("huge", 1)), nullptr);
  EXPECT_EQ(cache.find(request("999", 1)), nullptr);
  EXPECT_EQ(cache.bytes(), reply_bytes(sized_reply("huge", 1, 2 * kBudget)));
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
