#include "control/seed004_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

ControlContext seed004_context() {
  ControlContext c;
  c.ts_s = 0.1;
  c.path_speed_m_s = 0.3;
  c.previous_command = {0.3, 0.0, 0.0};
  return c;
}

// Hand-worked S3 law without wheel limits: vehicle 10 mm left of a straight path, turned
// 0 deg: the reference is 10 mm to its right, so vy = k_lateral * (-0.01); vx = path speed.
TEST(Seed004Controller, FeedForwardPlusProportionalHandValues) {
  Seed004Controller::Options options;  // k_lateral 2, k_heading 2.5, no Mecanum wheels
  Seed004Controller controller(options);
  TrackingEstimate e;
  e.e_d_m = 0.01;
  ControllerOutput out = controller.update(e, seed004_context());
  EXPECT_NEAR(out.command.vx_m_s, 0.3, 1e-12);
  EXPECT_NEAR(out.command.vy_m_s, -0.02, 1e-12);
  EXPECT_NEAR(out.command.wz_rad_s, 0.0, 1e-12);
  // Turned 0.1 rad left on an arc of curvature 2/m, on the path: the reference velocity seen
  // from the vehicle is 0.3 (cos 0.1, -sin 0.1); turn = 2 * 0.3 - 2.5 * 0.1.
  e = TrackingEstimate{};
  e.e_theta_rad = 0.1;
  e.curvature_1_m = 2.0;
  out = controller.update(e, seed004_context());
  EXPECT_NEAR(out.command.vx_m_s, 0.3 * std::cos(0.1), 1e-12);
  EXPECT_NEAR(out.command.vy_m_s, -0.3 * std::sin(0.1), 1e-12);
  EXPECT_NEAR(out.command.wz_rad_s, 0.6 - 0.25, 1e-12);
}

// Near the end (pose input): the speed ramps as sqrt(2 a remaining), then the end pose is held
// by the along-track feedback.
TEST(Seed004Controller, SlowsDownAndHoldsTheEndPose) {
  Seed004Controller controller(Seed004Controller::Options{});
  TrackingEstimate e;
  e.remaining_m = 0.06;  // sqrt(2 * 0.3 * 0.06) = 0.19 m/s
  EXPECT_NEAR(controller.update(e, seed004_context()).command.vx_m_s, std::sqrt(2 * 0.3 * 0.06),
              1e-12);
  e.remaining_m = 0.01;  // within end_hold_m: reference = end pose, vx = k_along * 0.01
  EXPECT_NEAR(controller.update(e, seed004_context()).command.vx_m_s, 0.01, 1e-12);
  e.remaining_m = -0.004;  // 4 mm past the end: back up
  EXPECT_NEAR(controller.update(e, seed004_context()).command.vx_m_s, -0.004, 1e-12);
}

// S3.4: a wheel over its limit scales all four by one factor (ratios kept); S3.5: the change of
// every wheel stays within max_accel * ts.
TEST(WheelProtection, ScalingKeepsRatiosAndTheAccelerationLimitHolds) {
  const WheelLimits limits{10.0, 20.0};
  const MecanumWheelSpeeds previous(6.0, 6.0, 6.0, 6.0);
  const MecanumWheelSpeeds desired(20.0, 4.0, 8.0, -2.0);
  // Speed scaling alone (a large acceleration allowance): factor 10/20.
  MecanumWheelSpeeds out = protect_wheel_speeds(desired, previous, {10.0, 1e9}, 0.1);
  EXPECT_TRUE(out.isApprox(desired * 0.5, 1e-12));
  // With the acceleration limit: change from previous at most 2 rad/s per wheel per 0.1 s,
  // scaled as a whole: (10, 2, 4, -1) - 6 = (4, -4, -2, -7) -> x 2/7.
  out = protect_wheel_speeds(desired, previous, limits, 0.1);
  const MecanumWheelSpeeds change = out - previous;
  EXPECT_NEAR(change.cwiseAbs().maxCoeff(), 2.0, 1e-12);
  EXPECT_TRUE(change.isApprox(MecanumWheelSpeeds(4.0, -4.0, -2.0, -7.0) * (2.0 / 7.0), 1e-12));
  EXPECT_LE(out.cwiseAbs().maxCoeff(), limits.max_wheel_speed_rad_s + 1e-12);
}

// The controller with Mecanum wheels: commands whose wheel speeds break the limits come out
// scaled with the direction of motion kept.
TEST(Seed004Controller, MecanumWheelProtectionKeepsTheDirection) {
  Seed004Controller::Options options;
  options.mecanum = MecanumGeometry{};
  options.wheel_limits = {8.0, 1e9};  // 8 rad/s: 0.4 m/s at the rim
  options.k_lateral_1_s = 20.0;
  Seed004Controller controller(options);
  TrackingEstimate e;
  e.e_d_m = 0.02;  // wants vy = -0.4 with vx = 0.3: wheels at up to 14 rad/s
  const ControllerOutput out = controller.update(e, seed004_context());
  EXPECT_LE(mecanum_inverse(*options.mecanum, out.command).cwiseAbs().maxCoeff(), 8.0 + 1e-9);
  EXPECT_NEAR(out.command.vy_m_s / out.command.vx_m_s, -0.4 / 0.3, 1e-9);
}

}  // namespace
}  // namespace agv::control
