#include "perception/mount_pose.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/angles.h"

namespace agv::perception {

Eigen::Matrix3d MountPose::rotation() const {
  return (Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

MountPose MountPose::from_rotation(const Eigen::Vector3d& xyz_m, const Eigen::Matrix3d& r) {
  // Inverse of R = Rz(yaw) Ry(pitch) Rx(roll); r(2,0) = -sin(pitch).
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  double roll = 0.0, yaw = 0.0;
  if (std::abs(std::cos(pitch)) > 1e-9) {
    roll = std::atan2(r(2, 1), r(2, 2));
    yaw = std::atan2(r(1, 0), r(0, 0));
  } else {  // gimbal lock: only roll - yaw (or roll + yaw) is defined; put it all in yaw
    yaw = std::atan2(-r(0, 1), r(1, 1));
  }
  MountPose mount;
  mount.xyz_m = xyz_m;
  mount.rpy_rad = {roll, pitch, yaw};
  return mount;
}

double MountPose::tilt_rad() const {
  const Eigen::Vector3d optical_axis = rotation().col(2);
  return std::acos(std::clamp(-optical_axis.z(), -1.0, 1.0));
}

std::string MountPose::describe() const {
  const Eigen::Matrix3d r = rotation();
  const Eigen::Vector3d axis = r.col(2);
  const Eigen::Vector3d image_up = -r.col(1);
  const double tilt_deg = rad_to_deg(tilt_rad());
  const double tilt_towards_deg = rad_to_deg(std::atan2(axis.y(), axis.x()));
  const double top_yaw_deg = rad_to_deg(std::atan2(image_up.y(), image_up.x()));
  const char* looking = tilt_deg < 1e-3  ? "looking straight down"
                        : axis.z() < 0.0 ? "looking down"
                                         : "looking up (the floor is not in view)";
  char text[320];
  std::snprintf(text, sizeof(text),
                "%.3f m ahead, %.3f m left, %.3f m up, %s, tilt %.2f deg (towards %.1f deg), "
                "image top towards %.1f deg (0 = front, 90 = left)",
                xyz_m.x(), xyz_m.y(), xyz_m.z(), looking, tilt_deg,
                tilt_deg < 1e-3 ? 0.0 : tilt_towards_deg, top_yaw_deg);
  return text;
}

}  // namespace agv::perception
