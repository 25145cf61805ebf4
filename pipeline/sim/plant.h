#pragma once

#include "common/body_twist.h"
#include "common/pose2.h"
#include "common/twist_motion.h"  // integrate_twist
#include "control/drive_response.h"

namespace agv::pipeline {

// Kinematic vehicle: moves with the twist its drive makes of the commands (DriveResponse: at
// once, through a first-order actuator lag, or through dual steering wheels turning within
// their limits).
class Plant {
 public:
  using Options = control::DriveResponse::Options;

  Plant(const Pose2& start, const BodyTwist& start_twist, const Options& options)
      : pose_(start), drive_(start_twist, options) {}

  // Advances by dt_s under a command held constant over that time.
  void step(const BodyTwist& command, double dt_s) {
    drive_.step(command, dt_s, [&](double h_s, const BodyTwist& twist) {
      pose_ = integrate_twist(pose_, twist, h_s);
    });
  }

  const Pose2& pose() const { return pose_; }
  const BodyTwist& twist() const { return drive_.twist(); }  // the twist the vehicle really has
  const control::DualSteerWheels& steer_wheels() const {
    return drive_.steer_wheels();
  }  // dual steer only

 private:
  Pose2 pose_;
  control::DriveResponse drive_;
};

}  // namespace agv::pipeline
