#pragma once

#include <cstdint>

#include "common/body_twist.h"

namespace agv::control {

// What the vehicle can do, bounding every command it is sent. Acceleration is the change of the
// commanded body velocity (vx, vy) between consecutive periods divided by the period: what the
// wheel drives must deliver.
struct VehicleLimits {
  double v_forward_max_m_s = 1.0;
  double v_lateral_max_m_s = 0.5;
  double a_max_m_s2 = 0.5;
  double w_max_rad_s = 1.0;
  double alpha_max_rad_s2 = 4.0;
};

// Bits of what check_limits returns.
enum LimitViolation : std::uint32_t {
  kViolatesForwardSpeed = 1u << 0,
  kViolatesLateralSpeed = 1u << 1,
  kViolatesAcceleration = 1u << 2,
  kViolatesYawRate = 1u << 3,
  kViolatesYawAcceleration = 1u << 4,
};

// The command closest to `desired` that the vehicle can follow after `previous` one period
// ts_s earlier: speeds clamped to their limits, then the change of (vx, vy) scaled down to
// a_max * ts_s keeping its direction, and the change of wz clamped to alpha_max * ts_s.
// `previous` must itself be within the speed limits.
BodyTwist limit_command(const BodyTwist& desired, const BodyTwist& previous,
                        const VehicleLimits& limits, double ts_s);

// Which limits `command` breaks after `previous` (0: none). A relative tolerance of 1e-6 absorbs
// floating-point rounding of commands that sit exactly on a limit.
std::uint32_t check_limits(const BodyTwist& command, const BodyTwist& previous,
                           const VehicleLimits& limits, double ts_s);

}  // namespace agv::control
