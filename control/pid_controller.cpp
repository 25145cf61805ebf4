#include "control/pid_controller.h"

#include <algorithm>

namespace agv::control {

void PidController::reset() {
  has_previous_ = false;
  integral_e_d_m_s_ = 0.0;
  integral_e_theta_rad_s_ = 0.0;
}

ControllerOutput PidController::update(const TrackingEstimate& estimate,
                                       const ControlContext& context) {
  const double ts = context.ts_s;
  const Options& o = options_;
  integral_e_d_m_s_ += estimate.e_d_m * ts;
  integral_e_theta_rad_s_ += estimate.e_theta_rad * ts;
  if (o.ki_d_1_s2 > 0.0) {
    const double bound = o.integral_limit_m_s / o.ki_d_1_s2;
    integral_e_d_m_s_ = std::clamp(integral_e_d_m_s_, -bound, bound);
  }
  if (o.ki_theta_1_s2 > 0.0) {
    const double bound = o.integral_limit_m_s / o.ki_theta_1_s2;
    integral_e_theta_rad_s_ = std::clamp(integral_e_theta_rad_s_, -bound, bound);
  }
  const double d_e_d = has_previous_ ? (estimate.e_d_m - previous_e_d_m_) / ts : 0.0;
  const double d_e_theta =
      has_previous_ ? (estimate.e_theta_rad - previous_e_theta_rad_) / ts : 0.0;
  previous_e_d_m_ = estimate.e_d_m;
  previous_e_theta_rad_ = estimate.e_theta_rad;
  has_previous_ = true;

  ControllerOutput out;
  out.command.vx_m_s = context.path_speed_m_s;
  out.command.vy_m_s =
      -(o.kp_d_1_s * estimate.e_d_m + o.ki_d_1_s2 * integral_e_d_m_s_ + o.kd_d * d_e_d);
  out.command.wz_rad_s = -(o.kp_theta_1_s * estimate.e_theta_rad +
                           o.ki_theta_1_s2 * integral_e_theta_rad_s_ + o.kd_theta * d_e_theta) +
                         estimate.curvature_1_m * context.path_speed_m_s;
  return out;
}

}  // namespace agv::control
