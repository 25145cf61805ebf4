#include "pipeline/watchdog.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace agv::pipeline {
namespace {

using namespace std::chrono_literals;

// The watchdog's rules are StallTracker's (tested on a fake clock); these check its wiring on
// the real clock: the monitor thread reports a silence by itself, and run time is scaled. Only
// lower bounds on measured silences: a loaded machine sleeps longer than asked, never shorter.
TEST(Watchdog, TheMonitorReportsASilenceOnItsOwn) {
  Watchdog dog({"busy", "stalls"}, 0.1, Watchdog::Clock::now());
  dog.beat(0);
  dog.beat(1);
  for (int i = 0; i < 30; ++i) {
    dog.beat(0);
    std::this_thread::sleep_for(10ms);
  }
  // Reported while still silent (no beat or stop has closed it yet).
  const std::vector<WatchdogStall> open = dog.stalls();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].thread, "stalls");
  EXPECT_GT(open[0].silent_for_s, 0.1);
  dog.beat(1);
  dog.stop();
  ASSERT_EQ(dog.stalls().size(), 1u);
  EXPECT_GE(dog.stalls()[0].silent_for_s, 0.29);
}

// At 10 simulated seconds per wall second, 50 ms of wall silence is at least 0.5 s.
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
