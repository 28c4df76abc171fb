// The named snapshots' caps: a new name past the count or the byte cap is refused naming the cap,
// the store unchanged; a name already kept is replaced when the new one fits; a delete frees room.
#include "macsim/sim_core/snapshot_store.h"

#include <gtest/gtest.h>

namespace macsim {
namespace {

/// A snapshot of `size` bytes (the store does not look inside).
WorldSnapshot of_size(std::size_t size, uint8_t fill = 1) {
  return WorldSnapshot{42, std::vector<uint8_t>(size, fill)};
}

TEST(SnapshotStore, ANewNamePastTheCountCapIsRefusedNamingItAndTheFlag) {
  SnapshotStore store({3, std::size_t{1} << 30});
  for (const char* name : {"a", "b", "c"}) ASSERT_TRUE(store.save(name, of_size(100)).ok());
  const std::size_t bytes = store.bytes();
  const Status refused = store.save("d", of_size(100));
  EXPECT_EQ(refused.code, ErrorCode::LimitReached);
  EXPECT_NE(refused.message.find("'d'"), std::string::npos) << refused.message;
  EXPECT_NE(refused.message.find("3"), std::string::npos) << refused.message;
  EXPECT_NE(refused.message.find("--max-snapshots"), std::string::npos) << refused.message;
  EXPECT_NE(refused.message.find("delete"), std::string::npos) << refused.message;
  EXPECT_EQ(store.size(), 3u);
  EXPECT_EQ(store.bytes(), bytes);
  EXPECT_EQ(store.find("d"), nullptr);
}

TEST(SnapshotStore, ANameAlreadyKeptIsReplacedWhenFull) {
  SnapshotStore store({2, std::size_t{1} << 30});
  ASSERT_TRUE(store.save("a", of_size(100, 1)).ok());
  ASSERT_TRUE(store.save("b", of_size(100, 1)).ok());
  const Status replaced = store.save("a", of_size(300, 7));
  ASSERT_TRUE(replaced.ok()) << replaced.message;
  EXPECT_EQ(store.size(), 2u);
  ASSERT_NE(store.find("a"), nullptr);
  EXPECT_EQ(store.find("a")->bytes, std::vector<uint8_t>(300, 7));
  EXPECT_EQ(store.bytes(), SnapshotStore::footprint("a", of_size(300)) +
                               SnapshotStore::footprint("b", of_size(100)));
}

TEST(SnapshotStore, ADeleteFreesAPlaceAndItsBytesAnUnknownNameIsRefused) {
  SnapshotStore store({2, std::size_t{1} << 30});
  ASSERT_TRUE(store.save("a", of_size(100)).ok());
  ASSERT_TRUE(store.save("b", of_size(200)).ok());
  EXPECT_EQ(store.save("c", of_size(100)).code, ErrorCode::LimitReached);
  ASSERT_TRUE(store.remove("a").ok());
  EXPECT_EQ(store.bytes(), SnapshotStore::footprint("b", of_size(200)));
  EXPECT_TRUE(store.save("c", of_size(100)).ok());
  EXPECT_EQ(store.names(), (std::vector<std::string>{"b", "c"}));
  const Status unknown = store.remove("nope");
  EXPECT_EQ(unknown.code, ErrorCode::InvalidArgument);
  EXPECT_NE(unknown.message.find("nope"), std::string::npos);
  EXPECT_EQ(store.size(), 2u);
}

TEST(SnapshotStore, TheByteCapCountsTheRealSizeAndRefusesWhatWouldPassIt) {
  const std::size_t one = SnapshotStore::footprint("a", of_size(1000));
  EXPECT_GE(one, 1000u + sizeof(WorldSnapshot));
  SnapshotStore store({100, 2 * one + 10});
  ASSERT_TRUE(store.save("a", of_size(1000)).ok());
  ASSERT_TRUE(store.save("b", of_size(1000)).ok());
  EXPECT_EQ(store.bytes(), 2 * one);
  const Status refused = store.save("c", of_size(1000));
  EXPECT_EQ(refused.code, ErrorCode::LimitReached);
  EXPECT_NE(refused.message.find("--max-snapshot-bytes"), std::string::npos) << refused.message;
  EXPECT_NE(refused.message.find(std::to_string(2 * one + 10)), std::string::npos)
      << refused.message;
  EXPECT_EQ(store.size(), 2u);
  // A replacement is counted without the one it replaces: the same size fits, a larger one not.
  EXPECT_TRUE(store.save("a", of_size(1000, 9)).ok());
  EXPECT_EQ(store.save("a", of_size(2000)).code, ErrorCode::LimitReached);
  EXPECT_EQ(store.find("a")->bytes, std::vector<uint8_t>(1000, 9));
  // A long name counts too.
  EXPECT_EQ(store.save(std::string(5000, 'n'), of_size(1)).code, ErrorCode::LimitReached);
  EXPECT_EQ(store.bytes(), 2 * one);
}

TEST(SnapshotStore, SpareCapacityOfTheBytesIsNotKept) {
  WorldSnapshot roomy = of_size(10);
  roomy.bytes.reserve(1 << 20);
  SnapshotStore store({10, 4096});
  ASSERT_TRUE(store.save("a", std::move(roomy)).ok());
  EXPECT_LT(store.bytes(), 4096u);
  EXPECT_LT(store.find("a")->bytes.capacity(), 4096u);
}

TEST(SnapshotStore, ClearEmptiesItAndKeepsTheCaps) {
  SnapshotStore store({1, 1 << 20});
  ASSERT_TRUE(store.save("a", of_size(10)).ok());
  store.clear();
  EXPECT_TRUE(store.empty());
  EXPECT_EQ(store.bytes(), 0u);
  EXPECT_EQ(store.limits().max_count, 1u);
  EXPECT_TRUE(store.save("b", of_size(10)).ok());
  EXPECT_EQ(store.save("c", of_size(10)).code, ErrorCode::LimitReached);
}

}  // namespace
}  // namespace macsim
