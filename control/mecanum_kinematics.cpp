#include "control/mecanum_kinematics.h"

namespace agv::control {

MecanumWheelSpeeds mecanum_inverse(const MecanumGeometry& geometry, const BodyTwist& twist) {
  const double k = geometry.half_wheelbase_m + geometry.half_track_m;
  const double r = geometry.wheel_radius_m;
  return MecanumWheelSpeeds{(twist.vx_m_s - twist.vy_m_s - k * twist.wz_rad_s) / r,
                            (twist.vx_m_s + twist.vy_m_s + k * twist.wz_rad_s) / r,
                            (twist.vx_m_s + twist.vy_m_s - k * twist.wz_rad_s) / r,
                            (twist.vx_m_s - twist.vy_m_s + k * twist.wz_rad_s) / r};
}

BodyTwist mecanum_forward(const MecanumGeometry& geometry, const MecanumWheelSpeeds& w) {
  const double k = geometry.half_wheelbase_m + geometry.half_track_m;
  const double r = geometry.wheel_radius_m;
  return {r / 4.0 * (w[0] + w[1] + w[2] + w[3]), r / 4.0 * (-w[0] + w[1] + w[2] - w[3]),
          r / (4.0 * k) * (-w[0] + w[1] - w[2] + w[3])};
}

}  // namespace agv::control
