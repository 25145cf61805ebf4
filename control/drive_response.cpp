#include "control/drive_response.h"

#include <algorithm>
#include <cmath>

namespace agv::control {

DriveResponse::DriveResponse(const BodyTwist& start_twist, const Options& options)
    : twist_(start_twist), options_(options) {
  if (options_.dual_steer) {
    wheels_ = dual_steer_inverse(*options_.dual_steer, start_twist);
    twist_ = dual_steer_forward(*options_.dual_steer, wheels_);
  }
}

double DriveResponse::half_response_s(const BodyTwist& from, const BodyTwist& to) const {
  if (!options_.dual_steer) return options_.actuator_lag_s;
  const DualSteerGeometry& geometry = *options_.dual_steer;
  const DualSteerWheels a = dual_steer_inverse(geometry, from),
                        b = dual_steer_inverse(geometry, to);
  double turn_rad = 0.0;
  if (geometry.front_steers()) turn_rad = std::abs(b.front_steer_rad - a.front_steer_rad);
  if (geometry.rear_steers())
    turn_rad = std::max(turn_rad, std::abs(b.rear_steer_rad - a.rear_steer_rad));
  return 0.5 * turn_rad / geometry.max_steer_rate_rad_s;
}

}  // namespace agv::control
