#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "common/body_twist.h"
#include "control/dual_steer_kinematics.h"

namespace agv::control {

// How a vehicle's twist follows the twist it is commanded: at once; through a first-order
// actuator lag (the twist approaches the command with time constant actuator_lag_s); or, for a
// dual steering-wheel vehicle, through wheels that turn towards the command within their
// steer-rate, steer-angle and speed limits (the twist is what the wheels make). The simulated
// plant moves with it, and the line tracker predicts with it where the vehicle has gone since a
// frame was taken (what a command does is not what the vehicle does while its wheels still turn).
class DriveResponse {
 public:
  struct Options {
    double actuator_lag_s = 0.0;  // 0: the twist follows the command at once
    std::optional<DualSteerGeometry> dual_steer;
  };

  DriveResponse(const BodyTwist& start_twist, const Options& options);

  // Advances by dt_s under a command held constant over that time, in sub-steps; calls
  // move(h_s, twist) for each with the twist the vehicle moves with over it (its mean).
  template <typename Move>
  void step(const BodyTwist& command, double dt_s, Move&& move);

  const BodyTwist& twist() const { return twist_; }                // the twist the vehicle has now
  const DualSteerWheels& steer_wheels() const { return wheels_; }  // dual steer only
  // Whether the twist follows the command at once (each step is one move with the command).
  bool immediate() const { return !options_.dual_steer && options_.actuator_lag_s <= 0.0; }
  // How long after a command changes from `from` to `to` the vehicle moves as half way there: a
  // lag's time constant; half the time the steered wheels take to turn from one to the other at
  // their steer rate; 0 at once.
  double half_response_s(const BodyTwist& from, const BodyTwist& to) const;

 private:
  BodyTwist twist_;
  Options options_;
  DualSteerWheels wheels_;
};

template <typename Move>
void DriveResponse::step(const BodyTwist& command, double dt_s, Move&& move) {
  if (options_.dual_steer) {
    const DualSteerGeometry& geometry = *options_.dual_steer;
    const DualSteerWheels target = dual_steer_inverse(geometry, command);
    const int substeps = std::max(1, static_cast<int>(std::ceil(dt_s / 0.005)));
    const double h = dt_s / substeps;
    for (int i = 0; i < substeps; ++i) {
      wheels_ = advance_dual_steer(geometry, wheels_, target, h);
      twist_ = dual_steer_forward(geometry, wheels_);
      move(h, twist_);
    }
    return;
  }
  if (options_.actuator_lag_s <= 0.0) {
    twist_ = command;
    move(dt_s, twist_);
    return;
  }
  // Exact first-order response per sub-step; the move is the sub-step's mean twist.
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
    move(h, mean);
  }
}

}  // namespace agv::control
