#pragma once

#include <Eigen/Core>

#include "common/body_twist.h"

namespace agv::control {

// Wheel angular speeds of a four-wheel Mecanum platform (45 deg rollers, "X" pattern seen from
// above), in the order front-left, front-right, rear-left, rear-right; positive rolls the
// vehicle forward. Frame convention of shared/DESIGN.md (x forward, y left, yaw CCW).
using MecanumWheelSpeeds = Eigen::Vector4d;

struct MecanumGeometry {
  double wheel_radius_m = 0.05;
  double half_wheelbase_m = 0.20;  // L1: half the distance between front and rear axles
  double half_track_m = 0.20;      // L2: half the distance between left and right wheels
};

// Seed 000 eq. 1 in this project's frame:
//   w_fl = (vx - vy - (L1+L2) wz) / r     w_fr = (vx + vy + (L1+L2) wz) / r
//   w_rl = (vx + vy - (L1+L2) wz) / r     w_rr = (vx - vy + (L1+L2) wz) / r
MecanumWheelSpeeds mecanum_inverse(const MecanumGeometry& geometry, const BodyTwist& twist);

// The pseudo-inverse of eq. 1 (the printed eq. 2 is garbled): least-squares twist from four
// wheel speeds; exact when the speeds are consistent.
BodyTwist mecanum_forward(const MecanumGeometry& geometry, const MecanumWheelSpeeds& wheels);

}  // namespace agv::control
