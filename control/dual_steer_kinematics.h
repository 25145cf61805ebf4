#pragma once

#include "common/body_twist.h"

namespace agv::control {

// Seed 002's three drive forms of a vehicle with two steerable drive wheels on its centre line.
enum class DriveForm {
  kBothSteer,       // 1: both wheels steer and drive; reference point: the platform centre
  kRearDriveFront,  // 2: the rear wheel drives (fixed straight) and is the reference point,
                    //    the front wheel steers
  kFrontDriveRear,  // 3: the front wheel drives (fixed straight) and is the reference point,
                    //    the rear wheel steers
};

struct DualSteerGeometry {
  DriveForm form = DriveForm::kBothSteer;
  double wheelbase_m = 1.0;                // distance between the two wheel centres
  double max_steer_rad = 1.5707963267949;  // steer angle range +-this (90 deg)
  double max_steer_rate_rad_s = 1.0;
  double max_wheel_speed_m_s = 1.0;  // ground speed of each wheel

  // Wheel centres on the vehicle's x axis, in the vehicle frame V (origin: reference point).
  double front_x_m() const;
  double rear_x_m() const;
  bool front_steers() const { return form != DriveForm::kFrontDriveRear; }
  bool rear_steers() const { return form != DriveForm::kRearDriveFront; }
};

// Steer angle (0: straight ahead, left positive) and signed ground speed of each wheel.
struct DualSteerWheels {
  double front_steer_rad = 0.0;
  double rear_steer_rad = 0.0;
  double front_speed_m_s = 0.0;
  double rear_speed_m_s = 0.0;
};

// Wheel states that give the body twist of the reference point: each wheel's velocity is
// (vx, vy + wz * x_wheel); a steered wheel turns to it (reversing past +-90 deg, clamped to the
// steer range), a fixed wheel drives its forward part only (its sideways part cannot be made).
DualSteerWheels dual_steer_inverse(const DualSteerGeometry& geometry, const BodyTwist& twist);

// The body twist the wheels make: least squares over the two wheels' velocity vectors (the
// rigid-body twist when they agree; a fixed wheel's reference point then has vy = 0).
BodyTwist dual_steer_forward(const DualSteerGeometry& geometry, const DualSteerWheels& wheels);

// Moves the wheels from `current` towards `target` over dt_s: steer angles at most
// max_steer_rate * dt_s, a wheel still turning driving only the part of its target velocity
// along where it points, and both speeds scaled by one factor when one exceeds the wheel
// speed limit (the ratio between them is kept).
DualSteerWheels advance_dual_steer(const DualSteerGeometry& geometry,
                                   const DualSteerWheels& current, const DualSteerWheels& target,
                                   double dt_s);

}  // namespace agv::control
