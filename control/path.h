#pragma once

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "common/pose2.h"
#include "control/hermite_cubic.h"

namespace agv::control {

// One piece of a path: a straight line (curvature 0), a circular arc of constant signed
// curvature (left turn positive), starting at `start` with tangent heading `start_heading_rad`,
// or a cubic Hermite piece (`hermite` set; curvature_1_m then holds its curvature at the start).
struct PathSegment {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  double start_heading_rad = 0.0;
  double length_m = 0.0;
  double curvature_1_m = 0.0;
  std::optional<HermiteCubic> hermite;
  std::vector<double> hermite_s_table_m;  // arc length at u = i / kHermiteTableSteps

  static constexpr int kHermiteTableSteps = 64;
  static PathSegment from_hermite(const HermiteCubic& curve);

  Eigen::Vector2d point_at(double s_m) const;
  double heading_at(double s_m) const;
  double curvature_at(double s_m) const;
  Eigen::Vector2d end() const { return point_at(length_m); }
  double end_heading_rad() const { return heading_at(length_m); }
  // Arc length (clamped to [0, length]) of the closest point of this segment to p.
  double closest_s(const Eigen::Vector2d& p) const;

 private:
  double hermite_u_at(double s_m) const;  // Hermite parameter at arc length s_m
  double hermite_s_at(double u) const;    // arc length at Hermite parameter u
};

// Foot point of a query point on the path: where, which way the path goes there, and the
// signed lateral offset of the query point (positive: left of the path, seen along travel).
struct PathProjection {
  double s_m = 0.0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;
  double curvature_1_m = 0.0;
  double lateral_m = 0.0;
  double distance_m = 0.0;  // unsigned distance to the foot point
  int segment = 0;
  bool before_start = false;  // the foot point is the start point and p lies behind it
  bool after_end = false;     // the foot point is the end point and p lies past it
};

// Heading and lateral error of a vehicle pose at its foot point, as DESIGN.md defines them.
struct TrackingError {
  double e_theta_rad = 0.0;
  double e_d_m = 0.0;
};

// A guide path: a chain of segments joined end to start, directed along the travel direction.
class Path {
 public:
  Path() = default;
  explicit Path(std::vector<PathSegment> segments);

  // Builder helpers: each appends a piece that starts where the path ends now.
  static Path starting_at(const Pose2& start);
  Path& add_line(double length_m);
  Path& add_arc(double radius_m, double angle_rad);  // angle > 0 turns left
  // Seed 004 S1: the same arc as add_arc, as `pieces` cubic Hermite pieces.
  Path& add_hermite_arc(double radius_m, double angle_rad, int pieces);
  // A cubic Hermite piece to `end` (position and tangent heading); the tangent vectors at both
  // ends have the length of the chord. The chord must not be zero.
  Path& add_hermite_to(const Pose2& end);
  Pose2 end_pose() const;

  const std::vector<PathSegment>& segments() const { return segments_; }
  double length_m() const { return total_length_m_; }
  bool empty() const { return segments_.empty(); }

  Eigen::Vector2d point_at(double s_m) const;
  double heading_at(double s_m) const;
  double curvature_at(double s_m) const;

  // Closest point on the path. With s_hint_m, only pieces within window_m of arc length of the
  // hint are searched, so that a path that passes near itself does not make the foot jump.
  PathProjection project(const Eigen::Vector2d& p, std::optional<double> s_hint_m = std::nullopt,
                         double window_m = 1.0) const;

  TrackingError tracking_error(const Pose2& vehicle, const PathProjection& foot) const;

 private:
  // What project() needs of a line or an arc without trigonometry, computed once per segment:
  // unit vectors along and to the left at both ends, the end point, an arc's centre and radius.
  struct Geometry {
    Eigen::Vector2d along_start = Eigen::Vector2d::Zero(), left_start = Eigen::Vector2d::Zero();
    Eigen::Vector2d along_end = Eigen::Vector2d::Zero(), left_end = Eigen::Vector2d::Zero();
    Eigen::Vector2d end = Eigen::Vector2d::Zero(), centre = Eigen::Vector2d::Zero();
    double radius_m = 0.0;
  };
  // The nearest point of segment i to p: arc length on the segment and the point.
  std::pair<double, Eigen::Vector2d> closest_on(int i, const Eigen::Vector2d& p) const;
  int segment_index_at(double s_m) const;
  void append(PathSegment segment);

  std::vector<PathSegment> segments_;
  std::vector<Geometry> geometry_;  // one per segment
  std::vector<double> segment_start_s_m_;
  double total_length_m_ = 0.0;
  Pose2 start_pose_;
};

}  // namespace agv::control
