#include "perception/line_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

namespace agv::perception {
namespace {

// Fills inliers, span and rms of `fit` for points within threshold of its line.
void score(const std::vector<Eigen::Vector2d>& points, double threshold_m, LineFit* fit) {
  const Eigen::Vector2d normal(-fit->direction.y(), fit->direction.x());
  fit->inliers.assign(points.size(), false);
  fit->inlier_count = 0;
  double sum_sq = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = 0; i < points.size(); ++i) {
    const double r = normal.dot(points[i] - fit->point);
    if (std::abs(r) > threshold_m) continue;
    fit->inliers[i] = true;
    ++fit->inlier_count;
    sum_sq += r * r;
    const double along = fit->direction.dot(points[i] - fit->point);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
  }
  fit->rms_m = fit->inlier_count > 0 ? std::sqrt(sum_sq / fit->inlier_count) : 0.0;
  fit->span_m = fit->inlier_count > 0 ? hi - lo : 0.0;
}

}  // namespace

LineFit fit_line_tls(const std::vector<Eigen::Vector2d>& points) {
  LineFit fit;
  if (points.size() < 2) return fit;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  fit.ok = true;
  fit.point = mean;
  fit.direction = solver.eigenvectors().col(1).normalized();  // largest eigenvalue
  score(points, std::numeric_limits<double>::infinity(), &fit);
  return fit;
}

LineFit fit_line_robust(const std::vector<Eigen::Vector2d>& points, double inlier_threshold_m,
                        int iterations) {
  LineFit best;
  const int n = static_cast<int>(points.size());
  if (n < 2) return best;
  cv::RNG rng(0x11e5eed);  // fixed: the same points always give the same line
  double best_cost = std::numeric_limits<double>::infinity();
  const double t2 = inlier_threshold_m * inlier_threshold_m;
  for (int it = 0; it < iterations; ++it) {
    const int a = rng.uniform(0, n);
    int b = rng.uniform(0, n - 1);
    if (b >= a) ++b;
    const Eigen::Vector2d d = points[b] - points[a];
    if (d.norm() < 1e-9) continue;
    const Eigen::Vector2d direction = d.normalized();
    const Eigen::Vector2d normal(-direction.y(), direction.x());
    double cost = 0.0;
    for (const auto& p : points) cost += std::min(std::pow(normal.dot(p - points[a]), 2), t2);
    if (cost < best_cost) {
      best_cost = cost;
      best.ok = true;
      best.point = points[a];
      best.direction = direction;
    }
  }
  if (!best.ok) return best;
  score(points, inlier_threshold_m, &best);
  for (int round = 0; round < 4; ++round) {
    std::vector<Eigen::Vector2d> inlier_points;
    for (int i = 0; i < n; ++i) {
      if (best.inliers[i]) inlier_points.push_back(points[i]);
    }
    if (inlier_points.size() < 2) break;
    LineFit refined = fit_line_tls(inlier_points);
    score(points, inlier_threshold_m, &refined);
    const bool settled = refined.inliers == best.inliers;
    best = refined;
    if (settled) break;
  }
  return best;
}

}  // namespace agv::perception
