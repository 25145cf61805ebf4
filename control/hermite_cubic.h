#pragma once

#include <Eigen/Core>
#include <vector>

#include "common/pose2.h"

namespace agv::control {

// A cubic Hermite curve P(u), u in [0, 1], with P(0) = p0, P(1) = p1, P'(0) = d0, P'(1) = d1
// (seed 004 S1: the coefficients are T^-1 * beta, here written with the Hermite basis).
struct HermiteCubic {
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero();
  Eigen::Vector2d d0 = Eigen::Vector2d::UnitX();
  Eigen::Vector2d p1 = Eigen::Vector2d::UnitX();
  Eigen::Vector2d d1 = Eigen::Vector2d::UnitX();

  Eigen::Vector2d point(double u) const;
  Eigen::Vector2d derivative(double u) const;         // dP/du
  Eigen::Vector2d second_derivative(double u) const;  // d2P/du2
  // Signed curvature at u (left turn positive), 1/m.
  double curvature_1_m(double u) const;
  // Arc length from u0 to u1 (u0 <= u1), by 5-point Gauss-Legendre quadrature.
  double length_m(double u0, double u1) const;
};

// Seed 004 S1: the arc that starts at `start` (position and tangent heading), has radius
// radius_m and turns by angle_rad (> 0 left), split into `pieces` equal parts, each a cubic
// Hermite piece matching position and first derivative of the exact arc at both ends
// (dP/du = radius * piece angle along the tangent).
std::vector<HermiteCubic> hermite_arc_pieces(const Pose2& start, double radius_m, double angle_rad,
                                             int pieces);

// Upper bound on the distance between a piece of hermite_arc_pieces and the exact arc at the
// same parameter: r * theta^4 / 384 for a piece of angle theta (the Hermite interpolation error
// |P(u) - H(u)| <= max|P''''| / 4! * u^2 (1 - u)^2, with |P''''| = r theta^4 and
// max u^2 (1 - u)^2 = 1/16).
double hermite_arc_deviation_bound_m(double radius_m, double piece_angle_rad);

}  // namespace agv::control
