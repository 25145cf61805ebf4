#include "control/pid_controller.h"

#include <gtest/gtest.h>

namespace agv::control {
namespace {

constexpr double kPidTs_s = 0.1;

ControlContext context(double path_speed_m_s = 0.3) {
  ControlContext c;
  c.ts_s = kPidTs_s;
  c.path_speed_m_s = path_speed_m_s;
  return c;
}

TrackingEstimate errors(double e_theta_rad, double e_d_m, double curvature_1_m = 0.0) {
  TrackingEstimate e;
  e.e_theta_rad = e_theta_rad;
  e.e_d_m = e_d_m;
  e.curvature_1_m = curvature_1_m;
  return e;
}

// Each term by hand (DESIGN.md signs: e_d > 0 is the vehicle left of the tape, so it must move
// right, vy < 0; e_theta > 0 is turned left, so it must turn right, wz < 0).
TEST(PidController, ProportionalTermsAndFeedForwardByHand) {
  PidController pid({2.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.05});
  const ControllerOutput out = pid.update(errors(0.1, 0.01, 0.5), context(0.4));
  EXPECT_DOUBLE_EQ(out.command.vx_m_s, 0.4);
  EXPECT_DOUBLE_EQ(out.command.vy_m_s, -2.0 * 0.01);
  EXPECT_DOUBLE_EQ(out.command.wz_rad_s, -3.0 * 0.1 + 0.5 * 0.4);
}

// The integral of a constant error over three periods is 3 * Ts * e; it pushes against the
// error, grows no further than the anti-windup bound, and reset() clears it.
TEST(PidController, IntegralPushesAgainstTheErrorWithinItsBound) {
  PidController pid({0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.05});
  ControllerOutput out;
  for (int k = 0; k < 3; ++k) out = pid.update(errors(0.02, 0.01), context());
  EXPECT_NEAR(out.command.vy_m_s, -1.0 * 3 * kPidTs_s * 0.01, 1e-12);
  EXPECT_NEAR(out.command.wz_rad_s, -2.0 * 3 * kPidTs_s * 0.02, 1e-12);
  for (int k = 0; k < 200; ++k) out = pid.update(errors(1.0, 1.0), context());
  EXPECT_NEAR(out.command.vy_m_s, -0.05, 1e-12);
  EXPECT_NEAR(out.command.wz_rad_s, -0.05, 1e-12);
  pid.reset();
  out = pid.update(errors(0.0, 0.0), context());
  EXPECT_DOUBLE_EQ(out.command.vy_m_s, 0.0);
  EXPECT_DOUBLE_EQ(out.command.wz_rad_s, 0.0);
}

// The derivative of an error growing by 0.01 m in one period is 0.1 m/s; it pushes against the
// growth. The first period has no previous error: no derivative kick.
TEST(PidController, DerivativeOpposesAGrowingErrorWithoutAFirstKick) {
  PidController pid({0.0, 0.0, 0.5, 0.0, 0.0, 0.2, 0.05});
  ControllerOutput out = pid.update(errors(0.05, 0.02), context());
  EXPECT_DOUBLE_EQ(out.command.vy_m_s, 0.0);
  EXPECT_DOUBLE_EQ(out.command.wz_rad_s, 0.0);
  out = pid.update(errors(0.07, 0.03), context());
  EXPECT_NEAR(out.command.vy_m_s, -0.5 * 0.01 / kPidTs_s, 1e-12);
  EXPECT_NEAR(out.command.wz_rad_s, -0.2 * 0.02 / kPidTs_s, 1e-12);
}

}  // namespace
}  // namespace agv::control
