#include "pipeline/sim/path_truth.h"

#include <cmath>

namespace agv::pipeline {

control::TrackingError PathTruth::errors(const Pose2& pose) {
  foot_ = path_.project(pose.translation(), s_m_, 0.5);
  s_m_ = foot_.s_m;
  return path_.tracking_error(pose, foot_);
}

LineMeasurement PathTruth::localisation(const Pose2& pose, double t_s) {
  const control::TrackingError e = errors(pose);
  LineMeasurement m;
  m.stamp_s = t_s;
  m.line_found = true;
  m.e_theta_rad = e.e_theta_rad;
  m.e_d_m = e.e_d_m;
  m.curvature_1_m = foot_.curvature_1_m;
  m.confidence = 1.0;
  m.lines_seen = 1;
  const Eigen::Vector2d tangent(std::cos(foot_.heading_rad), std::sin(foot_.heading_rad));
  const double past_end_m = foot_.after_end ? (pose.translation() - foot_.point).dot(tangent) : 0.0;
  m.path_remaining_m = path_.length_m() - foot_.s_m - past_end_m;
  // The path ahead, as the camera's preview gives it: the next joint where the curvature changes.
  double joint_s_m = 0.0;
  for (const control::PathSegment& segment : path_.segments()) {
    joint_s_m += segment.length_m;
    if (joint_s_m <= foot_.s_m || joint_s_m >= path_.length_m()) continue;
    const double ahead_1_m = path_.curvature_at(joint_s_m + 1e-6);
    if (std::abs(ahead_1_m - path_.curvature_at(joint_s_m - 1e-6)) < 1e-9) continue;
    m.curvature_change_m = joint_s_m - foot_.s_m;
    m.curvature_ahead_1_m = ahead_1_m;
    break;
  }
  return m;
}

}  // namespace agv::pipeline
