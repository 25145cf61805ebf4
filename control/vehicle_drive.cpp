#include "control/vehicle_drive.h"

namespace agv::control {

VehicleKind kind_of(const VehicleDrive& drive) {
  return std::holds_alternative<MecanumDrive>(drive) ? VehicleKind::kMecanum
                                                     : VehicleKind::kDualSteer;
}

std::string_view name_of(VehicleKind kind) {
  return kind == VehicleKind::kMecanum ? "mecanum" : "dual_steer";
}

WheelCommand wheel_command(const VehicleDrive& drive, const BodyTwist& twist) {
  if (const auto* mecanum = std::get_if<MecanumDrive>(&drive))
    return mecanum_inverse(mecanum->geometry, twist);
  return dual_steer_inverse(std::get<DualSteerGeometry>(drive), twist);
}

double front_track_x_m(const VehicleDrive& drive) {
  if (const auto* mecanum = std::get_if<MecanumDrive>(&drive))
    return mecanum->geometry.half_wheelbase_m;
  return std::get<DualSteerGeometry>(drive).front_x_m();
}

double rear_track_x_m(const VehicleDrive& drive) {
  if (const auto* mecanum = std::get_if<MecanumDrive>(&drive))
    return -mecanum->geometry.half_wheelbase_m;
  return std::get<DualSteerGeometry>(drive).rear_x_m();
}

}  // namespace agv::control
