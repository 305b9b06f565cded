// BoundedQueue: the hand-off between a full-device run's threads.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "navaid/runtime/bounded_queue.hpp"

namespace {

using navaid::runtime::BoundedQueue;

TEST(BoundedQueue, DropsTheOldestWhenFullAndCountsIt) {
  BoundedQueue<int> q(2, true);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_EQ(q.dropped(), 3u);
  EXPECT_EQ(q.max_depth(), 2u);
  q.close();
  EXPECT_EQ(q.pop(), 3);  // the newest two are kept, in order
  EXPECT_EQ(q.pop(), 4);
  EXPECT_EQ(q.pop(), std::nullopt);
}

TEST(BoundedQueue, WaitsForRoomAndLosesNothing) {
  BoundedQueue<int> q(1, false);
  std::vector<int> got;
  std::thread consumer([&] {
    while (auto v = q.pop()) got.push_back(*v);
  });
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(q.push(i));
  q.close();
  consumer.join();
  ASSERT_EQ(got.size(), 1000u);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(got[static_cast<std::size_t>(i)], i);
  EXPECT_EQ(q.dropped(), 0u);
}

TEST(BoundedQueue, ClosingWakesAWaitingProducerAndRefusesMore) {
  BoundedQueue<int> q(1, false);
  ASSERT_TRUE(q.push(1));
  bool refused = false;
  std::thread producer([&] { refused = !q.push(2); });  // waits: the queue is full
  q.close(true);                                         // after an error: discard and stop
  producer.join();
  EXPECT_TRUE(refused);
  EXPECT_EQ(q.pop(), std::nullopt);
}

}  // namespace
