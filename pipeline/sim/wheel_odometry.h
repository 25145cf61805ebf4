#pragma once

#include <cstdint>
#include <random>

#include "common/pose2.h"

namespace agv::pipeline {

// What a vehicle's own wheel odometry reports: its true motion with the errors real wheels
// make (a wheel radius a little off, a heading that drifts, slip).
struct OdometryNoise {
  double scale_error = 0.0;                  // distance over-reported by this fraction
  double yaw_drift_rad_per_m = 0.0;          // heading error added per metre travelled
  double position_noise_m_per_sqrt_m = 0.0;  // random walk of the position
  double yaw_noise_rad_per_sqrt_m = 0.0;     // random walk of the heading
};

// Integrates the true motion between consecutive poses with that noise, from (0, 0, 0) at the
// first pose: a pose in the odometry's own frame, of which only changes mean anything.
// Deterministic for a seed.
class WheelOdometry {
 public:
  WheelOdometry(const OdometryNoise& noise, std::uint64_t seed);
  // The odometry pose for the vehicle's true pose now (called in time order).
  Pose2 update(const Pose2& true_pose);

 private:
  OdometryNoise noise_;
  std::mt19937_64 rng_;
  bool started_ = false;
  Pose2 last_true_;
  Pose2 odometry_;
};

}  // namespace agv::pipeline
