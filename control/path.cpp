#include "control/path.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/angles.h"

namespace agv::control {
namespace {

constexpr double kStraightCurvature_1_m = 1e-12;

Eigen::Vector2d unit(double heading_rad) { return {std::cos(heading_rad), std::sin(heading_rad)}; }
Eigen::Vector2d left_normal(double heading_rad) {
  return {-std::sin(heading_rad), std::cos(heading_rad)};
}

}  // namespace

PathSegment PathSegment::from_hermite(const HermiteCubic& curve) {
  PathSegment segment;
  segment.hermite = curve;
  segment.start = curve.p0;
  segment.start_heading_rad = std::atan2(curve.d0.y(), curve.d0.x());
  segment.curvature_1_m = curve.curvature_1_m(0.0);
  segment.hermite_s_table_m.push_back(0.0);
  for (int i = 0; i < kHermiteTableSteps; ++i) {
    segment.hermite_s_table_m.push_back(
        segment.hermite_s_table_m.back() +
        curve.length_m(static_cast<double>(i) / kHermiteTableSteps,
                       static_cast<double>(i + 1) / kHermiteTableSteps));
  }
  segment.length_m = segment.hermite_s_table_m.back();
  return segment;
}

double PathSegment::hermite_s_at(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  const int k = std::min(kHermiteTableSteps - 1, static_cast<int>(u * kHermiteTableSteps));
  return hermite_s_table_m[k] + hermite->length_m(static_cast<double>(k) / kHermiteTableSteps, u);
}

double PathSegment::hermite_u_at(double s_m) const {
  s_m = std::clamp(s_m, 0.0, length_m);
  const auto it = std::upper_bound(hermite_s_table_m.begin(), hermite_s_table_m.end(), s_m);
  const int k =
      std::clamp(static_cast<int>(it - hermite_s_table_m.begin()) - 1, 0, kHermiteTableSteps - 1);
  const double s0 = hermite_s_table_m[k], s1 = hermite_s_table_m[k + 1];
  const double u0 = static_cast<double>(k) / kHermiteTableSteps;
  const double u1 = static_cast<double>(k + 1) / kHermiteTableSteps;
  double u = s1 > s0 ? u0 + (u1 - u0) * (s_m - s0) / (s1 - s0) : u0;
  for (int i = 0; i < 3; ++i) {  // Newton on s(u) - s_m, ds/du = |P'(u)|
    const double speed = hermite->derivative(u).norm();
    if (speed < 1e-12) break;
    u = std::clamp(u - (s0 + hermite->length_m(u0, u) - s_m) / speed, u0, u1);
  }
  return u;
}

Eigen::Vector2d PathSegment::point_at(double s_m) const {
  if (hermite) return hermite->point(hermite_u_at(s_m));
  if (std::abs(curvature_1_m) < kStraightCurvature_1_m) {
    return start + s_m * unit(start_heading_rad);
  }
  const double radius_m = 1.0 / curvature_1_m;  // signed
  const Eigen::Vector2d centre = start + radius_m * left_normal(start_heading_rad);
  return centre - radius_m * left_normal(start_heading_rad + curvature_1_m * s_m);
}

double PathSegment::heading_at(double s_m) const {
  if (hermite) {
    const Eigen::Vector2d d = hermite->derivative(hermite_u_at(s_m));
    return std::atan2(d.y(), d.x());
  }
  return wrap_angle_rad(start_heading_rad + curvature_1_m * s_m);
}

double PathSegment::curvature_at(double s_m) const {
  return hermite ? hermite->curvature_1_m(hermite_u_at(s_m)) : curvature_1_m;
}

double PathSegment::closest_s(const Eigen::Vector2d& p) const {
  if (hermite) {
    // The nearest table point, then Newton on f(u) = |P(u) - p|^2 / 2.
    double best_u = 0.0, best_d2 = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= kHermiteTableSteps; ++i) {
      const double u = static_cast<double>(i) / kHermiteTableSteps;
      const double d2 = (hermite->point(u) - p).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best_u = u;
    }
    double u = best_u;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector2d r = hermite->point(u) - p, d = hermite->derivative(u);
      const double f1 = r.dot(d), f2 = d.squaredNorm() + r.dot(hermite->second_derivative(u));
      if (f2 <= 0.0) break;
      u = std::clamp(u - f1 / f2, 0.0, 1.0);
    }
    return hermite_s_at(u);
  }

  if (std::abs(curvature_1_m) < kStraightCurvature_1_m) {
    return std::clamp((p - start).dot(unit(start_heading_rad)), 0.0, length_m);
  }
  const double radius_m = 1.0 / curvature_1_m;
  const Eigen::Vector2d centre = start + radius_m * left_normal(start_heading_rad);
  const Eigen::Vector2d to_p = p - centre;
  if (to_p.norm() < 1e-12) return 0.0;  // every point of the arc is equally close
  // Angle swept from the start point to the ray through p, in the direction of travel.
  const Eigen::Vector2d to_start = start - centre;
  const double swept_rad =
      std::atan2(to_start.x() * to_p.y() - to_start.y() * to_p.x(), to_start.dot(to_p));
  double s_m = swept_rad / curvature_1_m;
  const double circumference_m = 2.0 * std::numbers::pi * std::abs(radius_m);
  if (s_m < 0.0) s_m += circumference_m;
  if (s_m <= length_m) return s_m;
  // Outside the arc: the nearer end point.
  return (p - point_at(length_m)).norm() < (p - start).norm() ? length_m : 0.0;
}

Path::Path(std::vector<PathSegment> segments) {
  for (PathSegment& segment : segments) append(std::move(segment));
  if (!segments_.empty()) {
    start_pose_ = {segments_.front().start.x(), segments_.front().start.y(),
                   segments_.front().start_heading_rad};
  }
}

Path Path::starting_at(const Pose2& start) {
  Path path;
  path.start_pose_ = start;
  return path;
}

void Path::append(PathSegment segment) {
  segment_start_s_m_.push_back(total_length_m_);
  total_length_m_ += segment.length_m;
  Geometry g;
  const double end_heading_rad = segment.end_heading_rad();
  g.along_start = unit(segment.start_heading_rad);
  g.left_start = left_normal(segment.start_heading_rad);
  g.along_end = unit(end_heading_rad);
  g.left_end = left_normal(end_heading_rad);
  g.end = segment.end();
  if (!segment.hermite && std::abs(segment.curvature_1_m) >= kStraightCurvature_1_m) {
    g.radius_m = 1.0 / std::abs(segment.curvature_1_m);
    g.centre = segment.start + (1.0 / segment.curvature_1_m) * g.left_start;
  }
  geometry_.push_back(g);
  segments_.push_back(std::move(segment));
}

std::pair<double, Eigen::Vector2d> Path::closest_on(int i, const Eigen::Vector2d& p) const {
  const PathSegment& segment = segments_[i];
  if (segment.hermite) {
    const double s_m = segment.closest_s(p);
    return {s_m, segment.point_at(s_m)};
  }
  const Geometry& g = geometry_[i];
  if (g.radius_m == 0.0) {  // a line
    const double s_m = std::clamp((p - segment.start).dot(g.along_start), 0.0, segment.length_m);
    return {s_m, segment.start + s_m * g.along_start};
  }
  // An arc: the ray from its centre through p, where it lies within the arc; else the nearer end
  // (PathSegment::closest_s, without the trigonometry of point_at).
  const Eigen::Vector2d to_p = p - g.centre;
  const double to_p_m = to_p.norm();
  if (to_p_m < 1e-12) return {0.0, segment.start};
  const Eigen::Vector2d to_start = segment.start - g.centre;
  const double swept_rad =
      std::atan2(to_start.x() * to_p.y() - to_start.y() * to_p.x(), to_start.dot(to_p));
  double s_m = swept_rad / segment.curvature_1_m;
  if (s_m < 0.0) s_m += 2.0 * std::numbers::pi * g.radius_m;
  if (s_m <= segment.length_m) return {s_m, g.centre + (g.radius_m / to_p_m) * to_p};
  return (p - g.end).norm() < (p - segment.start).norm()
             ? std::pair<double, Eigen::Vector2d>{segment.length_m, g.end}
             : std::pair<double, Eigen::Vector2d>{0.0, segment.start};
}

Pose2 Path::end_pose() const {
  if (segments_.empty()) return start_pose_;
  const PathSegment& last = segments_.back();
  return {last.end().x(), last.end().y(), last.end_heading_rad()};
}

Path& Path::add_line(double length_m) {
  assert(length_m > 0.0);
  const Pose2 end = end_pose();
  append({end.translation(), end.yaw_rad, length_m, 0.0, std::nullopt, {}});
  return *this;
}

Path& Path::add_arc(double radius_m, double angle_rad) {
  assert(radius_m > 0.0 && angle_rad != 0.0);
  const Pose2 end = end_pose();
  const double curvature_1_m = (angle_rad > 0.0 ? 1.0 : -1.0) / radius_m;
  const double length_m = radius_m * std::abs(angle_rad);
  append({end.translation(), end.yaw_rad, length_m, curvature_1_m, std::nullopt, {}});
  return *this;
}

Path& Path::add_hermite_arc(double radius_m, double angle_rad, int pieces) {
  for (const HermiteCubic& piece : hermite_arc_pieces(end_pose(), radius_m, angle_rad, pieces)) {
    append(PathSegment::from_hermite(piece));
  }
  return *this;
}

Path& Path::add_hermite_to(const Pose2& end) {
  const Pose2 start = end_pose();
  const double chord_m = (end.translation() - start.translation()).norm();
  assert(chord_m > 0.0);
  append(PathSegment::from_hermite(
      {start.translation(),
       chord_m * Eigen::Vector2d(std::cos(start.yaw_rad), std::sin(start.yaw_rad)),
       end.translation(),
       chord_m * Eigen::Vector2d(std::cos(end.yaw_rad), std::sin(end.yaw_rad))}));
  return *this;
}

int Path::segment_index_at(double s_m) const {
  assert(!segments_.empty());
  const auto it = std::upper_bound(segment_start_s_m_.begin(), segment_start_s_m_.end(), s_m);
  return std::max(0, static_cast<int>(it - segment_start_s_m_.begin()) - 1);
}

Eigen::Vector2d Path::point_at(double s_m) const {
  s_m = std::clamp(s_m, 0.0, total_length_m_);
  const int i = segment_index_at(s_m);
  return segments_[i].point_at(s_m - segment_start_s_m_[i]);
}

double Path::heading_at(double s_m) const {
  s_m = std::clamp(s_m, 0.0, total_length_m_);
  const int i = segment_index_at(s_m);
  return segments_[i].heading_at(s_m - segment_start_s_m_[i]);
}

double Path::curvature_at(double s_m) const {
  s_m = std::clamp(s_m, 0.0, total_length_m_);
  const int i = segment_index_at(s_m);
  return segments_[i].curvature_at(s_m - segment_start_s_m_[i]);
}

PathProjection Path::project(const Eigen::Vector2d& p, std::optional<double> s_hint_m,
                             double window_m) const {
  assert(!segments_.empty());
  PathProjection best;
  double best_distance_m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(segments_.size()); ++i) {
    const double s0 = segment_start_s_m_[i];
    const double s1 = s0 + segments_[i].length_m;
    if (s_hint_m && (s1 < *s_hint_m - window_m || s0 > *s_hint_m + window_m)) continue;
    const auto [local_s, foot] = closest_on(i, p);
    const double distance_m = (p - foot).norm();
    if (distance_m < best_distance_m) {
      best_distance_m = distance_m;
      best.s_m = s0 + local_s;
      best.point = foot;
      best.segment = i;
    }
  }
  if (!std::isfinite(best_distance_m)) return project(p);  // hint matched nothing: search all
  const PathSegment& segment = segments_[best.segment];
  const double local_s = best.s_m - segment_start_s_m_[best.segment];
  best.heading_rad = segment.heading_at(local_s);
  best.curvature_1_m = segment.curvature_at(local_s);
  best.distance_m = best_distance_m;
  // Left and along at the foot: cached at a line's points and at any segment's ends; an arc's
  // inner points from its centre; a Hermite piece's from its heading.
  const Geometry& g = geometry_[best.segment];
  Eigen::Vector2d left, along;
  if (segment.hermite && local_s > 0.0 && local_s < segment.length_m) {
    left = left_normal(best.heading_rad);
    along = unit(best.heading_rad);
  } else if (g.radius_m > 0.0 && local_s > 0.0 && local_s < segment.length_m) {
    const Eigen::Vector2d outward = (best.point - g.centre) / g.radius_m;
    left = segment.curvature_1_m > 0.0 ? Eigen::Vector2d(-outward) : outward;
    along = Eigen::Vector2d(left.y(), -left.x());
  } else {
    const bool at_end = local_s >= segment.length_m && segment.length_m > 0.0;
    left = at_end ? g.left_end : g.left_start;
    along = at_end ? g.along_end : g.along_start;
  }
  best.lateral_m = (p - best.point).dot(left);
  const double along_m = (p - best.point).dot(along);
  best.before_start = best.s_m <= 0.0 && along_m < 0.0;
  best.after_end = best.s_m >= total_length_m_ && along_m > 0.0;
  return best;
}

TrackingError Path::tracking_error(const Pose2& vehicle, const PathProjection& foot) const {
  return {wrap_angle_rad(vehicle.yaw_rad - foot.heading_rad), foot.lateral_m};
}

}  // namespace agv::control
