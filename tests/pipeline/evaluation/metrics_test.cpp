#include "pipeline/evaluation/metrics.h"

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

namespace agv::pipeline {
namespace {

// The whole metric set of a hand-made run: the trace of SettleTimeIsTheLastReentryInterpolated
// (e_d 10, 6, 3, 1.5, 2.5, 1, 0.5, 0 mm every 0.1 s; e_theta 0.01 rad, inside its band), lateral
// commands 0, -0.05, -0.03, 0, 0, 0, 0, 0 m/s at path speed 0.3 m/s straight on.
// Settle 0.4333 s (re-entry between the samples at 0.4 and 0.5 s), so the RMS after settling is
// over the samples from t = 0.5 s: e_d 1, 0.5, 0 mm -> sqrt((1 + 0.25 + 0) / 3) mm, e_theta
// 0.01 rad. The first measurement arrives at 0.1 s. Largest lateral acceleration: the first step,
// 0.05 m/s in 0.1 s = 0.5 m/s^2. No overshoot (e_d never crosses zero). The scenario's default
// bands are 2 mm / 2 deg.
TEST(Metrics, RunMetricsOfAHandMadeTrace) {
  Scenario scenario;
  scenario.path = control::Path::starting_at({-1.0, 0.0, 0.0}).add_line(5.0);  // under both wheels
  scenario.path_speed_m_s = 0.3;
  const std::vector<double> e_d{0.010, 0.006, 0.003, 0.0015, 0.0025, 0.001, 0.0005, 0.0};
  const std::vector<double> vy{0.0, -0.05, -0.03, 0.0, 0.0, 0.0, 0.0, 0.0};
  RunResult run;
  for (size_t i = 0; i < e_d.size(); ++i) {
    TraceRow row;
    row.t_s = 0.1 * i;
    row.truth.e_d_m = e_d[i];
    row.truth.e_theta_rad = 0.01;
    row.output.command = {0.3, vy[i], 0.0};
    row.measurement_arrived = i >= 1;  // the first measurement arrives at 0.1 s
    row.front_wheel = {0.3 * row.t_s + 0.2, e_d[i]};
    row.rear_wheel = {0.3 * row.t_s - 0.2, e_d[i]};
    run.rows.push_back(row);
  }
  const RunMetrics m = compute_metrics(run, scenario);
  ASSERT_TRUE(m.settle_time_s);
  EXPECT_NEAR(*m.settle_time_s, 0.4 + 0.1 / 3.0, 1e-12);
  ASSERT_TRUE(m.rms_e_d_m && m.rms_e_theta_rad);
  EXPECT_NEAR(*m.rms_e_d_m, 1e-3 * std::sqrt(1.25 / 3.0), 1e-12);
  EXPECT_NEAR(*m.rms_e_theta_rad, 0.01, 1e-12);
  EXPECT_DOUBLE_EQ(m.max_abs_e_d_m, 0.010);
  // From the period after the first measurement on: 3, 1.5, 2.5, ... mm.
  EXPECT_DOUBLE_EQ(m.max_abs_e_d_after_first_measurement_m, 0.003);
  EXPECT_DOUBLE_EQ(m.overshoot_e_d_m, 0.0);
  EXPECT_NEAR(m.max_abs_v_lateral_m_s, 0.05, 1e-12);
  EXPECT_NEAR(m.max_abs_accel_m_s2, 0.5, 1e-9);
  EXPECT_EQ(m.limit_violations, 0);
  // Both wheel tracks run beside the path at e_d over 0.21 m of travel; each covers the
  // trapezoid-rule area of e_d against x: 0.03 m x sum of the interval means.
  double area_one = 0.0;
  for (size_t i = 0; i + 1 < e_d.size(); ++i) area_one += 0.03 * 0.5 * (e_d[i] + e_d[i + 1]);
  EXPECT_NEAR(m.coverage_area_m2, 2.0 * area_one, 1e-12);
}

// Lateral speed and acceleration mean the same for a vehicle that turns (vy = 0, as DWA
// commands) as for one that moves sideways: at 0.3 m/s turned 0.1 rad from the path the
// reference point crosses it at 0.3 sin(0.1) m/s; a heading that turns by 0.06 rad in one
// period changes the floor-frame velocity by 2 x 0.3 sin(0.03) m/s in 0.1 s. (Before, both
// read 0: they were |vy| and the change of the body-frame command.)
TEST(Metrics, LateralSpeedAndAccelerationCountTurning) {
  Scenario scenario;
  scenario.path = control::Path::starting_at({-1.0, 0.0, 0.0}).add_line(5.0);
  scenario.path_speed_m_s = 0.3;
  const std::vector<double> yaw{0.0, 0.04, 0.1, 0.1};
  RunResult run;
  for (size_t i = 0; i < yaw.size(); ++i) {
    TraceRow row;
    row.t_s = 0.1 * i;
    row.has_truth = true;
    row.pose = {0.03 * i, 0.0, yaw[i]};
    row.truth.e_theta_rad = yaw[i];
    row.output.command = {0.3, 0.0, 0.4};
    run.rows.push_back(row);
  }
  const RunMetrics m = compute_metrics(run, scenario);
  EXPECT_NEAR(m.max_abs_v_lateral_m_s, 0.3 * std::sin(0.1), 1e-12);
  EXPECT_NEAR(m.max_abs_accel_m_s2, 2.0 * 0.3 * std::sin(0.03) / 0.1, 1e-9);
}

}  // namespace
}  // namespace agv::pipeline
