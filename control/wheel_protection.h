#pragma once

#include "control/mecanum_kinematics.h"

namespace agv::control {

struct WheelLimits {
  double max_wheel_speed_rad_s = 20.0;   // each wheel, either direction
  double max_wheel_accel_rad_s2 = 20.0;  // change of each wheel's speed per second
};

// Seed 004 S3.4 and S3.5 on the wheel speeds of one control tick:
// - S3.4: when a wheel would exceed max_wheel_speed_rad_s, all four are scaled by the same
//   factor, so the ratios between them (the direction of motion and the turn) are kept;
// - S3.5: when a wheel's change from `previous` would exceed max_wheel_accel_rad_s2 * ts_s,
//   the change of all four is scaled by the same factor (the change keeps its direction).
// `previous` must itself be within the speed limit; the result then meets both limits.
MecanumWheelSpeeds protect_wheel_speeds(const MecanumWheelSpeeds& desired,
                                        const MecanumWheelSpeeds& previous,
                                        const WheelLimits& limits, double ts_s);

}  // namespace agv::control
