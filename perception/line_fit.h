#pragma once

#include <Eigen/Core>
#include <vector>

namespace agv::perception {

struct LineFit {
  bool ok = false;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();       // centroid of the inliers
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // unit
  std::vector<bool> inliers;
  int inlier_count = 0;
  double rms_m = 0.0;   // orthogonal residual RMS of the inliers
  double span_m = 0.0;  // extent of the inliers along the line
};

// Orthogonal (total least squares) line through points.
LineFit fit_line_tls(const std::vector<Eigen::Vector2d>& points);

// Robust line: RANSAC on pairs (deterministic sample order) scored by the truncated quadratic
// loss (MSAC), then total least squares on the inliers, repeated until the inlier set settles.
// Points farther than inlier_threshold_m from the line are outliers.
LineFit fit_line_robust(const std::vector<Eigen::Vector2d>& points, double inlier_threshold_m,
                        int iterations);

}  // namespace agv::perception
