#include "pipeline/metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::pipeline {
namespace {

// A hand-made trace: e_d falls 10, 6, 3, 1.5, 2.5, 1, 0.5, 0 mm at t = 0 .. 0.7 s; e_theta stays
// within its band. The last sample outside 2 mm is t = 0.4 s (2.5 mm); e_d re-enters the band
// a third of the way to the next sample (2.5 -> 1.0 crosses 2.0 at 0.5 / 1.5): t = 0.4333 s.
TEST(Metrics, SettleTimeIsTheLastReentryInterpolated) {
  const std::vector<double> t{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  const std::vector<double> e_d{0.010, 0.006, 0.003, 0.0015, 0.0025, 0.001, 0.0005, 0.0};
  const std::vector<double> e_theta(8, 0.01);
  const auto settle = settle_time(t, e_d, e_theta, 0.002, 0.0349);
  ASSERT_TRUE(settle);
  EXPECT_NEAR(*settle, 0.4 + 0.1 / 3.0, 1e-12);
}

TEST(Metrics, SettleTimeLaterOfTheTwoSignalsAndUndefinedWhenNeverSettled) {
  const std::vector<double> t{0.0, 0.1, 0.2, 0.3};
  const std::vector<double> e_d{0.003, 0.001, 0.001, 0.001};
  const std::vector<double> e_theta{0.1, 0.1, 0.02,
                                    0.0};  // band 0.05: re-enters at 0.1 + 0.1 * 5/8
  EXPECT_NEAR(*settle_time(t, e_d, e_theta, 0.002, 0.05), 0.1 + 0.1 * 0.05 / 0.08, 1e-12);
  EXPECT_FALSE(settle_time(t, {0.0, 0.0, 0.0, 0.003}, e_theta, 0.002, 0.05).has_value());
  EXPECT_DOUBLE_EQ(*settle_time(t, {0.0, 0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}, 0.002, 0.05), 0.0);
}

TEST(Metrics, OvershootIsTheExcursionPastZero) {
  EXPECT_DOUBLE_EQ(overshoot({0.01, 0.004, -0.0012, -0.0005, 0.0}), 0.0012);
  EXPECT_DOUBLE_EQ(overshoot({-0.01, -0.002, 0.0007, 0.0}), 0.0007);
  EXPECT_DOUBLE_EQ(overshoot({0.01, 0.005, 0.001}), 0.0);
}

TEST(Metrics, RootMeanSquareFromAnIndex) {
  EXPECT_DOUBLE_EQ(*rms_from({9.0, 3.0, -4.0}, 1), std::sqrt(12.5));
  EXPECT_FALSE(rms_from({1.0}, 1).has_value());
}

}  // namespace
}  // namespace agv::pipeline
