#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace agv::perception {

// A guide line near the vehicle as a circular arc (a straight line when curvature is 0), given
// by what a controller wants to know about it, in the vehicle frame V (DESIGN.md):
//   e_d_m          signed distance of the vehicle origin from the curve (positive: the vehicle
//                  is on the curve's left, seen along its direction),
//   heading_rad    direction of the curve at the foot point F of the origin (its yaw in V,
//                  so e_theta = -heading_rad),
//   curvature_1_m  signed curvature (positive: the curve turns left).
// F = -e_d n, n = (-sin heading, cos heading). The parametrisation has no singularity at zero
// curvature, so one model serves lines and arcs.
struct CurveModel {
  double e_d_m = 0.0;
  double heading_rad = 0.0;
  double curvature_1_m = 0.0;

  Eigen::Vector2d foot_point() const;
  Eigen::Vector2d tangent() const;  // unit, at the foot point
  Eigen::Vector2d normal() const;   // unit, left of the tangent
  // Signed distance of p from the curve, positive on its left:
  //   d = (2u - k r^2) / (1 + sqrt(1 - 2ku + k^2 r^2)),  q = p - F, u = q . n, r = |q|,
  // which is exactly (1/k) - sign(k) |p - centre| and tends to u as k -> 0.
  double signed_distance(const Eigen::Vector2d& p) const;
  // Arc length from the foot point to the point of the curve nearest p (along the tangent
  // direction; for a line, the projection on it).
  double arc_position(const Eigen::Vector2d& p) const;
  // Point of the curve at arc length s from the foot point.
  Eigen::Vector2d point_at(double s_m) const;
  // Unit direction of the curve there: the tangent at the foot point turned by curvature x s.
  Eigen::Vector2d tangent_at(double s_m) const;
  // The same curve travelled the other way.
  CurveModel reversed() const;
  // This curve, reversed where needed to run the way `reference` runs, compared where each
  // passes nearest `where` (put it where both are seen: away from that, a tight curve's direction,
  // at the origin's foot point say, may point either way).
  CurveModel oriented_like(const CurveModel& reference, const Eigen::Vector2d& where) const;

  // The model with its foot point and directions computed once, for loops over many points.
  struct Prepared {
    Eigen::Vector2d foot, tangent, normal;
    double curvature_1_m;
    double e_d_m;
    // CurveModel::arc_position, the heading's trigonometry done once.
    double arc_position(const Eigen::Vector2d& p) const {
      const Eigen::Vector2d q = p - foot;
      const double along = q.dot(tangent);
      const double k = curvature_1_m;
      if (std::abs(k) < 1e-9) return along;
      // Angle swept around the centre from the foot point to the ray through p.
      const double across = q.dot(normal);
      const double swept = std::atan2(k * along, 1.0 - k * across);
      return swept / k;
    }
    // arc_position, the turn of an arc counted from near_s_m rather than from the point opposite
    // the foot: within half a turn of near_s_m (evidence that straddles that opposite point, half
    // a turn round a tight arc from the origin's foot, keeps its positions together).
    double arc_position_near(const Eigen::Vector2d& p, double near_s_m) const {
      const double s = arc_position(p);
      if (std::abs(curvature_1_m) < 1e-9) return s;
      return near_s_m + std::remainder(s - near_s_m, 2.0 * M_PI / std::abs(curvature_1_m));
    }
    // The curve's direction at arc_position(p), not of unit length (tangent_at without the
    // trigonometry): the tangent at the foot turned by the angle swept, whose cosine and sine
    // are (1 - k p.n, k p.t) over their length.
    Eigen::Vector2d direction_at(const Eigen::Vector2d& p) const {
      const Eigen::Vector2d q = p - foot;
      const double k = curvature_1_m;
      if (std::abs(k) < 1e-9) return tangent;
      return (1.0 - k * q.dot(normal)) * tangent + (k * q.dot(tangent)) * normal;
    }
    // tangent_at(arc_position(p)) without the trigonometry (an arc tangent and a sine and cosine
    // per point: a tenth of a tracked frame's time, for the chords' widths): direction_at of unit
    // length; the tangent itself on a straight line.
    Eigen::Vector2d unit_direction_at(const Eigen::Vector2d& p) const {
      if (std::abs(curvature_1_m) < 1e-9) return tangent;
      return direction_at(p).normalized();
    }
    // A key that orders points as arc_position does, at a fraction of its cost (no arc
    // tangent): for an arc, the pseudo-angle of the same (y, x) = (k along, 1 - k across),
    // increasing with atan2(y, x) over (-pi, pi] (the side of y's sign as atan2 takes it),
    // divided by k. For sorting by arc position.
    double arc_order_key(const Eigen::Vector2d& p) const {
      const Eigen::Vector2d q = p - foot;
      const double along = q.dot(tangent);
      const double k = curvature_1_m;
      if (std::abs(k) < 1e-9) return along;
      const double y = k * along, x = 1.0 - k * q.dot(normal);
      const double r = std::abs(x) + std::abs(y);
      if (r == 0.0) return 0.0;
      const double pseudo = x >= 0.0 ? y / r : (std::signbit(y) ? -2.0 : 2.0) - y / r;
      return pseudo / k;
    }
    double signed_distance(double px, double py) const {
      const double qx = px - foot.x(), qy = py - foot.y();
      const double u = qx * normal.x() + qy * normal.y();
      const double r2 = qx * qx + qy * qy;
      const double k = curvature_1_m;
      const double root = std::sqrt(std::max(0.0, 1.0 - 2.0 * k * u + k * k * r2));
      return (2.0 * u - k * r2) / (1.0 + root);
    }
    double signed_distance(const Eigen::Vector2d& p) const { return signed_distance(p.x(), p.y()); }
    // The same, with its gradient with respect to (e_d, heading, curvature). With u = p.n + e_d,
    // r^2 = |p|^2 + 2 e_d p.n + e_d^2, A = 2u - k r^2, S = sqrt(1 - 2ku + k^2 r^2), d = A / (1 +
    // S):
    //   du/de_d = 1, dr2/de_d = 2u;   du/dh = -p.t, dr2/dh = -2 e_d p.t;   dA/dk = -r^2,
    //   dS/dk = (k r^2 - u) / S;  for e_d and h: dA = 2 du - k dr2, dS = (-2k du + k^2 dr2) / (2S);
    //   dd = (dA - d dS) / (1 + S)  (the divisions by S and 1 + S done once).
    double signed_distance(double px, double py, double* d_e_d, double* d_heading,
                           double* d_curvature) const {
      const double pn = px * normal.x() + py * normal.y();
      const double pt = px * tangent.x() + py * tangent.y();
      const double k = curvature_1_m;
      const double u = pn + e_d_m;
      const double r2 = px * px + py * py + 2.0 * e_d_m * pn + e_d_m * e_d_m;
      const double a = 2.0 * u - k * r2;
      const double s = std::sqrt(std::max(1e-12, 1.0 - 2.0 * k * u + k * k * r2));
      const double inverse_b = 1.0 / (1.0 + s), inverse_s = 1.0 / s;
      const double d = a * inverse_b;
      auto derivative = [&](double du, double dr2) {
        const double da = 2.0 * du - k * dr2;
        const double ds = 0.5 * (-2.0 * k * du + k * k * dr2) * inverse_s;
        return (da - d * ds) * inverse_b;
      };
      *d_e_d = derivative(1.0, 2.0 * u);
      *d_heading = derivative(-pt, -2.0 * e_d_m * pt);
      *d_curvature = (-r2 - d * (k * r2 - u) * inverse_s) * inverse_b;
      return d;
    }
    double signed_distance(const Eigen::Vector2d& p, Eigen::Vector3d* gradient) const {
      return signed_distance(p.x(), p.y(), &(*gradient)[0], &(*gradient)[1], &(*gradient)[2]);
    }
  };
  Prepared prepared() const { return {foot_point(), tangent(), normal(), curvature_1_m, e_d_m}; }
};

struct CurveFit {
  bool ok = false;
  CurveModel model;
  std::vector<bool> inliers;               // per point: it (or one of its edges) fits
  std::vector<std::uint8_t> edge_inliers;  // with edges: bit 0 first edge fits, bit 1 second
  int inlier_count = 0;
  double rms_m = 0.0;                // robust residual scale of the inliers (1.4826 x median |r|)
  double curvature_sigma_1_m = 0.0;  // standard deviation of the curvature from the fit
  double s_min_m = 0.0, s_max_m = 0.0;  // extent of the inliers along the curve
  bool is_line = true;                  // curvature not significant: fitted as a straight line
};

struct CurveFitOptions {
  double inlier_threshold_m = 0.0015;
  int ransac_iterations = 120;
  double curvature_significance = 3.0;  // keep a curvature only beyond this many sigmas
  double max_curvature_1_m = 10.0;      // arcs tighter than 0.1 m radius are not tape paths
  // Orientation of the result: the curve's direction at the inliers has a positive component
  // along this vector (vehicle frame; default: forward).
  Eigen::Vector2d forward = Eigen::Vector2d::UnitX();
};

// The two edges of chords across a tape, for fits on edges: point i of `first` lies at signed
// distance first_offset_m[i] from the centre curve (+ half the width on its left, - on its
// right), and likewise for `second`. The sides come from a first fit on the midpoints; fixing
// them keeps an edge from being explained by a curve on its wrong side. A NaN offset leaves
// that edge out.
struct EdgeObservations {
  const std::vector<Eigen::Vector2d>* first;
  const std::vector<Eigen::Vector2d>* second;
  const std::vector<double>* first_offset_m;
  const std::vector<double>* second_offset_m;
};

// Robust fit of one curve to points (vehicle frame, metres): RANSAC on three-point circles and
// two-point lines through the points, scored by the truncated quadratic loss, then Gauss-Newton
// (Cauchy weights), the inlier set re-taken until it settles. With `edges`, hypotheses still come
// from the points (chord midpoints) but are scored and refined on the edges, each at half the
// width from the curve: where a chord crosses a fork or a worn edge, its one good edge still
// counts and the other is an outlier. `mask` (optional) marks the points that may be used.
// `initial` (optional) replaces the RANSAC hypotheses: a model known to be near (tracking).
CurveFit fit_curve_robust(const std::vector<Eigen::Vector2d>& points,
                          const CurveFitOptions& options, const std::vector<bool>* mask = nullptr,
                          const EdgeObservations* edges = nullptr,
                          const CurveModel* initial = nullptr);

// The curve through three points (a line when they are collinear), oriented along `forward`.
std::optional<CurveModel> curve_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                        const Eigen::Vector2d& c, const Eigen::Vector2d& forward);

// The curve through point p0 with direction heading0 and curvature k (all in the vehicle frame),
// as the model of the vehicle origin's foot point on it (CurveModel's parametrisation).
CurveModel curve_through_point(const Eigen::Vector2d& p0, double heading0, double k);

// The curve y(x) = offset + slope x + second x^2 / 2 near x = 0, in a frame turned by frame_rad
// about the vehicle origin, as its model at the origin (the curvature y'' / (1 + y'^2)^1.5).
CurveModel curve_in_frame(double frame_rad, double offset_m, double slope, double second_1_m);

}  // namespace agv::perception
