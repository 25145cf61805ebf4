#include "control/vehicle_limits.h"

#include <algorithm>
#include <cmath>

namespace agv::control {
namespace {

constexpr double kRelativeTolerance = 1e-6;

bool exceeds(double value, double limit) {
  return std::abs(value) > limit * (1.0 + kRelativeTolerance) + 1e-12;
}

}  // namespace

BodyTwist limit_command(const BodyTwist& desired, const BodyTwist& previous,
                        const VehicleLimits& limits, double ts_s) {
  BodyTwist out{std::clamp(desired.vx_m_s, -limits.v_forward_max_m_s, limits.v_forward_max_m_s),
                std::clamp(desired.vy_m_s, -limits.v_lateral_max_m_s, limits.v_lateral_max_m_s),
                std::clamp(desired.wz_rad_s, -limits.w_max_rad_s, limits.w_max_rad_s)};
  // Both `previous` and the clamped target lie in the speed box, so every point between them
  // does too: scaling the step cannot break a speed limit.
  const double dvx = out.vx_m_s - previous.vx_m_s;
  const double dvy = out.vy_m_s - previous.vy_m_s;
  const double step_m_s = std::hypot(dvx, dvy);
  const double max_step_m_s = limits.a_max_m_s2 * ts_s;
  if (step_m_s > max_step_m_s) {
    const double scale = max_step_m_s / step_m_s;
    out.vx_m_s = previous.vx_m_s + dvx * scale;
    out.vy_m_s = previous.vy_m_s + dvy * scale;
  }
  const double max_turn_step_rad_s = limits.alpha_max_rad_s2 * ts_s;
  out.wz_rad_s = std::clamp(out.wz_rad_s, previous.wz_rad_s - max_turn_step_rad_s,
                            previous.wz_rad_s + max_turn_step_rad_s);
  return out;
}

std::uint32_t check_limits(const BodyTwist& command, const BodyTwist& previous,
                           const VehicleLimits& limits, double ts_s) {
  std::uint32_t violated = 0;
  if (exceeds(command.vx_m_s, limits.v_forward_max_m_s)) violated |= kViolatesForwardSpeed;
  if (exceeds(command.vy_m_s, limits.v_lateral_max_m_s)) violated |= kViolatesLateralSpeed;
  if (exceeds(command.wz_rad_s, limits.w_max_rad_s)) violated |= kViolatesYawRate;
  const double accel_m_s2 =
      std::hypot(command.vx_m_s - previous.vx_m_s, command.vy_m_s - previous.vy_m_s) / ts_s;
  if (exceeds(accel_m_s2, limits.a_max_m_s2)) violated |= kViolatesAcceleration;
  const double yaw_accel_rad_s2 = (command.wz_rad_s - previous.wz_rad_s) / ts_s;
  if (exceeds(yaw_accel_rad_s2, limits.alpha_max_rad_s2)) violated |= kViolatesYawAcceleration;
  return violated;
}

}  // namespace agv::control
