#pragma once

#include <Eigen/Core>
#include <cmath>

#include "common/angles.h"

namespace agv {

// A rigid motion of the plane (SE(2)): rotation by yaw_rad then translation.
// As a pose it places a child frame in a parent frame (e.g. the vehicle V in the world W).
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  Eigen::Vector2d translation() const { return {x_m, y_m}; }

  // The map of points given in this pose's frame into the parent frame, its rotation's cosine
  // and sine worked out once (for loops over many points).
  struct Map {
    double c, s, x_m, y_m;
    Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
      return {c * p.x() - s * p.y() + x_m, s * p.x() + c * p.y() + y_m};
    }
  };
  Map map() const { return {std::cos(yaw_rad), std::sin(yaw_rad), x_m, y_m}; }

  // Maps a point given in this pose's frame into the parent frame.
  Eigen::Vector2d transform(const Eigen::Vector2d& p) const { return map()(p); }

  // Maps a direction (no translation) from this pose's frame into the parent frame.
  Eigen::Vector2d rotate(const Eigen::Vector2d& v) const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
  }

  Pose2 inverse() const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return {-(c * x_m + s * y_m), -(-s * x_m + c * y_m), wrap_angle_rad(-yaw_rad)};
  }

  // this * other: other is given in this pose's frame.
  Pose2 compose(const Pose2& other) const {
    const Eigen::Vector2d t = transform(other.translation());
    return {t.x(), t.y(), wrap_angle_rad(yaw_rad + other.yaw_rad)};
  }
};

}  // namespace agv
