#include "control/seed004_controller.h"

#include <algorithm>
#include <cmath>

namespace agv::control {

ControllerOutput Seed004Controller::update(const TrackingEstimate& estimate,
                                           const ControlContext& context) {
  const Options& o = options_;
  const double remaining_m = estimate.remaining_m;
  const bool holding_end = remaining_m <= o.end_hold_m;
  // Feed-forward: the reference moves at path speed, slowing to reach the end at rest (S3).
  const double speed_m_s =
      holding_end ? 0.0
                  : std::min(context.path_speed_m_s,
                             std::sqrt(2.0 * o.end_decel_m_s2 * std::max(0.0, remaining_m)));
  const double turn_rad_s = holding_end ? 0.0 : estimate.curvature_1_m * speed_m_s;

  // The reference in the path frame at the foot point is (along, -e_d) with heading 0; the
  // vehicle is at (0, 0) heading e_theta. Seen from the vehicle (rotated by -e_theta):
  const double along_m = holding_end ? remaining_m : 0.0;
  const double c = std::cos(estimate.e_theta_rad), s = std::sin(estimate.e_theta_rad);
  const double error_x_m = along_m * c - estimate.e_d_m * s;
  const double error_y_m = -along_m * s - estimate.e_d_m * c;
  const double error_heading_rad = -estimate.e_theta_rad;

  ControllerOutput out;
  out.command.vx_m_s = speed_m_s * c + o.k_along_1_s * error_x_m;
  out.command.vy_m_s = -speed_m_s * s + o.k_lateral_1_s * error_y_m;
  out.command.wz_rad_s = turn_rad_s + o.k_heading_1_s * error_heading_rad;
  if (o.mecanum) {  // S4, then S3.4 and S3.5 on the wheels, back to the body twist
    const MecanumWheelSpeeds wheels = protect_wheel_speeds(
        mecanum_inverse(*o.mecanum, out.command),
        mecanum_inverse(*o.mecanum, context.previous_command), o.wheel_limits, context.ts_s);
    out.command = mecanum_forward(*o.mecanum, wheels);
  }
  return out;
}

}  // namespace agv::control
