#include "perception/corner_fillet.h"

#include <algorithm>
#include <cmath>

#include "common/angles.h"

namespace agv::perception {

std::optional<LinesMeet> where_lines_meet(const Eigen::Vector2d& in_m, double in_heading_rad,
                                          const Eigen::Vector2d& out_m, double out_heading_rad) {
  const Eigen::Vector2d u_in(std::cos(in_heading_rad), std::sin(in_heading_rad));
  const Eigen::Vector2d u_out(std::cos(out_heading_rad), std::sin(out_heading_rad));
  // in + d_in u_in = out - d_out u_out (Cramer's rule; u_in x u_out = sin(turn)).
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  const Eigen::Vector2d between = out_m - in_m;
  const double det = cross(u_in, u_out);
  if (det == 0.0) return std::nullopt;
  return LinesMeet{cross(between, u_out) / det, cross(u_in, between) / det};
}

std::optional<CurveModel> corner_fillet(const Eigen::Vector2d& in_m, double in_heading_rad,
                                        const Eigen::Vector2d& out_m, double out_heading_rad) {
  const double turn_rad = wrap_angle_rad(out_heading_rad - in_heading_rad);
  constexpr double kLeast_rad = M_PI / 180.0;
  if (std::abs(turn_rad) < kLeast_rad || std::abs(turn_rad) > M_PI - kLeast_rad)
    return std::nullopt;
  const Eigen::Vector2d u_in(std::cos(in_heading_rad), std::sin(in_heading_rad));
  const Eigen::Vector2d u_out(std::cos(out_heading_rad), std::sin(out_heading_rad));
  // Where the lines meet: d_in ahead of the point in and d_out behind the point out.
  const std::optional<LinesMeet> meets =
      where_lines_meet(in_m, in_heading_rad, out_m, out_heading_rad);
  if (!meets) return std::nullopt;
  const double d_in = meets->d_in_m, d_out = meets->d_out_m;
  if (!(d_in > 0.0) || !(d_out > 0.0)) return std::nullopt;
  const Eigen::Vector2d meet = in_m + d_in * u_in;
  const double tangent_m = std::min(d_in, d_out);
  const double radius_m = tangent_m / std::tan(0.5 * std::abs(turn_rad));
  constexpr double kLeastRadius_m = 1e-4;  // a mitred corner's point: no arc to read
  if (!(radius_m >= kLeastRadius_m)) return std::nullopt;
  const Eigen::Vector2d start = meet - tangent_m * u_in, end = meet + tangent_m * u_out;
  const double side = turn_rad > 0.0 ? 1.0 : -1.0;  // the centre: left of a left turn
  const Eigen::Vector2d centre = start + side * radius_m * Eigen::Vector2d(-u_in.y(), u_in.x());
  // How far round the arc the origin lies from its start (signed like the turn).
  const Eigen::Vector2d from_centre = -centre, start_from_centre = start - centre;
  const double round_rad = wrap_angle_rad(std::atan2(from_centre.y(), from_centre.x()) -
                                          std::atan2(start_from_centre.y(), start_from_centre.x()));
  if (side * round_rad <= 0.0) return curve_through_point(start, in_heading_rad, 0.0);
  if (side * round_rad >= std::abs(turn_rad)) return curve_through_point(end, out_heading_rad, 0.0);
  const Eigen::Vector2d foot = centre + radius_m * from_centre.normalized();
  return curve_through_point(foot, in_heading_rad + round_rad, side / radius_m);
}

}  // namespace agv::perception
