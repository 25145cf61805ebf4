#pragma once

#include <cmath>

#include "common/body_twist.h"
#include "common/pose2.h"

namespace agv {

// Pose after moving with a constant body twist for dt_s: the exact SE(2) exponential, not the
// small-angle model of seed 000 eq. 12 (DIGEST erratum 4).
inline Pose2 integrate_twist(const Pose2& start, const BodyTwist& twist, double dt_s) {
  const double angle = twist.wz_rad_s * dt_s;
  double dx, dy;
  if (std::abs(angle) < 1e-9) {
    // Second-order series of the expression below; exact to rounding for |angle| < 1e-9.
    dx = (twist.vx_m_s - 0.5 * twist.vy_m_s * angle) * dt_s;
    dy = (twist.vy_m_s + 0.5 * twist.vx_m_s * angle) * dt_s;
  } else {
    const double s = std::sin(angle), c = std::cos(angle);
    dx = (twist.vx_m_s * s + twist.vy_m_s * (c - 1.0)) / twist.wz_rad_s;
    dy = (twist.vx_m_s * (1.0 - c) + twist.vy_m_s * s) / twist.wz_rad_s;
  }
  return start.compose({dx, dy, angle});
}

}  // namespace agv
