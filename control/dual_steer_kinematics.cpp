#include "control/dual_steer_kinematics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace agv::control {
namespace {

// Steer angle and signed speed that move a wheel with velocity (vx, vy).
void steer_to(double vx_m_s, double vy_m_s, double max_steer_rad, double* steer_rad,
              double* speed_m_s) {
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  const double speed = std::hypot(vx_m_s, vy_m_s);
  if (speed < 1e-9) {
    *speed_m_s = 0.0;  // keep the steer angle where it is
    return;
  }
  double angle = std::atan2(vy_m_s, vx_m_s);
  double sign = 1.0;
  if (angle > kHalfPi) angle -= std::numbers::pi, sign = -1.0;
  if (angle < -kHalfPi) angle += std::numbers::pi, sign = -1.0;
  *steer_rad = std::clamp(angle, -max_steer_rad, max_steer_rad);
  // Clamped: the part of the velocity along the wheel is what it can drive.
  *speed_m_s = sign * speed * std::cos(angle - *steer_rad);
}

}  // namespace

double DualSteerGeometry::front_x_m() const {
  switch (form) {
    case DriveForm::kBothSteer:
      return 0.5 * wheelbase_m;
    case DriveForm::kRearDriveFront:
      return wheelbase_m;
    case DriveForm::kFrontDriveRear:
      return 0.0;
  }
  return 0.0;
}

double DualSteerGeometry::rear_x_m() const { return front_x_m() - wheelbase_m; }

DualSteerWheels dual_steer_inverse(const DualSteerGeometry& g, const BodyTwist& twist) {
  DualSteerWheels w;
  const double front_vy = twist.vy_m_s + twist.wz_rad_s * g.front_x_m();
  const double rear_vy = twist.vy_m_s + twist.wz_rad_s * g.rear_x_m();
  if (g.front_steers()) {
    steer_to(twist.vx_m_s, front_vy, g.max_steer_rad, &w.front_steer_rad, &w.front_speed_m_s);
  } else {
    w.front_speed_m_s = twist.vx_m_s;
  }
  if (g.rear_steers()) {
    steer_to(twist.vx_m_s, rear_vy, g.max_steer_rad, &w.rear_steer_rad, &w.rear_speed_m_s);
  } else {
    w.rear_speed_m_s = twist.vx_m_s;
  }
  return w;
}

BodyTwist dual_steer_forward(const DualSteerGeometry& g, const DualSteerWheels& w) {
  const double front_vx = w.front_speed_m_s * std::cos(w.front_steer_rad);
  const double front_vy = w.front_speed_m_s * std::sin(w.front_steer_rad);
  const double rear_vx = w.rear_speed_m_s * std::cos(w.rear_steer_rad);
  const double rear_vy = w.rear_speed_m_s * std::sin(w.rear_steer_rad);
  const double xf = g.front_x_m(), xr = g.rear_x_m();
  BodyTwist twist;
  twist.vx_m_s = 0.5 * (front_vx + rear_vx);
  twist.wz_rad_s = (front_vy - rear_vy) / (xf - xr);
  twist.vy_m_s = 0.5 * (front_vy + rear_vy) - twist.wz_rad_s * 0.5 * (xf + xr);
  return twist;
}

DualSteerWheels advance_dual_steer(const DualSteerGeometry& g, const DualSteerWheels& current,
                                   const DualSteerWheels& target, double dt_s) {
  const double max_turn_rad = g.max_steer_rate_rad_s * dt_s;
  DualSteerWheels next = target;
  next.front_steer_rad = std::clamp(target.front_steer_rad, current.front_steer_rad - max_turn_rad,
                                    current.front_steer_rad + max_turn_rad);
  next.rear_steer_rad = std::clamp(target.rear_steer_rad, current.rear_steer_rad - max_turn_rad,
                                   current.rear_steer_rad + max_turn_rad);
  // A wheel still turning drives only the part of its target velocity along where it points.
  next.front_speed_m_s *= std::max(0.0, std::cos(target.front_steer_rad - next.front_steer_rad));
  next.rear_speed_m_s *= std::max(0.0, std::cos(target.rear_steer_rad - next.rear_steer_rad));
  const double fastest_m_s =
      std::max(std::abs(next.front_speed_m_s), std::abs(next.rear_speed_m_s));
  if (fastest_m_s > g.max_wheel_speed_m_s) {
    const double scale = g.max_wheel_speed_m_s / fastest_m_s;
    next.front_speed_m_s *= scale;
    next.rear_speed_m_s *= scale;
  }
  return next;
}

}  // namespace agv::control
