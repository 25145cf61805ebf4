#include "pipeline/watchdog.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace agv::pipeline {
namespace {

using namespace std::chrono_literals;

// A thread that beats every 10 ms is never reported; one that goes silent for 300 ms with a
// 100 ms timeout is reported once, with the silence measured to within the check period plus
// scheduling slack; a thread that finished is not watched any more.
TEST(Watchdog, ReportsOnlyTheSilentThreadOnceWithItsSilence) {
  Watchdog dog({"busy", "stalls", "finishes"}, 0.1, Watchdog::Clock::now());
  dog.finished(2);
  for (int i = 0; i < 60; ++i) {
    dog.beat(0);
    if (i < 10 || i >= 40) dog.beat(1);  // silent from about 100 ms to 400 ms
    std::this_thread::sleep_for(10ms);
  }
  dog.stop();
  const std::vector<WatchdogStall> stalls = dog.stalls();
  ASSERT_EQ(stalls.size(), 1u);
  EXPECT_EQ(stalls[0].thread, "stalls");
  EXPECT_GE(stalls[0].silent_for_s, 0.29);
  EXPECT_LT(stalls[0].silent_for_s, 1.0);  // sanitizer builds sleep longer than asked
  EXPECT_NEAR(stalls[0].last_seen_s, 0.1, 0.3);
}

// Run time is scaled: at 10 simulated seconds per wall second, 50 ms of wall silence is 0.5 s.
TEST(Watchdog, MeasuresInRunTime) {
  Watchdog dog({"camera"}, 0.2, Watchdog::Clock::now(), 10.0);
  dog.beat(0);
  std::this_thread::sleep_for(50ms);
  dog.beat(0);
  dog.stop();
  ASSERT_EQ(dog.stalls().size(), 1u);
  EXPECT_GE(dog.stalls()[0].silent_for_s, 0.49);
}

}  // namespace
}  // namespace agv::pipeline
