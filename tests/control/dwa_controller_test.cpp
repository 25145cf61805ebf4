#include "control/dwa_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

ControlContext seed002_context() {
  ControlContext c;
  c.ts_s = 0.1;
  c.path_speed_m_s = 0.5;
  c.previous_command = {0.5, 0.0, 0.0};
  c.limits.v_forward_max_m_s = 0.8;
  c.limits.a_max_m_s2 = 1.2;
  c.limits.w_max_rad_s = 10.0 * M_PI / 180.0;
  c.limits.alpha_max_rad_s2 = 10.0 * M_PI / 180.0;
  return c;
}

// The default vehicle limits at 0.3 m/s along the path, turning at w0_rad_s.
ControlContext default_context(double w0_rad_s) {
  ControlContext c;
  c.ts_s = 0.1;
  c.path_speed_m_s = 0.3;
  c.previous_command = {0.3, 0.0, w0_rad_s};
  return c;
}

// The command lies in the dynamic window: |v - v0| <= a Ts, |w - w0| <= alpha Ts, vy = 0.
// 20 mm left of a straight path, heading along it, the best roll-out turns right, towards it.
TEST(DwaController, StaysInTheWindowAndTurnsTowardsThePath) {
  for (bool improved : {false, true}) {
    DwaController::Options options;
    options.improved = improved;
    DwaController dwa(options);
    TrackingEstimate e;
    e.e_d_m = 0.02;
    const ControlContext c = seed002_context();
    const ControllerOutput out = dwa.update(e, c);
    EXPECT_LE(std::abs(out.command.vx_m_s - 0.5), 1.2 * 0.1 + 1e-12);
    EXPECT_LE(std::abs(out.command.wz_rad_s), c.limits.alpha_max_rad_s2 * 0.1 + 1e-12);
    EXPECT_EQ(out.command.vy_m_s, 0.0);
    EXPECT_LT(out.command.wz_rad_s, 0.0) << (improved ? "improved" : "plain");
    EXPECT_EQ(dwa.last_candidates(), 11 * 21);
  }
}

// Improved DWA keeps to the wheels: with wheels 0.5 m from the reference and a wheel-speed
// limit of 0.5 m/s at v >= 0.38 m/s, only |w| <= sqrt(0.5^2 - v^2) / 0.5 is admitted.
TEST(DwaController, ImprovedWindowDropsWhatTheWheelsCannotDo) {
  DwaController::Options options;
  options.max_wheel_speed_m_s = 0.5;
  DwaController dwa(options);
  ControlContext c = seed002_context();
  c.limits.w_max_rad_s = 2.0;
  c.limits.alpha_max_rad_s2 = 20.0;
  TrackingEstimate e;
  e.e_theta_rad = 0.5;  // wants a hard right turn
  const ControllerOutput out = dwa.update(e, c);
  const double v = out.command.vx_m_s;
  EXPECT_LE(std::hypot(v, 0.5 * out.command.wz_rad_s), 0.5 + 1e-12);
  EXPECT_LT(dwa.last_candidates(), 11 * 21);
}

// From the camera on an arc of R 1 m, on the tape and along it at 0.3 m/s, turning at
// v / R already: the heading term, less the arc's own bend, is best for the roll-out that stays
// on the arc, w = 0.3 rad/s (within a tenth of the window's sample step, 0.04 rad/s; the
// parabola between samples refines it). The bearing to the next path point alone leans half the
// arc's angle inwards and scores a tighter turn best.
TEST(DwaController, OnAnArcTheBestRollOutStaysOnIt) {
  for (bool improved : {false, true}) {
    DwaController::Options options;
    options.improved = improved;
    DwaController dwa(options);
    const ControlContext c = default_context(0.3);
    TrackingEstimate e;
    e.curvature_1_m = 1.0;
    const ControllerOutput out = dwa.update(e, c);
    EXPECT_NEAR(out.command.wz_rad_s, 0.3, 0.004) << (improved ? "improved" : "plain");
  }
}

// The camera previews the end of an arc 0.05 m ahead (a line follows): the roll-outs (0.06 m
// at 0.3 m/s) are scored against the line beyond it, so the vehicle starts to unwind its turn,
// w below v / R by more than half a sample step, where without the preview it keeps turning at
// v / R.
TEST(DwaController, APreviewedLineAheadUnwindsTheTurn) {
  DwaController dwa(DwaController::Options{});
  const ControlContext c = default_context(0.3);
  TrackingEstimate e;
  e.curvature_1_m = 1.0;
  EXPECT_NEAR(dwa.update(e, c).command.wz_rad_s, 0.3, 0.004);
  e.curvature_change_m = 0.05;
  e.curvature_ahead_1_m = 0.0;
  EXPECT_LT(dwa.update(e, c).command.wz_rad_s, 0.3 - 0.02);
}

// A dual steering-wheel vehicle turns its wheels at 1 rad/s: at 0.3 m/s with the wheels 0.5 m
// from the reference point its yaw rate changes by at most 0.3 x 1 / 0.5 = 0.6 rad/s^2 (at zero
// steer), so the window holds |w - w0| <= 0.06 rad/s, not the 0.4 rad/s of alpha_max (a wider
// window commands turns the wheels reach a second later, and the vehicle weaves 57 mm).
TEST(DwaController, SteeredWheelsNarrowTheWindow) {
  for (bool improved : {false, true}) {
    DwaController::Options options;
    options.improved = improved;
    options.max_steer_rate_rad_s = 1.0;
    DwaController dwa(options);
    const ControlContext c = default_context(0.0);
    TrackingEstimate e;
    e.e_theta_rad = 0.3;  // wants a hard right turn
    const ControllerOutput out = dwa.update(e, c);
    EXPECT_LT(out.command.wz_rad_s, 0.0);
    EXPECT_GE(out.command.wz_rad_s, -0.06 - 1e-12);
  }
}

// At the end of the path (pose input: remaining 0) the window only holds v = 0 or braking.
TEST(DwaController, StopsForTheEndOfThePath) {
  DwaController dwa(DwaController::Options{});
  TrackingEstimate e;
  e.remaining_m = 0.0;
  ControlContext c = seed002_context();
  c.previous_command = {0.1, 0.0, 0.0};
  EXPECT_EQ(dwa.update(e, c).command.vx_m_s, 0.0);
}

}  // namespace
}  // namespace agv::control
