#include "control/wheel_protection.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

constexpr double kWheelTs_s = 0.1;
const WheelLimits kWheelLimits{10.0, 20.0};  // 10 rad/s; 20 rad/s^2: 2 rad/s per tick

MecanumWheelSpeeds wheels(double a, double b, double c, double d) {
  MecanumWheelSpeeds w;
  w << a, b, c, d;
  return w;
}

// Seed 004 S3.4: a command asking 15 rad/s of one wheel is scaled by 10/15 on all four, so the
// ratios (the direction of motion and the turn) stay.
TEST(WheelProtection, SpeedIsScaledOnAllFourKeepingTheirRatios) {
  const MecanumWheelSpeeds desired = wheels(15.0, 6.0, -3.0, 9.0);
  const MecanumWheelSpeeds out =
      protect_wheel_speeds(desired, desired * (10.0 / 15.0), kWheelLimits, kWheelTs_s);
  EXPECT_NEAR(out.cwiseAbs().maxCoeff(), 10.0, 1e-12);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(out[i], desired[i] * 10.0 / 15.0, 1e-12) << i;
}

// Seed 004 S3.5: from rest, a change of 5 rad/s on one wheel is scaled to 2 rad/s (20 rad/s^2
// over 0.1 s), the change of all four by the same factor.
TEST(WheelProtection, ChangeIsScaledOnAllFourKeepingItsDirection) {
  const MecanumWheelSpeeds previous = wheels(1.0, 1.0, 1.0, 1.0);
  const MecanumWheelSpeeds desired = wheels(6.0, 3.0, 1.0, -1.5);
  const MecanumWheelSpeeds out = protect_wheel_speeds(desired, previous, kWheelLimits, kWheelTs_s);
  const MecanumWheelSpeeds change = out - previous;
  EXPECT_NEAR(change.cwiseAbs().maxCoeff(), 2.0, 1e-12);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(change[i], (desired[i] - 1.0) * 2.0 / 5.0, 1e-12) << i;
}

// Within both limits the command passes unchanged.
TEST(WheelProtection, ACommandWithinTheLimitsPassesUnchanged) {
  const MecanumWheelSpeeds previous = wheels(5.0, 5.0, 5.0, 5.0);
  const MecanumWheelSpeeds desired = wheels(6.0, 4.5, 5.5, 4.0);
  const MecanumWheelSpeeds out = protect_wheel_speeds(desired, previous, kWheelLimits, kWheelTs_s);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(out[i], desired[i]) << i;
}

}  // namespace
}  // namespace agv::control
