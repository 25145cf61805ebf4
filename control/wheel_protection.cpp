#include "control/wheel_protection.h"

namespace agv::control {

MecanumWheelSpeeds protect_wheel_speeds(const MecanumWheelSpeeds& desired,
                                        const MecanumWheelSpeeds& previous,
                                        const WheelLimits& limits, double ts_s) {
  MecanumWheelSpeeds out = desired;
  const double fastest_rad_s = out.cwiseAbs().maxCoeff();
  if (fastest_rad_s > limits.max_wheel_speed_rad_s) {
    out *= limits.max_wheel_speed_rad_s / fastest_rad_s;
  }
  // Both `previous` and `out` are inside the speed box, so every point between them is too.
  const MecanumWheelSpeeds change = out - previous;
  const double largest_change_rad_s = change.cwiseAbs().maxCoeff();
  const double allowed_change_rad_s = limits.max_wheel_accel_rad_s2 * ts_s;
  if (largest_change_rad_s > allowed_change_rad_s) {
    out = previous + change * (allowed_change_rad_s / largest_change_rad_s);
  }
  return out;
}

}  // namespace agv::control
