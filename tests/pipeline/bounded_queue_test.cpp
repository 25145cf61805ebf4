#include "pipeline/bounded_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace agv::pipeline {
namespace {

using namespace std::chrono_literals;

TEST(BoundedQueue, DropOldestKeepsTheNewestAndCountsDrops) {
  BoundedQueue<int> queue(3, QueuePolicy::kDropOldest);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(queue.push(i));
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(*queue.pop(0ms), 2);
  EXPECT_EQ(queue.stats().dropped, 2u);
  EXPECT_EQ(queue.stats().max_depth, 3u);
}

TEST(BoundedQueue, BlockingPushTimesOutWhenFull) {
  BoundedQueue<int> queue(1, QueuePolicy::kBlock);
  EXPECT_TRUE(queue.push(1));
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(queue.push(2, 20ms));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 20ms);
  EXPECT_EQ(queue.stats().rejected, 1u);
  EXPECT_EQ(*queue.pop(0ms), 1);
}

TEST(BoundedQueue, PopTimesOutWhenEmpty) {
  BoundedQueue<int> queue(2, QueuePolicy::kBlock);
  EXPECT_FALSE(queue.pop(10ms).has_value());
}

TEST(BoundedQueue, PopNewestSupersedesTheRest) {
  BoundedQueue<int> queue(8, QueuePolicy::kDropOldest);
  for (int i = 0; i < 4; ++i) queue.push(i);
  EXPECT_EQ(*queue.pop_newest(), 3);
  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.stats().superseded, 3u);
  EXPECT_FALSE(queue.pop_newest().has_value());
}

TEST(BoundedQueue, CloseWakesEveryWaiter) {
  BoundedQueue<int> full(1, QueuePolicy::kBlock);
  full.push(0);
  BoundedQueue<int> empty(1, QueuePolicy::kBlock);
  std::atomic<int> woken{0};
  std::thread pusher([&] {
    EXPECT_FALSE(full.push(1, std::chrono::hours(1)));
    ++woken;
  });
  std::thread popper([&] {
    EXPECT_FALSE(empty.pop(std::chrono::hours(1)).has_value());
    ++woken;
  });
  std::this_thread::sleep_for(20ms);
  full.close();
  empty.close();
  pusher.join();
  popper.join();
  EXPECT_EQ(woken.load(), 2);
  EXPECT_FALSE(empty.push(5));
  EXPECT_EQ(*full.pop(0ms), 0);  // what was in the queue is still delivered after close
}

// Four producers push as fast as they can while a slow consumer takes the newest item; every
// item pushed is accounted for: pushed = popped + dropped + superseded + left in the queue.
TEST(BoundedQueue, StressEveryItemIsAccountedFor) {
  for (QueuePolicy policy : {QueuePolicy::kDropOldest, QueuePolicy::kBlock}) {
    BoundedQueue<int> queue(4, policy);
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> attempts{0}, refused{0};
    std::vector<std::thread> producers;
    for (int p = 0; p < 4; ++p) {
      producers.emplace_back([&] {
        while (!stop.load()) {
          ++attempts;
          if (!queue.push(1, 1ms)) ++refused;
        }
      });
    }
    std::uint64_t taken = 0;
    for (int i = 0; i < 200; ++i) {
      if (i % 2 == 0) {
        if (queue.pop_newest()) ++taken;
      } else if (queue.pop(1ms)) {
        ++taken;
      }
      std::this_thread::sleep_for(200us);
    }
    stop.store(true);
    queue.close();
    for (std::thread& t : producers) t.join();
    const QueueStats s = queue.stats();
    EXPECT_EQ(s.pushed + s.rejected, attempts.load());
    EXPECT_EQ(s.rejected, refused.load());
    EXPECT_EQ(s.popped, taken);
    EXPECT_EQ(s.pushed, s.popped + s.dropped + s.superseded + queue.size());
    EXPECT_LE(s.max_depth, 4u);
  }
}

}  // namespace
}  // namespace agv::pipeline
