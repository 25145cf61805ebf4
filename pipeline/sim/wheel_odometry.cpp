#include "pipeline/sim/wheel_odometry.h"

#include <cmath>

namespace agv::pipeline {

WheelOdometry::WheelOdometry(const OdometryNoise& noise, std::uint64_t seed)
    : noise_(noise), rng_(seed * 0x2545F4914F6CDD1Dull + 11) {}

Pose2 WheelOdometry::update(const Pose2& true_pose) {
  if (!started_) {
    started_ = true;
    last_true_ = true_pose;
    return odometry_;
  }
  const Pose2 step = last_true_.inverse().compose(true_pose);  // in the last vehicle frame
  last_true_ = true_pose;
  const double distance_m = step.translation().norm();
  std::normal_distribution<double> unit(0.0, 1.0);
  const double root = std::sqrt(distance_m);
  Pose2 measured;
  measured.x_m = step.x_m * (1.0 + noise_.scale_error) +
                 noise_.position_noise_m_per_sqrt_m * root * unit(rng_);
  measured.y_m = step.y_m * (1.0 + noise_.scale_error) +
                 noise_.position_noise_m_per_sqrt_m * root * unit(rng_);
  measured.yaw_rad = step.yaw_rad + noise_.yaw_drift_rad_per_m * distance_m +
                     noise_.yaw_noise_rad_per_sqrt_m * root * unit(rng_);
  odometry_ = odometry_.compose(measured);
  return odometry_;
}

}  // namespace agv::pipeline
