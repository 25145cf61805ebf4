#include "control/hermite_cubic.h"

#include <array>
#include <cassert>
#include <cmath>

namespace agv::control {

Eigen::Vector2d HermiteCubic::point(double u) const {
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * d0 + (-2 * u3 + 3 * u2) * p1 +
         (u3 - u2) * d1;
}

Eigen::Vector2d HermiteCubic::derivative(double u) const {
  const double u2 = u * u;
  return (6 * u2 - 6 * u) * p0 + (3 * u2 - 4 * u + 1) * d0 + (-6 * u2 + 6 * u) * p1 +
         (3 * u2 - 2 * u) * d1;
}

Eigen::Vector2d HermiteCubic::second_derivative(double u) const {
  return (12 * u - 6) * p0 + (6 * u - 4) * d0 + (-12 * u + 6) * p1 + (6 * u - 2) * d1;
}

double HermiteCubic::curvature_1_m(double u) const {
  const Eigen::Vector2d d = derivative(u), dd = second_derivative(u);
  const double speed = d.norm();
  if (speed < 1e-12) return 0.0;
  return (d.x() * dd.y() - d.y() * dd.x()) / (speed * speed * speed);
}

double HermiteCubic::length_m(double u0, double u1) const {
  assert(u0 <= u1);
  static constexpr std::array<double, 5> kNodes = {0.0, -0.5384693101056831, 0.5384693101056831,
                                                   -0.9061798459386640, 0.9061798459386640};
  static constexpr std::array<double, 5> kWeights = {0.5688888888888889, 0.4786286704993665,
                                                     0.4786286704993665, 0.2369268850561891,
                                                     0.2369268850561891};
  const double half = 0.5 * (u1 - u0), mid = 0.5 * (u0 + u1);
  double sum = 0.0;
  for (int i = 0; i < 5; ++i) sum += kWeights[i] * derivative(mid + half * kNodes[i]).norm();
  return half * sum;
}

std::vector<HermiteCubic> hermite_arc_pieces(const Pose2& start, double radius_m, double angle_rad,
                                             int pieces) {
  assert(radius_m > 0.0 && angle_rad != 0.0 && pieces >= 1);
  const double sign = angle_rad > 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d centre =
      start.translation() +
      sign * radius_m * Eigen::Vector2d(-std::sin(start.yaw_rad), std::cos(start.yaw_rad));
  const double piece_rad = angle_rad / pieces;
  // Point and tangent of the exact arc after turning by `turned_rad`.
  auto arc_point = [&](double turned_rad) {
    const double h = start.yaw_rad + turned_rad;
    return Eigen::Vector2d(centre - sign * radius_m * Eigen::Vector2d(-std::sin(h), std::cos(h)));
  };
  auto arc_derivative = [&](double turned_rad) {
    const double h = start.yaw_rad + turned_rad;
    return Eigen::Vector2d(radius_m * std::abs(piece_rad) *
                           Eigen::Vector2d(std::cos(h), std::sin(h)));
  };
  std::vector<HermiteCubic> out;
  for (int i = 0; i < pieces; ++i) {
    out.push_back({arc_point(i * piece_rad), arc_derivative(i * piece_rad),
                   arc_point((i + 1) * piece_rad), arc_derivative((i + 1) * piece_rad)});
  }
  return out;
}

double hermite_arc_deviation_bound_m(double radius_m, double piece_angle_rad) {
  return radius_m * std::pow(piece_angle_rad, 4) / 384.0;
}

}  // namespace agv::control
