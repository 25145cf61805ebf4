#pragma once

#include <string_view>
#include <variant>

#include "common/body_twist.h"
#include "control/dual_steer_kinematics.h"
#include "control/mecanum_kinematics.h"
#include "control/wheel_protection.h"

namespace agv::control {

enum class VehicleKind { kMecanum, kDualSteer };

// A Mecanum vehicle's drive: its geometry and what seed 004's wheel protection keeps to.
struct MecanumDrive {
  MecanumGeometry geometry;
  WheelLimits wheel_limits;
};

// How a vehicle moves: one struct per kind, so that a vehicle carries only its own settings.
using VehicleDrive = std::variant<MecanumDrive, DualSteerGeometry>;

// What the wheels of a drive are told for a body twist: four Mecanum wheel speeds, or two
// steer angles and wheel speeds.
using WheelCommand = std::variant<MecanumWheelSpeeds, DualSteerWheels>;

VehicleKind kind_of(const VehicleDrive& drive);
std::string_view name_of(VehicleKind kind);  // "mecanum" | "dual_steer" (scenario words)

// The wheel command (inverse kinematics) of a body twist for this drive.
WheelCommand wheel_command(const VehicleDrive& drive, const BodyTwist& twist);

// The wheel centres on the vehicle's centre line whose tracks make seed 002's coverage area,
// x in the vehicle frame: the dual steering wheels, or a Mecanum vehicle's axle centres.
double front_track_x_m(const VehicleDrive& drive);
double rear_track_x_m(const VehicleDrive& drive);

}  // namespace agv::control
