#include "pipeline/sim/plant.h"

#include <algorithm>
#include <cmath>

namespace agv::pipeline {

Plant::Plant(const Pose2& start, const BodyTwist& start_twist, const Options& options)
    : pose_(start), twist_(start_twist), options_(options) {
  if (options_.dual_steer) {
    wheels_ = control::dual_steer_inverse(*options_.dual_steer, start_twist);
    twist_ = control::dual_steer_forward(*options_.dual_steer, wheels_);
  }
}

void Plant::step_dual_steer(const BodyTwist& command, double dt_s) {
  const control::DualSteerGeometry& geometry = *options_.dual_steer;
  const control::DualSteerWheels target = control::dual_steer_inverse(geometry, command);
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt_s / 0.005)));
  const double h = dt_s / substeps;
  for (int i = 0; i < substeps; ++i) {
    wheels_ = control::advance_dual_steer(geometry, wheels_, target, h);
    twist_ = control::dual_steer_forward(geometry, wheels_);
    pose_ = integrate_twist(pose_, twist_, h);
  }
}

void Plant::step(const BodyTwist& command, double dt_s) {
  if (options_.dual_steer) {
    step_dual_steer(command, dt_s);
    return;
  }
  if (options_.actuator_lag_s <= 0.0) {
    twist_ = command;
    pose_ = integrate_twist(pose_, twist_, dt_s);
    return;
  }
  // Exact first-order response per sub-step; the pose integrates the sub-step's mean twist.
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt_s / 0.002)));
  const double h = dt_s / substeps;
  const double decay = std::exp(-h / options_.actuator_lag_s);
  const double mean_gain = 1.0 - options_.actuator_lag_s / h * (1.0 - decay);
  for (int i = 0; i < substeps; ++i) {
    auto advance = [&](double& state, double target) {
      const double mean = target + (state - target) * (1.0 - mean_gain);
      state = target + (state - target) * decay;
      return mean;
    };
    BodyTwist mean;
    mean.vx_m_s = advance(twist_.vx_m_s, command.vx_m_s);
    mean.vy_m_s = advance(twist_.vy_m_s, command.vy_m_s);
    mean.wz_rad_s = advance(twist_.wz_rad_s, command.wz_rad_s);
    pose_ = integrate_twist(pose_, mean, h);
  }
}

}  // namespace agv::pipeline
