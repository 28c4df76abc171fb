// The recorder's queue: held to its bytes with each sample's bookkeeping counted, so tiny samples
// cannot overshoot it, and a batch taken stays counted until it was written.
#include "sample_queue.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>

namespace macsim::topic {
namespace {

ReceivedSample sample(std::size_t bytes) {
  ReceivedSample s;
  s.bytes.assign(bytes, std::uint8_t{7});
  return s;
}

TEST(SampleQueue, ASampleCountsItsBookkeepingAndItsBuffersCapacity) {
  EXPECT_GE(SampleQueue::cost(sample(1)), sizeof(SampleQueue::Entry) + 1 + 16);
  ReceivedSample grown = sample(10);
  grown.bytes.reserve(1000);
  EXPECT_GE(SampleQueue::cost(grown), 1000u);
}

TEST(SampleQueue, TinySamplesFillItByTheirCostNotTheirBytes) {
  const std::size_t each = SampleQueue::cost(sample(4));
  SampleQueue queue(10 * each);
  int taken = 0;
  for (int i = 0; i < 100; ++i) taken += queue.push(0, sample(4)) ? 1 : 0;
  EXPECT_EQ(taken, 10);  // counted by bytes alone, all 100 (400 bytes) would have fit
  EXPECT_EQ(queue.dropped(), 90u);
  EXPECT_EQ(queue.bytes(), 10 * each);
}

TEST(SampleQueue, ABatchTakenStaysCountedUntilReleased) {
  const std::size_t each = SampleQueue::cost(sample(100));
  SampleQueue queue(4 * each);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(queue.push(i, sample(100)));
  EXPECT_FALSE(queue.push(9, sample(100)));

  SampleQueue::Batch batch = queue.take(std::chrono::milliseconds(0));
  ASSERT_EQ(batch.size(), 4u);
  EXPECT_EQ(batch.front().topic, 0);
  EXPECT_EQ(batch.back().sample.bytes.size(), 100u);
  // Being written: a full queue's worth is still in memory, so nothing more fits.
  EXPECT_EQ(queue.bytes(), 4 * each);
  EXPECT_FALSE(queue.push(9, sample(100)));
  EXPECT_TRUE(queue.take(std::chrono::milliseconds(0)).empty());

  queue.release(batch);  // written
  EXPECT_EQ(queue.bytes(), 0u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(queue.push(i, sample(100)));
  EXPECT_FALSE(queue.push(9, sample(100)));
  EXPECT_EQ(queue.dropped(), 3u);
}

TEST(SampleQueue, ASampleLargerThanTheBudgetIsDropped) {
  SampleQueue queue(1000);
  EXPECT_FALSE(queue.push(0, sample(2000)));
  EXPECT_TRUE(queue.push(0, sample(10)));
  EXPECT_EQ(queue.dropped(), 1u);
}

}  // namespace
}  // namespace macsim::topic
