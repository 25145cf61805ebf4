#pragma once

namespace agv {

// Velocity of the vehicle reference point in the vehicle frame V (x forward, y left),
// and its yaw rate (counter-clockwise positive).
struct BodyTwist {
  double vx_m_s = 0.0;
  double vy_m_s = 0.0;
  double wz_rad_s = 0.0;
};

}  // namespace agv
