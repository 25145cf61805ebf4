#include "control/vehicle_limits.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

const VehicleLimits kVehicleLimits{1.0, 0.5, 0.5, 1.0, 4.0};
constexpr double kLimitTs_s = 0.1;

TEST(VehicleLimits, CommandWithinLimitsPassesUnchanged) {
  const BodyTwist previous{0.3, 0.0, 0.0}, desired{0.3, 0.04, 0.2};
  const BodyTwist out = limit_command(desired, previous, kVehicleLimits, kLimitTs_s);
  EXPECT_DOUBLE_EQ(out.vx_m_s, desired.vx_m_s);
  EXPECT_DOUBLE_EQ(out.vy_m_s, desired.vy_m_s);
  EXPECT_DOUBLE_EQ(out.wz_rad_s, desired.wz_rad_s);
  EXPECT_EQ(check_limits(out, previous, kVehicleLimits, kLimitTs_s), 0u);
}

// A step of (0, 0.3) m/s is 6 times a_max * Ts = 0.05 m/s: scaled to 0.05 m/s in the same
// direction.
TEST(VehicleLimits, AccelerationIsScaledKeepingDirection) {
  const BodyTwist previous{0.3, 0.0, 0.0};
  const BodyTwist out = limit_command({0.3 + 0.3, 0.3, 0.0}, previous, kVehicleLimits, kLimitTs_s);
  EXPECT_NEAR(std::hypot(out.vx_m_s - 0.3, out.vy_m_s), 0.05, 1e-12);
  EXPECT_NEAR((out.vx_m_s - 0.3) / out.vy_m_s, 1.0, 1e-12);
  EXPECT_EQ(check_limits(out, previous, kVehicleLimits, kLimitTs_s), 0u);
}

TEST(VehicleLimits, SpeedsAreClampedAndChecked) {
  const BodyTwist previous{0.95, 0.49, 0.9};
  const BodyTwist out = limit_command({3.0, 2.0, 5.0}, previous, kVehicleLimits, kLimitTs_s);
  EXPECT_LE(out.vx_m_s, 1.0);
  EXPECT_LE(out.vy_m_s, 0.5);
  EXPECT_LE(out.wz_rad_s, 1.0);
  EXPECT_EQ(check_limits(out, previous, kVehicleLimits, kLimitTs_s), 0u);
  EXPECT_EQ(check_limits({3.0, 0.0, 0.0}, {3.0, 0.0, 0.0}, kVehicleLimits, kLimitTs_s),
            kViolatesForwardSpeed);
  EXPECT_EQ(check_limits({0.0, 0.0, 0.0}, {0.3, 0.0, 0.0}, kVehicleLimits, kLimitTs_s),
            kViolatesAcceleration);
  EXPECT_EQ(check_limits({0.0, 0.0, 0.5}, {0.0, 0.0, 0.0}, kVehicleLimits, kLimitTs_s),
            kViolatesYawAcceleration);
}

// A step sideways only: (0, 0.3) m/s in one period is 3 m/s^2, six times a_max. The check must
// see lateral acceleration as well as forward (the drive's wheels deliver both).
TEST(VehicleLimits, LateralAccelerationCountsAsAcceleration) {
  EXPECT_EQ(check_limits({0.3, 0.3, 0.0}, {0.3, 0.0, 0.0}, kVehicleLimits, kLimitTs_s),
            kViolatesAcceleration);
  const BodyTwist out = limit_command({0.3, 0.3, 0.0}, {0.3, 0.0, 0.0}, kVehicleLimits, kLimitTs_s);
  EXPECT_NEAR(out.vy_m_s, 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(out.vx_m_s, 0.3);
}

}  // namespace
}  // namespace agv::control
