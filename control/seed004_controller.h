#pragma once

#include <optional>

#include "control/mecanum_kinematics.h"
#include "control/path_controller.h"
#include "control/wheel_protection.h"

namespace agv::control {

// Seed 004's tracker (S2-S4) for omnidirectional vehicles: the reference pose is the foot point
// with the path's tangent heading (the printed theta_ref = atan2(y_ref, x_ref) is a typo), or
// the end pose once the vehicle is within end_hold_m of the path's end. The command is the
// reference's velocity (feed-forward: path speed along the tangent, turn rate curvature *
// speed) plus proportional feedback on the along-track, lateral and heading errors of the
// reference seen from the vehicle. On a Mecanum vehicle the command then goes through the
// inverse kinematics (S4) and the wheel-speed protection of S3.4/S3.5 (wheel_protection.h).
//
// Works on either input: from the vehicle's pose (the patent's world frame: the estimate's
// remaining_m says how far the end is, so the vehicle slows down and holds the end pose) or
// from the camera's e_theta, e_d and curvature (remaining_m infinite: the tape's end is found
// by line loss). The speed ramps down as sqrt(2 a_end remaining) near the end.
class Seed004Controller : public PathController {
 public:
  struct Options {
    double k_along_1_s = 1.0;     // feedback gain on the along-track error
    double k_lateral_1_s = 2.0;   // ... on the lateral error
    double k_heading_1_s = 2.5;   // ... on the heading error
    double end_decel_m_s2 = 0.3;  // a_end: deceleration of the speed profile before the end
    double end_hold_m = 0.02;     // within this of the end, the reference is the end pose
    std::optional<MecanumGeometry> mecanum;  // set: S3.4/S3.5 wheel protection on its wheels
    WheelLimits wheel_limits;
  };

  explicit Seed004Controller(const Options& options) : options_(options) {}

  ControllerOutput update(const TrackingEstimate& estimate, const ControlContext& context) override;
  void reset() override {}
  std::string name() const override { return "seed004_ff_p"; }

 private:
  Options options_;
};

}  // namespace agv::control
