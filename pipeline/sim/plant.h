#pragma once

#include <optional>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "common/twist_motion.h"  // integrate_twist
#include "control/dual_steer_kinematics.h"

namespace agv::pipeline {

// Kinematic vehicle: integrates the twist it is commanded, optionally through a first-order
// actuator lag (the real twist approaches the command with time constant lag_s). A dual
// steering-wheel vehicle instead turns its wheels towards the command within their steer-rate,
// steer-angle and speed limits, and moves with the twist its wheels make.
class Plant {
 public:
  struct Options {
    double actuator_lag_s = 0.0;  // 0: the twist follows the command at once
    std::optional<control::DualSteerGeometry> dual_steer;
  };

  Plant(const Pose2& start, const BodyTwist& start_twist, const Options& options);

  // Advances by dt_s under a command held constant over that time.
  void step(const BodyTwist& command, double dt_s);

  const Pose2& pose() const { return pose_; }
  const BodyTwist& twist() const { return twist_; }  // the twist the vehicle really has
  const control::DualSteerWheels& steer_wheels() const { return wheels_; }  // dual steer only

 private:
  void step_dual_steer(const BodyTwist& command, double dt_s);

  Pose2 pose_;
  BodyTwist twist_;
  Options options_;
  control::DualSteerWheels wheels_;
};

}  // namespace agv::pipeline
