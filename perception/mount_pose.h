#pragma once

#include <Eigen/Core>
#include <string>

namespace agv::perception {

// Pose of the camera C in the vehicle frame V (shared/DESIGN.md): position of the optical
// centre, and R_VC = Rz(yaw) * Ry(pitch) * Rx(roll), whose columns are the camera's x, y, z
// axes written in V. Straight down, image top towards the front: rpy = (pi, 0, -pi/2).
struct MountPose {
  Eigen::Vector3d xyz_m = Eigen::Vector3d(0.30, 0.0, 0.15);
  Eigen::Vector3d rpy_rad = Eigen::Vector3d(3.14159265358979323846, 0.0, -1.57079632679489661923);

  Eigen::Matrix3d rotation() const;
  static MountPose from_rotation(const Eigen::Vector3d& xyz_m, const Eigen::Matrix3d& r_vc);

  // Angle between the optical axis and straight down.
  double tilt_rad() const;
  // "0.300 m ahead, 0.000 m left, 0.150 m up, looking down, tilt 0.0 deg, image top towards
  // the front (yaw 0.0 deg)".
  std::string describe() const;
};

}  // namespace agv::perception
