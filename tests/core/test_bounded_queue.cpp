#include <gtest/gtest.h>

#include <thread>

#include "core/bounded_queue.h"

using namespace plslam;

TEST(BoundedQueue, BlockPolicyLosesNothingAndEndsStream) {
  BoundedQueue<int> q(2, QueuePolicy::kBlock);
  std::thread producer([&] {
    for (int i = 0; i < 100; ++i) q.push(i);
    q.close();
  });
  int expected = 0;
  while (auto v = q.pop()) EXPECT_EQ(*v, expected++);
  producer.join();
  EXPECT_EQ(expected, 100);
  EXPECT_EQ(q.dropped(), 0u);
}

TEST(BoundedQueue, DropOldestKeepsNewest) {
  BoundedQueue<int> q(3, QueuePolicy::kDropOldest);
  for (int i = 0; i < 10; ++i) q.push(i);
  q.close();
  EXPECT_EQ(q.dropped(), 7u);
  EXPECT_EQ(*q.pop(), 7);
  EXPECT_EQ(*q.pop(), 8);
  EXPECT_EQ(*q.pop(), 9);
  EXPECT_FALSE(q.pop().has_value());
  EXPECT_FALSE(q.push(11));
}
