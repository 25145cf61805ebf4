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

namespace agv::pipeline {
namespace {

// Coverage area against hand-computed polygons beside a straight path along +x.
TEST(Metrics, CoverageAreaOfKnownPolygons) {
  const control::Path straight = control::Path::starting_at({0.0, 0.0, 0.0}).add_line(5.0);
  // A track 0.1 m to the left over 2 m: a 2 x 0.1 rectangle.
  EXPECT_NEAR(track_area_m2(straight, {{0.0, 0.1}, {1.0, 0.1}, {2.0, 0.1}}), 0.2, 1e-12);
  // A trapezoid: from 0 to 0.2 m over 1 m, then 0.2 m for 1 m: 0.1 + 0.2.
  EXPECT_NEAR(track_area_m2(straight, {{0.0, 0.0}, {1.0, -0.2}, {2.0, -0.2}}), 0.3, 1e-12);
  // Crossing the path: from +0.1 to -0.1 over 1 m is two triangles of 0.5 x 0.5 x 0.1.
  EXPECT_NEAR(track_area_m2(straight, {{0.0, 0.1}, {1.0, -0.1}}), 0.05, 1e-12);
  // Standing still adds nothing.
  EXPECT_NEAR(track_area_m2(straight, {{1.0, 0.3}, {1.0, 0.3}}), 0.0, 1e-12);
  // Beside an arc: a track 0.1 m inside a quarter circle of radius 1 m, integrated over the
  // path's arc length (pi/2 m): 0.1 * pi / 2, to the trapezoid rule's chord error.
  const control::Path arc = control::Path::starting_at({0.0, 0.0, 0.0}).add_arc(1.0, M_PI / 2);
  std::vector<Eigen::Vector2d> inside;
  for (int i = 0; i <= 90; ++i) {
    const double a = i * M_PI / 180.0;
    inside.emplace_back(0.9 * std::sin(a), 1.0 - 0.9 * std::cos(a));
  }
  EXPECT_NEAR(track_area_m2(arc, inside), 0.1 * M_PI / 2, 1e-6);
}

}  // namespace
}  // namespace agv::pipeline
