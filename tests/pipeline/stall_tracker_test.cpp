#include "pipeline/stall_tracker.h"

#include <gtest/gtest.h>

namespace agv::pipeline {
namespace {

// Driven by a fake clock: the watchdog's rules, exactly, whatever the machine's load.
// Timeout 0.1 s, checked every 0.025 s (the monitor's period), over 0.6 s: "busy" beats every
// 0.01 s; "stalls" is silent from 0.1 s to 0.4 s; "finishes" finished at 0 and then never beats.
TEST(StallTracker, ReportsOnlyTheSilentThreadOnceWithItsSilence) {
  StallTracker tracker({"busy", "stalls", "finishes"}, 0.1);
  tracker.finished(2, 0.0);
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.01 * i;
    tracker.beat(0, t);
    if (i <= 10 || i >= 40) tracker.beat(1, t);
    if (i % 3 == 0) tracker.check(t);
  }
  tracker.close(0.6);
  ASSERT_EQ(tracker.stalls().size(), 1u);
  EXPECT_EQ(tracker.stalls()[0].thread, "stalls");
  EXPECT_DOUBLE_EQ(tracker.stalls()[0].last_seen_s, 0.1);
  EXPECT_NEAR(tracker.stalls()[0].silent_for_s, 0.3, 1e-12);  // ended by its next beat at 0.4 s
}

// A silence of exactly the timeout is no stall; beyond it, one (times exact in binary).
TEST(StallTracker, ASilenceUpToTheTimeoutIsNoStall) {
  StallTracker tracker({"camera"}, 0.125);
  tracker.beat(0, 1.0);
  tracker.check(1.125);
  tracker.beat(0, 1.125);
  tracker.check(1.25);
  EXPECT_TRUE(tracker.stalls().empty());
  tracker.check(1.25 + 1.0 / 1024);
  EXPECT_EQ(tracker.stalls().size(), 1u);
}

// Two silences of one thread are two records; a silence still open when tracking is closed
// ends there; the record's length follows the silence between checks.
TEST(StallTracker, EachSilenceIsOneRecordAndCloseEndsTheOpenOne) {
  StallTracker tracker({"control"}, 0.2);
  tracker.beat(0, 0.0);
  tracker.check(0.5);
  EXPECT_NEAR(tracker.stalls().at(0).silent_for_s, 0.5, 1e-12);
  tracker.check(0.7);
  EXPECT_NEAR(tracker.stalls().at(0).silent_for_s, 0.7, 1e-12);
  tracker.beat(0, 1.0);
  tracker.check(1.5);
  tracker.close(2.0);
  ASSERT_EQ(tracker.stalls().size(), 2u);
  EXPECT_NEAR(tracker.stalls()[0].silent_for_s, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(tracker.stalls()[1].last_seen_s, 1.0);
  EXPECT_NEAR(tracker.stalls()[1].silent_for_s, 1.0, 1e-12);
}

}  // namespace
}  // namespace agv::pipeline
