#include "perception/path_memory.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>

#include "common/angles.h"
#include "perception/corner_fillet.h"
#include "perception/joined_arcs_fit.h"
#include "perception/point_grid.h"

namespace agv::perception {

namespace {

// How far from singular a symmetric positive matrix is, free of its scale: |det| / (largest
// column sum)^n, 0 for a singular one (a cheap stand-in for the reciprocal condition number,
// which Eigen's LDLT::rcond() estimates by iterations: 6 % of the memory's time). Small where
// the points do not spread along t.
template <int N>
double conditioning(const Eigen::Matrix<double, N, N>& m) {
  const double column_sum = m.cwiseAbs().colwise().sum().maxCoeff();
  return std::abs(m.determinant()) / std::pow(column_sum, N);
}

// A local course's own bend (below) from at least this many points spread along it so that the
// fit's conditioning (t in units of the neighbourhood) is at least this: points spread evenly
// across the neighbourhood give 0.01, all on one side of it 1e-4, across a quarter of it 1e-5.
constexpr size_t kMinPointsForBend = 5;
constexpr double kMinBendCondition = 1e-6;

// The evidence for the registration: each remembered point's nearest evidence point, and the
// tape's local course there, worked out once when first asked for: the evidence within the
// neighbourhood in a frame along its principal direction, fitted with n = a + b t + c t^2, c
// half the curvature of the line in view (a straight line through the evidence lies inside an
// arc by about neighbourhood^2 / 6R, 0.04 mm on R 0.3 m, and the registration pulled the memory
// inwards by that every frame: 0.5 mm by the end of a quarter turn), or better the points' own
// where the neighbourhood holds enough of them to fit it (a bend the line in view does not have:
// a corner's, a joint's). On straight tape the points' own bend is noise: the examples' straight
// runs read 0.004 -> 0.005 mm with it.
class EvidenceIndex {
 public:
  // Set when first asked for (course_at), not before: most evidence points are nobody's
  // nearest.
  struct LocalCourse {
    bool valid;  // 3 or more points in the neighbourhood
    Eigen::Vector2d mean, tangent, normal;
    Eigen::Vector3d n_of_t;  // (a, b, c)

    // The signed distance of p from the course along its normal, and its gradient in p.
    double distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const {
      const double t = tangent.dot(p - mean), n = normal.dot(p - mean);
      *gradient = normal - (n_of_t[1] + 2.0 * n_of_t[2] * t) * tangent;
      return n - (n_of_t[0] + t * (n_of_t[1] + t * n_of_t[2]));
    }
  };

  EvidenceIndex(const std::vector<Eigen::Vector2d>& evidence, const CurveModel& line,
                double neighbourhood_m)
      : evidence_(evidence),
        line_(line),
        prepared_line_(line.prepared()),
        neighbourhood_m_(neighbourhood_m),
        grid_(evidence, neighbourhood_m),
        fine_grid_(evidence,
                   PointGrid::dense_cell_m(evidence, 0.25 * neighbourhood_m, neighbourhood_m)),
        courses_(new LocalCourse[evidence.size()]),
        computed_(evidence.size(), false),
        in_neighbourhood_(evidence.size(), false) {}

  // The index of the evidence point nearest to p (the lowest index among equals), if it lies
  // within the neighbourhood; else PointGrid::kNone.
  size_t nearest(const Eigen::Vector2d& p) const {
    return fine_grid_.nearest_index(evidence_, p, neighbourhood_m_);
  }

  const LocalCourse& course_at(size_t j) {
    LocalCourse& course = courses_[j];
    if (computed_[j]) return course;
    computed_[j] = true;
    course.valid = false;
    course.n_of_t.setZero();
    // The neighbourhood in the evidence's order (the sums below in that order): marked, then
    // read off between the lowest and highest index marked (neighbours along the tape are
    // neighbours in the scan).
    size_t first = evidence_.size(), last = 0;
    grid_.for_each_near(evidence_[j], [&](size_t k) {
      if ((evidence_[k] - evidence_[j]).squaredNorm() > neighbourhood_m_ * neighbourhood_m_) return;
      in_neighbourhood_[k] = true;
      first = std::min(first, k);
      last = std::max(last, k);
    });
    std::vector<size_t>& near = near_;
    near.clear();
    for (size_t k = first; k <= last && first <= last; ++k) {
      if (!in_neighbourhood_[k]) continue;
      in_neighbourhood_[k] = false;
      near.push_back(k);
    }
    if (near.size() < 3) return course;
    // The sums one by one (the same sums as Eigen's outer products, which went through memory
    // in halves and were read back whole: a stall per point).
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (size_t k : near) {
      const Eigen::Vector2d& e = evidence_[k];
      mean += e;
      sxx += e.x() * e.x();
      sxy += e.x() * e.y();
      syy += e.y() * e.y();
    }
    Eigen::Matrix2d scatter;
    scatter << sxx, sxy, sxy, syy;
    mean /= static_cast<double>(near.size());
    scatter = scatter / static_cast<double>(near.size()) - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
    eigen.computeDirect(scatter);
    course.valid = true;
    course.mean = mean;
    course.normal = eigen.eigenvectors().col(0);  // least spread: across the tape
    course.tangent = Eigen::Vector2d(-course.normal.y(), course.normal.x());
    // n(t) = a + b t + c t^2 across the course, t along it. The bend c: the points' own where
    // they spread along the course enough to tell it (a tight corner's, a joint's: on a bend the
    // line in view does not have, its curvature being one arc's through all its evidence, the
    // points lie a third of the bend's sagitta off the course, all to one side; a corner of R 0.14
    // m seen as a straight line drew the distance error's estimate to -0.13 % on exact odometry);
    // else the line in view's. t in units of the neighbourhood in the sums (their entries from 1
    // to t^4 otherwise span 10 decades).
    const double unit_m = neighbourhood_m_;
    double s[5] = {0.0, 0.0, 0.0, 0.0, 0.0};  // sums of u^0 .. u^4, u = t / unit_m
    double sn[3] = {0.0, 0.0, 0.0};           // sums of n u^0 .. n u^2
    for (size_t k : near) {
      const Eigen::Vector2d q = evidence_[k] - mean;
      const double u = course.tangent.dot(q) / unit_m, n = course.normal.dot(q);
      const double u2 = u * u;
      s[0] += 1.0;
      s[1] += u;
      s[2] += u2;
      s[3] += u2 * u;
      s[4] += u2 * u2;
      sn[0] += n;
      sn[1] += n * u;
      sn[2] += n * u2;
    }
    Eigen::Matrix3d ata;
    ata << s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4];
    const Eigen::Vector3d aty(sn[0], sn[1], sn[2]);
    const Eigen::Vector3d to_metres(1.0, 1.0 / unit_m, 1.0 / (unit_m * unit_m));
    if (near.size() >= kMinPointsForBend && conditioning(ata) > kMinBendCondition) {
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
      if (ldlt.info() == Eigen::Success) {
        course.n_of_t = ldlt.solve(aty).cwiseProduct(to_metres);
        return course;
      }
    }
    // Else the line in view's bend: its curvature turns its own direction to the left, and the
    // normal here lies to the right of the tangent, so a left turn along the tangent bends
    // towards -normal. Then the offset and slope that fit the points with that bend (rows
    // (1, u)).
    const double along = course.tangent.dot(prepared_line_.direction_at(mean));
    course.n_of_t[2] = -0.5 * line_.curvature_1_m * (along >= 0.0 ? 1.0 : -1.0);
    const double line_bend_u = course.n_of_t[2] * unit_m * unit_m;
    const Eigen::Matrix2d ata2 = ata.topLeftCorner<2, 2>();
    const Eigen::Vector2d aty2(sn[0] - line_bend_u * s[2], sn[1] - line_bend_u * s[3]);
    if (conditioning(ata2) > 1e-9) {
      const Eigen::LDLT<Eigen::Matrix2d> ldlt(ata2);
      if (ldlt.info() == Eigen::Success)
        course.n_of_t.head<2>() = ldlt.solve(aty2).cwiseProduct(to_metres.head<2>());
    }
    return course;
  }

 private:
  const std::vector<Eigen::Vector2d>& evidence_;
  CurveModel line_;  // the line in view the evidence belongs to
  CurveModel::Prepared prepared_line_;
  double neighbourhood_m_;
  PointGrid grid_;
  // For the nearest point: cells a quarter of the neighbourhood, or as small as the evidence's
  // spread allows a dense grid (a full search's 480 points 0.4 mm apart hold 20 a cell of the
  // neighbourhood's size, which every remembered point would look at).
  PointGrid fine_grid_;
  std::unique_ptr<LocalCourse[]> courses_;
  std::vector<bool> computed_;
  // Scratch for the neighbourhood of the course being worked out (all false between uses).
  std::vector<bool> in_neighbourhood_;
  std::vector<size_t> near_;
};

// A branch leaving a way at a tangent: its offset across the way grows as c (s - from_m)^2.
struct TangentDeparture {
  double from_m, c_1_m;
  double offset_m(double s_m) const { return c_1_m * (s_m - from_m) * (s_m - from_m); }
};

// Where the branch whose points lie `side` (+1 left, -1 right) of a way, past gate_m across it
// (marked in `off`, at arc positions `along`, offsets `across`, the nearest at first_off_m),
// left it: sqrt(offset) = sqrt(c) (s - from_m) is a straight line in s, fitted to the points
// within fit_m of the nearest; none for fewer than 3 or no growth.
std::optional<TangentDeparture> tangent_departure(const std::vector<double>& along,
                                                  const std::vector<double>& across,
                                                  const std::vector<bool>& off, double side,
                                                  double first_off_m, double fit_m, double gate_m) {
  double n = 0.0, st = 0.0, stt = 0.0, sr = 0.0, str = 0.0;
  for (size_t i = 0; i < along.size(); ++i) {
    if (!off[i] || side * across[i] <= 0.0 || along[i] > first_off_m + fit_m) continue;
    const double r = std::sqrt(side * across[i]);
    n += 1.0;
    st += along[i];
    stt += along[i] * along[i];
    sr += r;
    str += along[i] * r;
  }
  const double det = n * stt - st * st;
  if (n < 3.0 || det <= 0.0) return std::nullopt;
  const double slope = (n * str - st * sr) / det;  // sqrt(c)
  if (!(slope > 0.0)) return std::nullopt;
  return TangentDeparture{first_off_m - std::sqrt(gate_m) / slope, slope * slope};
}

// One frame's evidence no denser than radius_m: each run of consecutive points (the scans'
// order, along the tape) that stay within radius_m of the run's first point becomes their mean,
// counting as that many observations.
struct WeightedPoint {
  Eigen::Vector2d p;
  int count;
};
std::vector<WeightedPoint> thinned(const std::vector<Eigen::Vector2d>& points, double radius_m) {
  std::vector<WeightedPoint> runs;
  Eigen::Vector2d first = Eigen::Vector2d::Zero(), sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (const Eigen::Vector2d& p : points) {
    if (count > 0 && (p - first).squaredNorm() <= radius_m * radius_m) {
      sum += p;
      ++count;
      continue;
    }
    if (count > 0) runs.push_back({sum / count, count});
    first = sum = p;
    count = 1;
  }
  if (count > 0) runs.push_back({sum / count, count});
  return runs;
}

// Tolerances that scale with the tape's width use at least this width (narrower tapes).
constexpr double kNarrowTape_m = 0.01;

// Remembered points along the tape further apart than this leave a gap between them.
constexpr double kContiguous_m = 0.01;

// Whether `curve` passes p within near_m, running within max_turn_rad of heading_rad there
// (vehicle frame; an infinite max_turn_rad: whichever way it runs).
bool passes_along(const CurveModel::Prepared& curve, const Eigen::Vector2d& p, double heading_rad,
                  double near_m, double max_turn_rad) {
  if (std::abs(curve.signed_distance(p)) > near_m) return false;
  if (std::isinf(max_turn_rad)) return true;
  const Eigen::Vector2d d = curve.unit_direction_at(p);
  return std::abs(wrap_angle_rad(std::atan2(d.y(), d.x()) - heading_rad)) <= max_turn_rad;
}

// Whether the tape a model of the remembered tape puts under the vehicle runs more than 90 deg
// from the vehicle's heading: the vehicle drives along its tape, so such a reading (a fit in a
// corner's window, tight enough that its foot point lies round the bend: agv evaluate seed 12,
// sequence 4, 148 deg) is no measurement.
bool runs_against_the_vehicle(const CurveModel& model) {
  return std::abs(wrap_angle_rad(model.heading_rad)) > M_PI / 2.0;
}

// The line a measurement describes, in the vehicle frame (with_model's inverse).
CurveModel model_of(const LineMeasurement& m) {
  return CurveModel{m.e_d_m, -m.e_theta_rad, m.curvature_1_m};
}

// `in_view` with its errors and curvature from the remembered tape's model at the origin.
LineMeasurement with_model(const LineMeasurement& in_view, const CurveModel& model) {
  LineMeasurement m = in_view;
  m.e_d_m = model.e_d_m;
  m.e_theta_rad = wrap_angle_rad(-model.heading_rad);
  m.curvature_1_m = model.curvature_1_m;
  m.extrapolated = false;
  return m;
}

// A turn by a fixed angle, its cosine and sine worked out once for the many points it turns.
class Turn {
 public:
  explicit Turn(double angle_rad) : c_(std::cos(angle_rad)), s_(std::sin(angle_rad)) {}
  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
    return {c_ * p.x() - s_ * p.y(), s_ * p.x() + c_ * p.y()};
  }

 private:
  double c_, s_;
};

// Across a gap just past a corner: the end behind (at x0: value, slope and half the second
// derivative in `behind`) carried on as an arc at its curvature until it turns to the direction
// of the end ahead (at x1), then straight on; where it has turned past that direction already,
// the arc ends at x0 (the quadratic through a corner's last 40 mm, part arc and part the line
// after it, overshoots the line's direction at its end: agv evaluate seed 1, sequence 6, 4.4
// deg, and the cubic across the gap bulged 2.6 mm), only before a straight end ahead (a turn
// back the other way is an S, not the line after the corner). Where that arc ends within
// meets_m of the line through the end ahead, between the two ends and behind the origin, the
// tape at the origin is that line: value, slope and second derivative (0) at x = 0. Else
// nothing.
std::optional<Eigen::Vector3d> line_after_corner_arc(double x0, const Eigen::Vector3d& behind,
                                                     double x1, const Eigen::Vector3d& ahead,
                                                     double meets_m) {
  constexpr double kMinCurvature_1_m = 1.0;  // R 1 m: tighter is a corner's arc
  const double h0 = std::atan(behind[1]), h1 = std::atan(ahead[1]);
  const double k0 = 2.0 * behind[2] / std::pow(1.0 + behind[1] * behind[1], 1.5);
  const double k1 = 2.0 * ahead[2] / std::pow(1.0 + ahead[1] * ahead[1], 1.5);
  if (std::abs(k0) < kMinCurvature_1_m) return std::nullopt;
  const bool turned_past = k0 * (h1 - h0) <= 0.0;
  if (turned_past && std::abs(k1) >= kMinCurvature_1_m) return std::nullopt;
  const Eigen::Vector2d start(x0, behind[0]);
  const Eigen::Vector2d centre = start + Eigen::Vector2d(-std::sin(h0), std::cos(h0)) / k0;
  const Eigen::Vector2d end =
      turned_past ? start
                  : Eigen::Vector2d(centre + Eigen::Vector2d(std::sin(h1), -std::cos(h1)) / k0);
  auto line_y = [&](double x) { return ahead[0] + ahead[1] * (x - x1); };
  if (std::abs(end.y() - line_y(end.x())) * std::cos(h1) > meets_m || end.x() < x0 || end.x() > 0.0)
    return std::nullopt;
  return Eigen::Vector3d(line_y(0.0), ahead[1], 0.0);
}

// The arc positions along `course` of the points within band_m of it (NaN for the others), and
// the nearest of them behind the origin (at most 0; -inf for none) and ahead of it (+inf).
struct AlongCourse {
  std::vector<double> s_of;
  double last_behind = -std::numeric_limits<double>::infinity();
  double first_ahead = std::numeric_limits<double>::infinity();
  // Which end of the gap point i lies in: 0 within span_m behind last_behind, 1 within span_m
  // beyond first_ahead, else (or off the band) -1.
  int end_of(size_t i, double span_m) const {
    const double s = s_of[i];
    return s <= last_behind && s >= last_behind - span_m   ? 0
           : s >= first_ahead && s <= first_ahead + span_m ? 1
                                                           : -1;
  }
};
AlongCourse along_course(const CurveModel::Prepared& course, double band_m,
                         const std::vector<Eigen::Vector2d>& points) {
  AlongCourse r;
  r.s_of.assign(points.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::abs(course.signed_distance(points[i])) > band_m) continue;
    const double s = course.arc_position(points[i]);
    r.s_of[i] = s;
    if (s <= 0.0)
      r.last_behind = std::max(r.last_behind, s);
    else
      r.first_ahead = std::min(r.first_ahead, s);
  }
  return r;
}

// How many observations the (x, observations) pairs hold together.
int observations_of(const std::vector<std::pair<double, int>>& along) {
  int n = 0;
  for (const auto& [x, count] : along) n += count;
  return n;
}

// The x of the point that holds the k-th observation (from 0) counted from `first` on, the pairs
// sorted by x (the last point's where they hold fewer).
template <typename Iterator>
double x_of_observation(Iterator first, Iterator last, int k) {
  int seen = 0;
  for (Iterator it = first; it != last; ++it) {
    seen += it->second;
    if (seen > k) return it->first;
  }
  return std::prev(last)->first;
}

}  // namespace

void PathMemory::reset() {
  points_.clear();
  tape_width_m_ = 0.0;
  disagreeing_frames_ = 0;
  disagreeing_width_m_ = 0.0;
  correction_ = Pose2{};
  reset_misalignment();
  last_odometry_.reset();
  tape_heading_rad_.reset();
  ahead_heading_rad_.reset();
  corner_passed_at_m_.reset();
  recent_headings_.clear();
  last_course_.reset();
  on_arc_from_m_.reset();
  last_reading_.reset();
  view_.reset();
  view_before_.reset();
  reported_at_m_.reset();
  unconfirmed_.reset();
  frames_without_line_ = 0;
  last_corner_course_.reset();
  read_off_corner_ = false;
  read_across_corner_ = false;
}

std::vector<Eigen::Vector2d> PathMemory::points_in_vehicle_frame() const {
  const Pose2::Map to_vehicle = vehicle_.inverse().map();
  std::vector<Eigen::Vector2d> out;
  out.reserve(points_.size());
  for (const Point& point : points_) out.push_back(to_vehicle(point.p));
  return out;
}

void PathMemory::reset_misalignment() {
  misalignment_cov_.setZero();
  misalignment_cov_(3, 3) = options_.yaw_drift_sigma_rad_per_m * options_.yaw_drift_sigma_rad_per_m;
  misalignment_cov_(4, 4) = options_.distance_error_sigma * options_.distance_error_sigma;
  yaw_drift_rad_per_m_ = 0.0;
  distance_error_ = 0.0;
}

void PathMemory::grow_misalignment(double travelled_m, const Eigen::Vector2d& moved_m,
                                   OdometryKind kind) {
  // The misalignment's uncertainty grows by what the odometry can have got wrong since the last
  // frame: a constant by kind of odometry and a part per metre driven (from 0 when nothing is
  // remembered: this frame's evidence is placed where the vehicle is; the yaw drift and distance
  // error estimates stay).
  if (points_.empty()) {
    misalignment_cov_.topRows<3>().setZero();
    misalignment_cov_.leftCols<3>().setZero();
  }
  // On wheels the rotation grows by the yaw drift estimate's error times the distance (x_r +=
  // d x_b) and the shift by the distance error estimate's times the motion (x_t += m x_s); update
  // takes the estimates' own rotation and shift out.
  if (kind == OdometryKind::wheels) {
    Misalignment grow = Misalignment::Identity();
    if (options_.yaw_drift_sigma_rad_per_m > 0.0) {
      grow(0, 3) = travelled_m;
      misalignment_cov_(3, 3) += options_.yaw_drift_walk_rad_per_m_per_sqrt_m *
                                 options_.yaw_drift_walk_rad_per_m_per_sqrt_m * travelled_m;
    }
    if (options_.distance_error_sigma > 0.0) {
      grow.block<2, 1>(1, 4) = moved_m;
      misalignment_cov_(4, 4) += options_.distance_error_walk_per_sqrt_m *
                                 options_.distance_error_walk_per_sqrt_m * travelled_m;
    }
    misalignment_cov_ = grow * misalignment_cov_ * grow.transpose();
  }
  const PathMemoryOptions::Prior& prior = kind == OdometryKind::wheels   ? options_.wheels_prior
                                          : kind == OdometryKind::frames ? options_.frames_prior
                                                                         : options_.guess_prior;
  // At least a micrometre (and a microradian): a vehicle standing still on wheels (no constant
  // shift) leaves its memory where it is, and the prior's information finite.
  constexpr double kMinSigma = 1e-6;
  const double shift_per_m =
      kind == OdometryKind::wheels ? options_.wheels_shift_per_m : options_.prior_shift_per_m;
  const double sigma_t = std::max(kMinSigma, prior.shift_m + shift_per_m * travelled_m);
  const double sigma_r =
      std::max(kMinSigma, prior.turn_rad + options_.prior_turn_rad_per_m * travelled_m);
  misalignment_cov_.diagonal().head<3>() +=
      Eigen::Vector3d(sigma_r * sigma_r, sigma_t * sigma_t, sigma_t * sigma_t);
  // Along a straight tape the shift along it is never seen: the uncertainty stops at what a
  // registration may correct at all.
  const Eigen::Vector3d cap(options_.max_correction_rad * options_.max_correction_rad,
                            options_.max_correction_m * options_.max_correction_m,
                            options_.max_correction_m * options_.max_correction_m);
  for (int i = 0; i < 3; ++i) {
    if (misalignment_cov_(i, i) <= cap[i]) continue;
    const double scale = std::sqrt(cap[i] / misalignment_cov_(i, i));
    misalignment_cov_.row(i) *= scale;
    misalignment_cov_.col(i) *= scale;
  }
}

void PathMemory::register_to(const std::vector<Eigen::Vector2d>& evidence, const CurveModel& line,
                             double travelled_m, std::vector<Eigen::Vector2d>* in_vehicle) {
  // d_i + J_i delta = 0 for the remembered points that lie on the tape in view, d_i the distance
  // from the tape's local course through the nearest evidence points (the evidence itself, bent
  // by the line in view's curvature: not the curve fitted to all of it, which may not hold across
  // a joint; see EvidenceIndex), delta = (rotation about the origin, shift x, shift y). The shift
  // along a straight tape is not observable: a small ridge keeps it at 0.
  if (evidence.size() < 3) return;
  std::vector<RegistrationRow>& rows = registration_rows_;
  rows.clear();
  int count = 0;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;  // the overlap's bounding box
  EvidenceIndex index(evidence, line, options_.neighbourhood_m);
  for (size_t i = 0; i < in_vehicle->size(); ++i) {
    const Eigen::Vector2d& p = (*in_vehicle)[i];
    const size_t nearest = index.nearest(p);
    if (nearest == PointGrid::kNone) continue;
    // The local direction of the evidence: its points within the neighbourhood of the nearest.
    const EvidenceIndex::LocalCourse& course = index.course_at(nearest);
    if (!course.valid) continue;
    Eigen::Vector2d normal;
    const double d = course.distance(p, &normal);
    if (std::abs(d) > options_.gate_m) continue;
    rows.push_back(
        {Eigen::Vector3d(normal.dot(Eigen::Vector2d(-p.y(), p.x())), normal.x(), normal.y()), d,
         static_cast<double>(points_[i].observations)});
    count += points_[i].observations;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (count < options_.min_overlap_points || (hi - lo).norm() < options_.min_overlap_span_m) return;
  // The most likely correction given the points (each good to point_sigma_m) and how far the
  // memory may be out of line: along a straight tape the points say nothing of the shift along
  // it, and the prior keeps it where the odometry put it. Then twice more with Cauchy weights on
  // the residuals the correction leaves (registration_residual_scale_m).
  // With the odometry's yaw drift and distance error (states the points see only through their
  // past coupling to the rotation and shift): the same in the 5 x 5 information form. A state
  // left out (its prior 0) is held at 0 (its prior information 1, no coupling).
  const double point_weight = 1.0 / (options_.point_sigma_m * options_.point_sigma_m);
  const double scale_m = options_.registration_residual_scale_m;
  const bool held[2] = {!(options_.yaw_drift_sigma_rad_per_m > 0.0),
                        !(options_.distance_error_sigma > 0.0)};
  Misalignment prior_cov = misalignment_cov_;
  for (int k = 3; k < 5; ++k) {
    if (!held[k - 3]) continue;
    prior_cov.row(k).setZero();
    prior_cov.col(k).setZero();
    prior_cov(k, k) = 1.0;
  }
  const Misalignment prior_information = prior_cov.ldlt().solve(Misalignment::Identity());
  Misalignment information = prior_information;
  Eigen::Matrix<double, 5, 1> delta = Eigen::Matrix<double, 5, 1>::Zero();
  for (int round = 0; round < (scale_m > 0.0 ? 3 : 1); ++round) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtd = Eigen::Vector3d::Zero();
    for (const RegistrationRow& row : rows) {
      double w = row.observations;
      if (round > 0) {
        const double r = (row.d + row.j.dot(delta.head<3>())) / scale_m;
        w /= 1.0 + r * r;
      }
      // jtj += w j j', jtd += w j d, element by element (Eigen's outer product went through
      // memory in halves and was read back whole: a stall per row).
      for (int a = 0; a < 3; ++a) {
        const double wj = w * row.j[a];
        for (int b = 0; b < 3; ++b) jtj(a, b) += wj * row.j[b];
        jtd[a] += wj * row.d;
      }
    }
    information = prior_information;
    information.topLeftCorner<3, 3>() += point_weight * jtj;
    Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
    rhs.head<3>() = -point_weight * jtd;
    delta = information.ldlt().solve(rhs);
  }
  misalignment_cov_ = information.ldlt().solve(Misalignment::Identity());
  for (int k = 3; k < 5; ++k) {
    if (!held[k - 3]) continue;
    misalignment_cov_.row(k).setZero();
    misalignment_cov_.col(k).setZero();
  }
  if (std::abs(delta[0]) > options_.max_correction_rad ||
      delta.segment<2>(1).norm() > options_.max_correction_m) {
    points_.clear();  // the remembered tape is not this tape (or the odometry jumped)
    in_vehicle->clear();
    reset_misalignment();
    return;
  }
  yaw_drift_rad_per_m_ += delta[3];
  // The distance error at most distance_error_rate_per_m further per metre driven since the last
  // frame (what one registration says of it may be a corner's bias, or another tape's). Its
  // variance is the filter's all the same: where the limit holds, the filter is surer of the
  // estimate than it should be, and the estimate converges the slower for it.
  const double most = options_.distance_error_rate_per_m * travelled_m;
  distance_error_ += std::clamp(delta[4], -most, most);
  const Pose2 move{delta[1], delta[2], delta[0]};
  const Pose2::Map moved = move.map();
  for (Eigen::Vector2d& p : *in_vehicle) p = moved(p);
  vehicle_ = vehicle_.compose(move.inverse());
}

std::optional<LineMeasurement> PathMemory::at_origin(
    const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle) const {
  // A frame along the tape near the origin: the remembered tape's direction under the vehicle
  // when known (the line in view may be a corner's outgoing leg the vehicle has not reached),
  // else the line in view's heading there; refined by the fit's own slope (up to twice) so that
  // the slopes the fit sees stay small. Only points near the origin across the tape too: with a
  // frame still turned (a corner's outgoing leg in view), the window along it would reach the
  // other leg.
  const double first_frame_rad = tape_heading_rad_
                                     ? wrap_angle_rad(*tape_heading_rad_ - vehicle_.yaw_rad)
                                     : -in_view.e_theta_rad;
  double frame_rad = first_frame_rad;
  std::optional<JoinedArcs> fit;
  // Only points as near the origin as the window's corners (a rounding margin) can lie in it,
  // whichever way it turns.
  const double reach_m = std::hypot(options_.window_m, options_.window_across_m) + 1e-9;
  std::vector<size_t> near_origin;
  near_origin.reserve(in_vehicle.size());
  for (size_t i = 0; i < in_vehicle.size(); ++i)
    if (in_vehicle[i].squaredNorm() <= reach_m * reach_m) near_origin.push_back(i);
  // Where the window holds more than one tape (below), only the points within a tape width of
  // the course last measured, carried forward.
  bool on_course_only = false;
  bool both_sides = true;  // whether the window's tape reaches min_cover_m on both sides
  // (std::optional here trips GCC 12's maybe-uninitialized warning.)
  const bool has_course = last_course_.has_value();
  const CurveModel::Prepared course = (has_course ? last_course_now() : CurveModel{}).prepared();
  const double course_gate_m = std::max(tape_width_m_, kNarrowTape_m);
  for (int pass = 0;; ++pass) {
    std::vector<Eigen::Vector2d> local;
    std::vector<double> weights;                // each point's observations
    std::vector<std::pair<double, int>> along;  // (x, observations)
    local.reserve(near_origin.size());
    weights.reserve(near_origin.size());
    along.reserve(near_origin.size());
    const Turn to_frame(-frame_rad);
    for (size_t i : near_origin) {
      const Eigen::Vector2d q = to_frame(in_vehicle[i]);
      if (std::abs(q.x()) > options_.window_m || std::abs(q.y()) > options_.window_across_m)
        continue;
      if (on_course_only && std::abs(course.signed_distance(in_vehicle[i])) > course_gate_m)
        continue;
      local.push_back(q);
      weights.push_back(points_[i].observations);
      along.emplace_back(q.x(), points_[i].observations);
    }
    // Enough tape on both sides: the side_points-th observation from either end reaches
    // min_cover_m (a stray point or two far out is not tape under the vehicle); or, once a course
    // was measured and on wheel odometry, on one side, the other reaching the origin within
    // one_side_reach_m: the tape under the vehicle seen from one side of a hole in the memory
    // just ahead of it (where a fork's legs overlapped and gave no chord one tape wide) or just
    // behind it (the way not taken, forgotten); the fit then only as near the course carried
    // forward as the tape ahead must be (below). Not in the memory's warm-up (its first readings
    // from one side: e_theta RMS 0.006 -> 0.016 deg on straight-tape examples), nor on motion read
    // from the frames (datasets/yellow_junction_worn: two frames past the fork read from one side
    // 1.1 mm / 1.7 deg and 0.2 mm / 0.9 deg off, where the line in view carried back was within
    // 0.1 mm / 0.01 deg).
    const int k = options_.side_points;
    if (observations_of(along) < std::max(options_.min_points, 2 * k + 2)) return std::nullopt;
    std::sort(along.begin(), along.end());
    const double lo = x_of_observation(along.begin(), along.end(), k);
    const double hi = x_of_observation(along.rbegin(), along.rend(), k);
    const double cover_m = options_.min_cover_m, short_m = options_.one_side_reach_m;
    both_sides = lo <= -cover_m && hi >= cover_m;
    const bool one_side = (lo <= -cover_m && hi >= -short_m) || (hi >= cover_m && lo <= short_m);
    if (!both_sides && !(one_side && odometry_kind_ == OdometryKind::wheels)) return std::nullopt;
    // Read from one side, two joined arcs only where they fit clearly better than one
    // (one_side_joint_gain).
    fit = fit_joined_arcs(local, weights);
    if (!both_sides && fit && fit->break_x_m) {
      JoinedArcsOptions one_piece;
      one_piece.joint = false;
      const std::optional<JoinedArcs> one = fit_joined_arcs(local, weights, one_piece);
      if (one && one->rms_m <= options_.one_side_joint_gain * fit->rms_m) fit = one;
    }
    if (!fit) return std::nullopt;
    // The fit is in this frame: turn it only for another pass (the model below adds the slope).
    if (std::abs(fit->slope) < 0.02 || pass == 2) {
      // A residual of millimetres in the fit kept: the window holds more than one tape (a
      // fork's other leg beside the one under the vehicle), whose fit runs off at any angle.
      // Fitted again, turned as at first, to the tape along the course last measured, where
      // there is one.
      if (fit->rms_m <= options_.max_fit_rms_m) break;
      if (!has_course || on_course_only) return std::nullopt;
      on_course_only = true;
      frame_rad = first_frame_rad;
      pass = -1;
      continue;
    }
    frame_rad += std::atan(fit->slope);
  }
  // The tape under the vehicle turns by its curvature times the distance driven: a fit that
  // turns it much further from the direction last measured under the vehicle (points of a
  // fork's two legs, or of a tape crossing, in the window: the direction read 180 deg off) is
  // no measurement.
  if (last_course_) {
    const double heading_rad = vehicle_.yaw_rad + frame_rad + std::atan(fit->slope);
    const double driven_m = odometer_m_ - last_course_->odometer_m;
    if (std::abs(wrap_angle_rad(heading_rad - last_course_->heading_rad)) >
        options_.max_turn_rad + options_.max_curvature_1_m * driven_m)
      return std::nullopt;
  }
  const CurveModel fitted =
      curve_in_frame(frame_rad, fit->offset_m, fit->slope, fit->curvature_1_m);
  if (runs_against_the_vehicle(fitted)) return std::nullopt;
  // Read from one side, the fit runs to the end of its tape: only as near the course last
  // measured, carried forward, as the tape ahead must be (from_tape_ahead); none in the warm-up.
  if (!both_sides && !near_course_carried_forward(fitted)) return std::nullopt;
  // Nor is one that puts the tape far across from both the line in view carried back and the
  // course last measured carried forward (another stretch of the path beside the vehicle).
  const double tolerance_m = std::max(tape_width_m_, kNarrowTape_m) + options_.max_offset_jump_m;
  const bool near_view =
      in_view.line_found && std::abs(fitted.e_d_m - in_view.e_d_m) <= tolerance_m;
  const bool near_course =
      last_course_ && std::abs(fitted.e_d_m - last_course_now().e_d_m) <= tolerance_m;
  if (last_course_ && !near_view && !near_course) return std::nullopt;
  return with_model(in_view, fitted);
}

bool PathMemory::straight_after_turn() const {
  bool turned = false;
  for (const auto& [odometer_m, yaw_rad] : recent_headings_) {
    const double turn_rad = std::abs(wrap_angle_rad(vehicle_.yaw_rad - yaw_rad));
    if (odometer_m_ - odometer_m <= options_.bridge_steady_m &&
        turn_rad > options_.bridge_steady_turn_rad)
      return false;
    turned = turned || turn_rad > options_.bridge_after_turn_rad;
  }
  return turned;
}

std::optional<LineMeasurement> PathMemory::across_gap(
    const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle,
    bool corner_in_gap) const {
  // Just after a corner passed on the memory alone, or a turn driven with the tape in view; or
  // (corner_in_gap) at neither, inside a corner never seen whole whose way out is the line in
  // view.
  const bool after_corner =
      corner_passed_at_m_ && odometer_m_ - *corner_passed_at_m_ <= options_.bridge_after_corner_m;
  if (corner_in_gap != (!after_corner && !straight_after_turn())) return std::nullopt;
  if (corner_in_gap && (!in_view.line_found || !(options_.corner_gap_view_turn_rad > 0.0)))
    return std::nullopt;
  const double band_m =
      after_corner || corner_in_gap ? options_.window_across_m : options_.bridge_band_m;
  // In a frame along the remembered tape's direction at the origin (else the vehicle's): the
  // tape nearest behind the origin and nearest ahead of it, each over gap_end_m.
  const double frame_rad =
      tape_heading_rad_ ? wrap_angle_rad(*tape_heading_rad_ - vehicle_.yaw_rad) : 0.0;
  std::vector<Eigen::Vector2d> local;
  std::vector<int> observations;  // each local point's
  std::vector<double> along;
  const Turn to_frame(-frame_rad);
  for (size_t i = 0; i < in_vehicle.size(); ++i) {
    const Eigen::Vector2d q = to_frame(in_vehicle[i]);
    if (std::abs(q.y()) > band_m || q.x() < -options_.keep_behind_m ||
        q.x() > options_.max_gap_m + options_.gap_end_m)
      continue;
    local.push_back(q);
    observations.push_back(points_[i].observations);
    along.push_back(q.x());
  }
  // The gap: two consecutive points (along the tape) more than kContiguous_m apart, the origin
  // between them or less than twice min_cover_m beyond either (where the fit at the origin lacks
  // tape on that side), the nearest such.
  std::sort(along.begin(), along.end());
  double last_behind = 0.0, first_ahead = 0.0, best = 2.0 * options_.min_cover_m;
  for (size_t j = 0; j + 1 < along.size(); ++j) {
    if (along[j + 1] - along[j] < kContiguous_m) continue;
    const double outside = std::max({0.0, along[j], -along[j + 1]});  // origin at 0
    if (outside >= best) continue;
    best = outside;
    last_behind = along[j];
    first_ahead = along[j + 1];
  }
  if (!(first_ahead > last_behind)) return std::nullopt;
  if (first_ahead - last_behind > options_.max_gap_m) return std::nullopt;
  // The two ends (points in the frame above), in a frame along the chord across the gap (so that
  // the tape across it has small slopes): each end's position and direction where it meets the gap
  // from a quadratic through the tape within gap_end_m of its point next to the gap, and a cubic
  // between them with those values and slopes (Hermite), whose value, slope and second
  // derivative at the origin give the errors. Within gap_end_m of that point, not within
  // gap_end_m along the frame: a corner's arc ending at the gap runs across the frame, and its
  // stretch along the frame took in the whole arc, whose quadratic then turned the end by up to
  // 20 deg from frame to frame (agv evaluate seed 43, sequence 5: a corner of R 0.10 m whose exit
  // the camera never saw, bridged 15 mm / 15 deg off).
  auto point_at = [&local](double x) {
    return *std::find_if(local.begin(), local.end(),
                         [x](const Eigen::Vector2d& q) { return q.x() == x; });
  };
  const Eigen::Vector2d p0 = point_at(last_behind), p1 = point_at(first_ahead);
  std::vector<Eigen::Vector2d> ends[2];
  std::vector<int> end_observations[2];
  int observed[2] = {0, 0};
  const double reach2 = options_.gap_end_m * options_.gap_end_m;
  for (size_t i = 0; i < local.size(); ++i) {
    const Eigen::Vector2d& q = local[i];
    const int end = q.x() <= last_behind && (q - p0).squaredNorm() <= reach2   ? 0
                    : q.x() >= first_ahead && (q - p1).squaredNorm() <= reach2 ? 1
                                                                               : -1;
    if (end < 0) continue;
    ends[end].push_back(q);
    end_observations[end].push_back(observations[i]);
    observed[end] += observations[i];
  }
  if (observed[0] < options_.min_points || observed[1] < options_.min_points) return std::nullopt;
  const double chord_rad = std::atan2(p1.y() - p0.y(), p1.x() - p0.x());
  const Turn along_chord(-chord_rad);
  // Value and slope at x_end of y = a + b (x - x_end) + c (x - x_end)^2, least squares.
  auto end_of = [&](int end, double x_end) {
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d aty = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < ends[end].size(); ++i) {
      const Eigen::Vector2d r = along_chord(ends[end][i]);
      const double u = r.x() - x_end, w = end_observations[end][i];
      const Eigen::Vector3d row(1.0, u, u * u);
      ata += w * row * row.transpose();
      aty += w * row * r.y();
    }
    return Eigen::Vector3d(ata.ldlt().solve(aty));
  };
  const double x0 = along_chord(p0).x(), x1 = along_chord(p1).x();
  const Eigen::Vector3d behind = end_of(0, x0), ahead = end_of(1, x1);
  if (!behind.allFinite() || !ahead.allFinite() || !(x1 > x0)) return std::nullopt;
  // Where the two ends' directions disagree (the tape remembered behind still bends out of a
  // corner, or was seen badly there), the line through the end ahead, the tape seen last, if
  // it meets the end behind within max_gap_offset_m.
  const bool agree =
      std::abs(std::atan(ahead[1]) - std::atan(behind[1])) <= options_.max_gap_turn_rad;
  if (corner_in_gap) {
    // The ends turn by more than max_gap_turn_rad (else no corner) with the origin between
    // them, the end behind lies on the course measured before the corner and the end ahead on
    // the line in view (else one of them may be another leg's, or not yet the way out).
    if (agree || !(x0 < 0.0 && 0.0 < x1) || !last_course_ ||
        odometer_m_ - last_course_->odometer_m > options_.max_gap_m)
      return std::nullopt;
    // Whether `curve` passes through the end at x (frame y = c[0], slope c[1]) within
    // corner_gap_view_offset_m, running in its direction within corner_gap_view_turn_rad.
    const Turn to_vehicle(frame_rad + chord_rad);
    auto runs_through = [&](const CurveModel& curve, double x, const Eigen::Vector3d& c) {
      return passes_along(curve.prepared(), to_vehicle(Eigen::Vector2d(x, c[0])),
                          frame_rad + chord_rad + std::atan(c[1]),
                          options_.corner_gap_view_offset_m, options_.corner_gap_view_turn_rad);
    };
    // (The frames after one read across the corner checked the end behind against the course
    // before the corner; their own course is the arc's.)
    if ((!read_across_corner_ && !runs_through(last_course_now(), x0, behind)) ||
        !runs_through(model_of(in_view), x1, ahead))
      return std::nullopt;
    // The corner's arc tangent to the way in and the way out (a cubic across a 90 deg corner of
    // R 0.11 m lies up to 4.9 mm off it).
    const std::optional<CurveModel> fillet = corner_fillet(
        to_vehicle(Eigen::Vector2d(x0, behind[0])), frame_rad + chord_rad + std::atan(behind[1]),
        to_vehicle(Eigen::Vector2d(x1, ahead[0])), frame_rad + chord_rad + std::atan(ahead[1]));
    if (!fillet || runs_against_the_vehicle(*fillet)) return std::nullopt;
    return with_model(in_view, *fillet);
  }
  // The origin in the frame is x = 0 (a rotation about it); beyond either end, that end's own.
  double y, slope, second;
  if (const std::optional<Eigen::Vector3d> line =
          line_after_corner_arc(x0, behind, x1, ahead, options_.bridge_arc_meets_m)) {
    y = (*line)[0];
    slope = (*line)[1];
    second = (*line)[2];
  } else if (!agree) {
    // ... and only where that line passes by the end behind (not a branch leaving there).
    if (std::abs(ahead[0] + ahead[1] * (x0 - x1) - behind[0]) > options_.max_gap_offset_m)
      return std::nullopt;
    y = ahead[0] - ahead[1] * x1;
    slope = ahead[1];
    second = 0.0;
  } else if (0.0 <= x0 || 0.0 >= x1) {
    const Eigen::Vector3d& c = 0.0 <= x0 ? behind : ahead;
    const double u = -(0.0 <= x0 ? x0 : x1);
    y = c[0] + c[1] * u + c[2] * u * u;
    slope = c[1] + 2.0 * c[2] * u;
    second = 2.0 * c[2];
  } else {
    // Hermite basis on t = (x - x0) / h.
    const double h = x1 - x0, t = -x0 / h;
    const double y0 = behind[0], m0 = behind[1] * h, y1 = ahead[0], m1 = ahead[1] * h;
    const double t2 = t * t, t3 = t2 * t;
    y = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * y1 +
        (t3 - t2) * m1;
    slope = ((6 * t2 - 6 * t) * y0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * y1 +
             (3 * t2 - 2 * t) * m1) /
            h;
    second =
        ((12 * t - 6) * y0 + (6 * t - 4) * m0 + (-12 * t + 6) * y1 + (6 * t - 2) * m1) / (h * h);
  }
  // The chord frame in the vehicle frame is turned by frame_rad + chord_rad.
  const CurveModel bridged = curve_in_frame(frame_rad + chord_rad, y, slope, second);
  if (runs_against_the_vehicle(bridged)) return std::nullopt;
  return with_model(in_view, bridged);
}

std::optional<LineMeasurement> PathMemory::through_gap(
    const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle) const {
  if (options_.through_end_m <= 0.0 || !last_course_) return std::nullopt;
  const CurveModel course = last_course_now();
  const CurveModel::Prepared along = course.prepared();
  const double band_m = std::max(tape_width_m_, kNarrowTape_m);
  // Arc positions along the course of the points near it; the gap around the origin.
  const AlongCourse on_course = along_course(along, band_m, in_vehicle);
  const double last_behind = on_course.last_behind, first_ahead = on_course.first_ahead;
  // A gap (no tape within a centimetre either side of the origin is at_origin's case).
  if (!std::isfinite(last_behind) || !std::isfinite(first_ahead) ||
      first_ahead - last_behind > options_.max_gap_m || first_ahead - last_behind < kContiguous_m)
    return std::nullopt;
  std::vector<Eigen::Vector2d> ends;
  std::vector<int> end_of;  // 0 behind, 1 ahead
  std::vector<int> observations;
  for (size_t i = 0; i < in_vehicle.size(); ++i) {
    const int end = on_course.end_of(i, options_.through_end_m);
    if (end < 0) continue;
    ends.push_back(in_vehicle[i]);
    end_of.push_back(end);
    observations.push_back(points_[i].observations);
  }
  CurveFitOptions fit_options;
  fit_options.inlier_threshold_m = options_.through_inlier_m;
  fit_options.forward = course.tangent();
  const CurveFit fit = fit_curve_robust(ends, fit_options);
  if (!fit.ok ||
      std::abs(fit.model.curvature_1_m - course.curvature_1_m) > options_.through_max_bend_1_m)
    return std::nullopt;
  // Both ends held: enough observations within the inlier band, over at least 2 cm each (the
  // stem behind is forgotten keep_behind_m back).
  constexpr double kMinEndSpan_m = 0.02;
  const CurveModel::Prepared fitted = fit.model.prepared();
  int held[2] = {0, 0};
  double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
  for (size_t i = 0; i < ends.size(); ++i) {
    if (std::abs(fitted.signed_distance(ends[i])) > options_.through_inlier_m) continue;
    const int end = end_of[i];
    held[end] += observations[i];
    const double s = fitted.arc_position(ends[i]);
    lo[end] = std::min(lo[end], s);
    hi[end] = std::max(hi[end], s);
  }
  for (int end : {0, 1})
    if (held[end] < options_.min_points || hi[end] - lo[end] < kMinEndSpan_m) return std::nullopt;
  if (runs_against_the_vehicle(fit.model) || !near_course_carried_forward(fit.model))
    return std::nullopt;
  return with_model(in_view, fit.model);
}

std::optional<LineMeasurement> PathMemory::around_corner(
    const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle) const {
  // Only after a course measured on an arc: the circle is started from it. Where the last frame
  // read the way out off that arc here (the line after it, below), it is still the arc's, within
  // max_gap_m driven.
  const bool on_arc =
      last_course_ && std::abs(last_course_->curvature_1_m) >= options_.corner_min_curvature_1_m;
  const bool read_off = read_off_corner_ && last_corner_course_ &&
                        odometer_m_ - last_corner_course_->odometer_m <= options_.max_gap_m;
  if (options_.corner_band_m <= 0.0 || !(on_arc || read_off)) return std::nullopt;
  const CurveModel course = course_now(*last_corner_course_);
  const CurveModel::Prepared along = course.prepared();
  const double band_m = std::max(options_.corner_band_m, tape_width_m_);
  // Arc positions along the course (carried on from where it was measured) of the points near
  // it; the gap around the origin between the nearest behind and the nearest ahead.
  const AlongCourse on_course = along_course(along, band_m, in_vehicle);
  const double last_behind = on_course.last_behind, first_ahead = on_course.first_ahead;
  // No tape remembered along the course within max_gap_m behind (a tight corner under a low
  // camera, its arc never seen): the course alone, measured within max_gap_m driven, is the arc.
  const bool seen_behind = std::isfinite(last_behind) && -last_behind <= options_.max_gap_m;
  if (!seen_behind && odometer_m_ - last_corner_course_->odometer_m > options_.max_gap_m)
    return std::nullopt;
  std::vector<Eigen::Vector2d> ends, ahead;
  int observed[2] = {0, 0};
  for (size_t i = 0; i < in_vehicle.size(); ++i) {
    const int end = on_course.end_of(i, options_.gap_end_m);
    if (end < 0) continue;
    ends.push_back(in_vehicle[i]);
    if (end == 1) ahead.push_back(in_vehicle[i]);
    observed[end] += points_[i].observations;
  }
  if (seen_behind && observed[0] < options_.min_points) return std::nullopt;
  if (seen_behind && observed[1] >= options_.min_points &&
      first_ahead - last_behind <= options_.max_gap_m) {
    // One circle (or line) through both ends, from the course: it must hold nine in ten of their
    // points (the tape ahead may already be the straight after the corner: then it does not).
    CurveFitOptions fit_options;
    fit_options.inlier_threshold_m = 3.0 * options_.corner_max_rms_m;
    fit_options.forward = course.tangent();
    const CurveFit fit = fit_curve_robust(ends, fit_options, nullptr, nullptr, &course);
    if (fit.ok && fit.rms_m <= options_.corner_max_rms_m &&
        10 * fit.inlier_count >= 9 * static_cast<int>(ends.size()) &&
        !runs_against_the_vehicle(fit.model))
      return with_model(in_view, fit.model);
    const std::optional<CurveModel> joined = line_after_arc(course, ahead);
    if (joined && !runs_against_the_vehicle(*joined)) return with_model(in_view, *joined);
  }
  // The corner ends in the gap and its way out runs off the arc at once (a tight corner: out of
  // the band): the tape nearest ahead of the vehicle (within max_gap_m ahead, window_across_m
  // across), over gap_end_m, as the line after the arc.
  double nearest_x = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : in_vehicle)
    if (p.x() > 0.0 && p.x() <= options_.max_gap_m && std::abs(p.y()) <= options_.window_across_m)
      nearest_x = std::min(nearest_x, p.x());
  if (!std::isfinite(nearest_x)) return std::nullopt;
  ahead.clear();
  int observed_ahead = 0;
  for (size_t i = 0; i < in_vehicle.size(); ++i) {
    const Eigen::Vector2d& p = in_vehicle[i];
    if (p.x() < nearest_x || p.x() > nearest_x + options_.gap_end_m ||
        std::abs(p.y()) > options_.window_across_m)
      continue;
    ahead.push_back(p);
    observed_ahead += points_[i].observations;
  }
  if (observed_ahead < options_.min_points) return std::nullopt;
  const std::optional<CurveModel> joined = line_after_arc(course, ahead);
  if (!joined || runs_against_the_vehicle(*joined)) return std::nullopt;
  return with_model(in_view, *joined);
}

std::optional<CurveModel> PathMemory::line_after_arc(
    const CurveModel& arc, const std::vector<Eigen::Vector2d>& ahead) const {
  // The line through the points ahead (their principal direction, oriented along the arc).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : ahead) mean += p;
  mean /= static_cast<double>(ahead.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : ahead) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
  Eigen::Vector2d direction = eigen.eigenvectors().col(1);
  if (direction.dot(arc.prepared().unit_direction_at(mean)) < 0.0) direction = -direction;
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  double residual = 0.0;
  for (const Eigen::Vector2d& p : ahead)
    residual = std::max(residual, std::abs(normal.dot(p - mean)));
  if (residual > 3.0 * options_.corner_max_rms_m) return std::nullopt;  // not straight
  // The arc's centre lies its radius from that line, on the arc's inner side (the line is tangent
  // to it), within bridge_arc_meets_m; the tangent point lies behind the points ahead (not
  // beyond them: there the line would start where tape is already remembered off it).
  const double k = arc.curvature_1_m;
  const Eigen::Vector2d centre = arc.foot_point() + arc.normal() / k;
  const double centre_side = normal.dot(centre - mean);  // + : left of the line
  if (std::abs(std::abs(centre_side) - 1.0 / std::abs(k)) > options_.bridge_arc_meets_m ||
      centre_side * k <= 0.0)
    return std::nullopt;
  const Eigen::Vector2d touch = centre - centre_side * normal;
  const double touch_along = direction.dot(touch - mean);
  if (touch_along > 0.0) return std::nullopt;  // the line starts ahead of the points ahead
  // Under the vehicle: the line once past the tangent point, else the arc. The arc carried on
  // from where it was last measured may have drifted off the line by then (its curvature read
  // from a short stretch, the odometry since): where the circle tangent to the course there and
  // to the line touches the line behind the points ahead, that circle (corner_into_line).
  const double origin_along = direction.dot(-mean);
  if (origin_along < touch_along) {
    if (options_.corner_into_line) {
      if (const std::optional<CurveModel> fillet = arc_into_line(mean, direction)) return *fillet;
    }
    return arc;
  }
  return curve_through_point(mean, std::atan2(direction.y(), direction.x()), 0.0);
}

std::optional<CurveModel> PathMemory::arc_into_line(const Eigen::Vector2d& line_point,
                                                    const Eigen::Vector2d& line_direction) const {
  if (!last_corner_course_) return std::nullopt;
  const Eigen::Vector2d in = vehicle_.inverse().transform(last_corner_course_->foot_m);
  const double in_heading_rad = last_corner_course_->heading_rad - vehicle_.yaw_rad;
  const double out_heading_rad = std::atan2(line_direction.y(), line_direction.x());
  const double turn_rad = wrap_angle_rad(out_heading_rad - in_heading_rad);
  // Where the course's tangent meets the line: d_in ahead of the course's point, d_out behind
  // the line's point; the circle tangent to both at d_in from the meeting point (the course's
  // point on it) touches the line behind its point where d_in <= d_out.
  const std::optional<LinesMeet> meets =
      where_lines_meet(in, in_heading_rad, line_point, out_heading_rad);
  if (!meets || !(meets->d_in_m > 0.0) || meets->d_in_m > meets->d_out_m) return std::nullopt;
  const double d_in = meets->d_in_m;
  // Its curvature near the course's (within a third): else the course or the line is not the
  // corner's.
  const double k_1_m = std::tan(0.5 * std::abs(turn_rad)) / d_in;
  if (std::abs(k_1_m - std::abs(last_corner_course_->curvature_1_m)) >
      std::abs(last_corner_course_->curvature_1_m) / 3.0)
    return std::nullopt;
  const std::optional<CurveModel> fillet =
      corner_fillet(in, in_heading_rad, line_point, out_heading_rad);
  if (!fillet || runs_against_the_vehicle(*fillet)) return std::nullopt;
  return fillet;
}

std::optional<LineMeasurement> PathMemory::from_tape_ahead(
    const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle,
    std::optional<double> ahead_before_rad) const {
  // Not in the memory's warm-up (there the line in view carried back is what the memory has).
  if (!last_course_) return std::nullopt;
  // In a frame along the tape ahead read the frame before, else along the line in view's
  // direction at the origin (then turned by the fit's slope, up to twice, as at_origin does): the
  // remembered tape nearest ahead of the origin.
  double frame_rad = ahead_before_rad ? wrap_angle_rad(*ahead_before_rad - vehicle_.yaw_rad)
                                      : -in_view.e_theta_rad;
  std::optional<JoinedArcs> fit;
  double kept = 0.0;  // the fraction of the points the fit kept (the rest: another tape)
  JoinedArcsOptions one_piece;
  one_piece.both_sides = false;
  one_piece.joint = false;
  for (int pass = 0;; ++pass) {
    const Turn to_frame(-frame_rad);
    std::vector<Eigen::Vector2d> reach, local;
    std::vector<double> reach_weights, weights;  // each point's observations
    double nearest_m = std::numeric_limits<double>::infinity();
    int behind = 0;
    for (size_t i = 0; i < in_vehicle.size(); ++i) {
      const Eigen::Vector2d q = to_frame(in_vehicle[i]);
      if (q.x() <= 0.0 && q.x() >= -options_.window_m &&
          std::abs(q.y()) <= options_.window_across_m)
        behind += points_[i].observations;
      if (q.x() <= 0.0 || q.x() > options_.ahead_max_gap_m + options_.ahead_span_m ||
          std::abs(q.y()) > options_.window_across_m)
        continue;
      reach.push_back(q);
      reach_weights.push_back(points_[i].observations);
      nearest_m = std::min(nearest_m, q.x());
    }
    if (!(nearest_m <= options_.ahead_max_gap_m) || behind >= options_.side_points)
      return std::nullopt;
    double observed = 0.0;
    for (size_t i = 0; i < reach.size(); ++i) {
      if (reach[i].x() > nearest_m + options_.ahead_span_m) continue;
      local.push_back(reach[i]);
      weights.push_back(reach_weights[i]);
      observed += reach_weights[i];
    }
    if (observed < options_.min_points) return std::nullopt;
    double far_m = nearest_m;
    for (const Eigen::Vector2d& q : local) far_m = std::max(far_m, q.x());
    if (far_m - nearest_m < 0.5 * options_.ahead_span_m) return std::nullopt;
    fit = fit_joined_arcs(local, weights, one_piece);
    if (!fit) return std::nullopt;
    kept = static_cast<double>(fit->points) / observed;
    if (std::abs(fit->slope) < 0.02 || pass == 2) break;
    frame_rad += std::atan(fit->slope);
  }
  if (fit->rms_m > options_.ahead_max_rms_m || kept < options_.ahead_min_kept ||
      fit->points < 3 * options_.min_points ||
      std::abs(fit->curvature_1_m) > options_.max_curvature_1_m)
    return std::nullopt;
  const CurveModel fitted =
      curve_in_frame(frame_rad, fit->offset_m, fit->slope, fit->curvature_1_m);
  // The course last measured under the vehicle, carried forward, is surer than the tape ahead
  // where they disagree by more than its curvature can explain over the distance driven since (a
  // junction's other leg remembered; a fork's, beside the memory restarted).
  if (!near_course_carried_forward(fitted)) return std::nullopt;
  LineMeasurement m = with_model(in_view, fitted);
  m.extrapolated = true;
  return m;
}

void PathMemory::add_preview(const std::vector<Eigen::Vector2d>& in_vehicle,
                             LineMeasurement* m) const {
  // Walk along the tape from the foot point: at each step, the points within the window in a
  // frame along the tape there give the local curvature (and correct the walk's position and
  // direction); the first change that holds for two windows is where the curvature changes.
  const CurveModel origin = model_of(*m);
  Eigen::Vector2d at = origin.foot_point();
  double heading = origin.heading_rad;
  double curvature = origin.curvature_1_m;
  // NaN: none yet (std::optional here trips GCC 12's maybe-uninitialized warning).
  double first_change_s = std::numeric_limits<double>::quiet_NaN();
  double first_break_s = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> ahead;
  const double h = options_.preview_half_window_m, across_m = 0.02;
  const PointGrid grid(in_vehicle, std::hypot(h, across_m));
  std::vector<Eigen::Vector2d> local;
  std::vector<double> weights;  // each local point's observations
  for (double s = options_.preview_step_m;; s += options_.preview_step_m) {
    // Advance along the arc of the current curvature.
    const double turn = curvature * options_.preview_step_m;
    const double chord = std::abs(curvature) > 1e-9 ? 2.0 * std::sin(0.5 * turn) / curvature
                                                    : options_.preview_step_m;
    at += chord * Eigen::Vector2d(std::cos(heading + 0.5 * turn), std::sin(heading + 0.5 * turn));
    heading += turn;
    // The points within the window (in the grid's order: the fit orders them along x), looked
    // at only within its bounding box (and a rounding margin).
    const double c = std::abs(std::cos(heading)), sn = std::abs(std::sin(heading));
    const Eigen::Vector2d reach(c * h + sn * across_m + 1e-9, sn * h + c * across_m + 1e-9);
    const Eigen::Vector2d box_lo = at - reach, box_hi = at + reach;
    local.clear();
    weights.clear();
    double hi = -1.0;
    const Turn to_window(-heading);
    grid.for_each_near_in_box(at, box_lo, box_hi, [&](size_t j) {
      const Eigen::Vector2d& p = in_vehicle[j];
      if (p.x() < box_lo.x() || p.x() > box_hi.x() || p.y() < box_lo.y() || p.y() > box_hi.y())
        return;
      const Eigen::Vector2d q = to_window(p - at);
      if (std::abs(q.x()) > h || std::abs(q.y()) > across_m) return;
      local.push_back(q);
      weights.push_back(points_[j].observations);
      hi = std::max(hi, q.x());
    });
    if (hi < 0.5 * h) break;  // the evidence ends here
    // One piece first (no breakpoint search): the joined arcs only where its curvature
    // suggests a change (a window across a joint reads about the mean of its two pieces).
    JoinedArcsOptions one_piece;
    one_piece.joint = false;
    std::optional<JoinedArcs> fit = fit_joined_arcs(local, weights, one_piece);
    if (fit && std::abs(fit->curvature_1_m - origin.curvature_1_m) >
                   options_.preview_suspect_fraction * options_.preview_change_1_m)
      fit = fit_joined_arcs(local, weights);
    if (!fit) break;
    at += Turn(heading)({0.0, fit->offset_m});
    heading += std::atan(fit->slope);
    curvature = fit->curvature_1_m;
    // A change is larger than preview_change_1_m and than the window's own uncertainty (worn
    // tape's wear shifts the centre line over millimetres: one window's curvature is uncertain
    // by 0.3-1 1/m there, and the controllers would turn for each such reading).
    bool changed = std::abs(curvature - origin.curvature_1_m) > options_.preview_change_1_m;
    if (changed) {
      JoinedArcsOptions with_sigma;
      with_sigma.curvature_sigma = true;
      const std::optional<JoinedArcs> again = fit_joined_arcs(local, weights, with_sigma);
      changed = again && std::abs(curvature - origin.curvature_1_m) >
                             options_.preview_change_sigmas * again->curvature_sigma_1_m;
    }
    if (!changed) {
      first_change_s = first_break_s = std::numeric_limits<double>::quiet_NaN();
      ahead.clear();
      continue;
    }
    if (std::isnan(first_change_s)) {
      first_change_s = s;
      if (fit->break_x_m) first_break_s = s + *fit->break_x_m;
    }
    ahead.push_back(curvature);
    if (ahead.size() >= 2) break;
  }
  if (ahead.size() < 2) return;
  // Where it changes: the breakpoint the window saw, else half a step before the window.
  m->curvature_change_m = !std::isnan(first_break_s)
                              ? std::max(0.0, first_break_s)
                              : std::max(0.0, first_change_s - 0.5 * options_.preview_step_m);
  m->curvature_ahead_1_m = ahead.back();
}

std::vector<bool> PathMemory::on_other_lines(const LineDetection& detection,
                                             const std::vector<Eigen::Vector2d>& points) {
  std::vector<bool> on_other(points.size(), false);
  if (detection.lines.size() < 2) return on_other;
  std::vector<CurveModel::Prepared> curves;  // prepared once for all the points
  for (const DetectedLine& line : detection.lines) curves.push_back(line.model.prepared());
  const DetectedLine& followed = detection.lines[detection.followed];
  // How far from the vehicle a line's evidence starts and ends.
  auto reach_m = [](const DetectedLine& line) {
    const double start = line.model.point_at(line.s_min_m).norm();
    const double end = line.model.point_at(line.s_max_m).norm();
    return std::make_pair(std::min(start, end), std::max(start, end));
  };
  const double margin_m = std::max(followed.width_m, 0.01);
  // Without a junction, a line whose evidence ends before the followed line's begins is the way
  // the vehicle came too (a corner rounder than its tape is wide, R 0.11 m for 15 mm tape, shows
  // its legs as two lines that meet in no junction: the incoming leg remembered up to the corner
  // was forgotten, and with it the tape under the vehicle there, agv evaluate seed 45 sequence 9).
  std::vector<bool> came_by(detection.lines.size(), false);
  if (!detection.junction) {
    const double followed_begins_m = reach_m(followed).first;
    for (size_t other = 0; other < detection.lines.size(); ++other)
      came_by[other] = reach_m(detection.lines[other]).second <= followed_begins_m + margin_m;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    if (std::abs(curves[detection.followed].signed_distance(p)) < 0.5 * followed.width_m) continue;
    // Nearer the vehicle than the junction: the way it came (a corner's incoming leg, a fork's
    // stem), not a way it leaves by.
    if (detection.junction && p.norm() < detection.junction->point_m.norm() - margin_m) continue;
    for (size_t other = 0; other < detection.lines.size() && !on_other[i]; ++other) {
      if (static_cast<int>(other) == detection.followed || came_by[other]) continue;
      const DetectedLine& line = detection.lines[other];
      const double s = curves[other].arc_position(p);
      on_other[i] = s >= line.s_min_m && s <= line.s_max_m &&
                    std::abs(curves[other].signed_distance(p)) < 0.5 * line.width_m;
    }
  }
  return on_other;
}

std::vector<bool> PathMemory::off_the_way_ahead(const LineDetection& detection,
                                                const std::vector<Eigen::Vector2d>& points) const {
  // Where a fork's legs merge into one band wider than the tape, the band's chords give no
  // evidence of either leg, and the full search may follow the branch until the legs part: the
  // memory then holds the branch ahead of the vehicle and a hole where the way taken runs, and
  // read the branch at the origin once the vehicle got there (agv evaluate seed 33 sequence 11:
  // up to 66 mm off over 0.25 m). Once the line in view is the way taken, it carried back meets
  // the tape under the vehicle; the remembered tape between that leaves its course is the branch.
  std::vector<bool> off_way(points.size(), false);
  if (!last_course_ || odometer_m_ - last_course_->odometer_m > options_.way_recent_m)
    return off_way;
  const CurveModel under_vehicle = last_course_now();
  const DetectedLine& followed = detection.lines[detection.followed];
  const CurveModel way = followed.model.oriented_like(under_vehicle, Eigen::Vector2d::Zero());
  if (std::abs(way.e_d_m - under_vehicle.e_d_m) > options_.way_agreement_m ||
      std::abs(wrap_angle_rad(way.heading_rad - under_vehicle.heading_rad)) >
          options_.way_agreement_rad)
    return off_way;
  const CurveModel::Prepared course = way.prepared();
  // From the origin's foot point to the evidence's far end, along the way (as oriented).
  const double from_m = course.arc_position(followed.model.point_at(followed.s_min_m));
  const double to_m = course.arc_position(followed.model.point_at(followed.s_max_m));
  const double far_m = std::max(from_m, to_m);
  // Only on the side of the way not taken: right of a left choice, left of a right one; going
  // straight, not on the side the line in view turns away from (a branch followed where the way
  // straight on was chosen, the tape straight on remembered beside it: agv evaluate seed 23
  // sequence 1, the branch taken for the way when that was forgotten, 120 mm off).
  const double away_1_m = options_.way_straight_turn_1_m;
  const bool left_not_taken =
      detection.branch == BranchChoice::kRight ||
      (detection.branch == BranchChoice::kStraight && way.curvature_1_m >= -away_1_m);
  const bool right_not_taken =
      detection.branch == BranchChoice::kLeft ||
      (detection.branch == BranchChoice::kStraight && way.curvature_1_m <= away_1_m);
  // Across the way (positive on the left); along it only where some point lies past the gate
  // (most frames none: an arc position is an arc tangent).
  std::vector<double> across(points.size());
  bool any_past_gate = false;
  for (size_t i = 0; i < points.size(); ++i) {
    across[i] = course.signed_distance(points[i]);
    any_past_gate = any_past_gate || std::abs(across[i]) > options_.way_gate_m;
  }
  if (!any_past_gate) return off_way;
  std::vector<double> along(points.size());
  for (size_t i = 0; i < points.size(); ++i) along[i] = course.arc_position(points[i]);
  for (const double side : {1.0, -1.0}) {
    if (!(side > 0.0 ? left_not_taken : right_not_taken)) continue;
    // The branch's points past the gate; then where it left the way.
    double first_off_m = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < points.size(); ++i) {
      if (along[i] <= 0.0 || along[i] > far_m || side * across[i] <= options_.way_gate_m) continue;
      off_way[i] = true;
      first_off_m = std::min(first_off_m, along[i]);
    }
    if (!std::isfinite(first_off_m)) continue;
    const std::optional<TangentDeparture> departure = tangent_departure(
        along, across, off_way, side, first_off_m, options_.way_stub_fit_m, options_.way_gate_m);
    // Found behind the origin (31/7: points of the way itself, the course carried back 1 mm off
    // them), it is no branch leaving ahead.
    if (!departure || departure->from_m <= 0.0) continue;
    // Between where it leaves and the gate, its points lie nearer the branch than the way: more
    // than half its offset there across, where that is over way_stub_min_m.
    for (size_t i = 0; i < points.size(); ++i) {
      if (off_way[i] || along[i] <= departure->from_m || along[i] >= first_off_m) continue;
      const double branch_m = departure->offset_m(along[i]);
      off_way[i] = branch_m > options_.way_stub_min_m && side * across[i] > 0.5 * branch_m;
    }
  }
  return off_way;
}

std::vector<Eigen::Vector2d> PathMemory::evidence_of(const LineDetection& detection) {
  // The centres of the chords with both edges on the followed tape, about as wide as the tape
  // has been (where another tape leaves or meets it, a chord from this tape's edge to the
  // other's has its centre on neither, and the line's own median width may be the merged one),
  // and not within a tape width of another line in view.
  const DetectedLine& line = detection.lines[detection.followed];
  // A line of unknown width (0: no chord with both edges on it, a fit to single edges) says
  // nothing of the tape's width, and its chords' middles are not the tape's centre: no evidence
  // until a width is known (remembered from it, 6 mm for 97 mm tape, every chord of that tape
  // was refused from then on).
  if (!(tape_width_m_ > 0.0)) {
    if (!(line.width_m > 0.0)) return {};
    tape_width_m_ = line.width_m;
  }
  std::vector<double> widths;
  // Chords across the overlap of a junction's legs first: a chord only a little wider than the
  // tape there has its midpoint off the followed leg's centre by half the excess.
  std::vector<bool> overlapping;
  const std::vector<Eigen::Vector2d> overlap = overlap_centres(detection, &overlapping);
  const std::vector<Eigen::Vector2d> merged = overlap_centres_along_course(detection, &overlapping);
  std::vector<Eigen::Vector2d> evidence = chord_centres(detection, overlapping, &widths);
  // A width taken from a first frame that saw only part of the tape would refuse every chord of
  // the whole tape from then on (98 mm tape remembered as 81 mm: no evidence for metres): where
  // the followed line keeps showing one other width and none of its chords is accepted, for
  // relatch_frames frames more than those of a third width (a majority vote: the full search
  // every 10th frame finding another line, a shadow's edge, no longer starts the count again),
  // that width is the tape's. A frame whose line's width is unknown does not vote.
  const bool known_width = line.width_m > 0.0;
  const bool disagrees =
      known_width && evidence.size() < 3 &&
      std::abs(line.width_m - tape_width_m_) > options_.chord_width_tolerance * tape_width_m_;
  const bool same_as_before = std::abs(line.width_m - disagreeing_width_m_) <=
                              options_.chord_width_tolerance * line.width_m;
  if (!disagrees) {
    if (known_width) disagreeing_frames_ = 0;
  } else if (same_as_before) {
    ++disagreeing_frames_;
  } else if (disagreeing_frames_ > 0) {
    --disagreeing_frames_;
  } else {
    disagreeing_width_m_ = line.width_m;
    disagreeing_frames_ = 1;
  }
  if (disagreeing_frames_ >= options_.relatch_frames) {
    tape_width_m_ = line.width_m;
    disagreeing_frames_ = 0;
    widths.clear();
    evidence = chord_centres(detection, overlapping, &widths);
  }
  evidence.insert(evidence.end(), overlap.begin(), overlap.end());
  evidence.insert(evidence.end(), merged.begin(), merged.end());
  // The tape's width follows what the accepted evidence shows (slowly: a worn stretch or a
  // merged chord does not move it).
  if (widths.size() >= 3) {
    std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
    tape_width_m_ += 0.2 * (widths[widths.size() / 2] - tape_width_m_);
  }
  return evidence;
}

std::vector<Eigen::Vector2d> PathMemory::overlap_centres(const LineDetection& detection,
                                                         std::vector<bool>* used) const {
  std::vector<Eigen::Vector2d> centres;
  used->assign(detection.chords.size(), false);
  const double w = tape_width_m_;
  if (!detection.junction || detection.lines.size() < 2 || !(w > 0.0)) return centres;
  const DetectedLine& line = detection.lines[detection.followed];
  // The followed leg's side of each other line (+1 left, -1 right; 0: not a tape width clear of
  // it): where its evidence ends farthest from the vehicle.
  const Eigen::Vector2d start = line.model.point_at(line.s_min_m);
  const Eigen::Vector2d end = line.model.point_at(line.s_max_m);
  const Eigen::Vector2d far_end = start.norm() > end.norm() ? start : end;
  std::vector<CurveModel::Prepared> curves;
  std::vector<double> sides;
  for (const DetectedLine& other_line : detection.lines) {
    curves.push_back(other_line.model.prepared());
    const double side_distance = curves.back().signed_distance(far_end);
    sides.push_back(std::abs(side_distance) < w ? 0.0 : side_distance > 0.0 ? 1.0 : -1.0);
  }
  const CurveModel::Prepared& followed = curves[detection.followed];
  for (int index : line.chords) {
    const Chord& chord = detection.chords[index];
    const Eigen::Vector2d ahead = followed.unit_direction_at(chord.centre());
    const Eigen::Vector2d normal(-ahead.y(), ahead.x());
    const double width_m = std::abs(normal.dot(chord.a - chord.b));
    if (width_m <= w + kOverlapMin_m || width_m >= 2.0 * w) continue;
    // The other leg the chord overlaps: within a tape width of it, where its evidence is.
    for (size_t other = 0; other < detection.lines.size(); ++other) {
      if (static_cast<int>(other) == detection.followed || sides[other] == 0.0) continue;
      const DetectedLine& other_line = detection.lines[other];
      const CurveModel::Prepared& curve = curves[other];
      const double s = curve.arc_position(chord.centre());
      if (s < other_line.s_min_m - w || s > other_line.s_max_m + w ||
          std::abs(curve.signed_distance(chord.centre())) > w)
        continue;
      const double side = sides[other];
      const double da = side * curve.signed_distance(chord.a);
      const double db = side * curve.signed_distance(chord.b);
      const Eigen::Vector2d& outer = da > db ? chord.a : chord.b;
      const Eigen::Vector2d& inner = da > db ? chord.b : chord.a;
      // The inner edge is the other leg's far edge, half a width beyond its centre.
      if (std::abs(std::min(da, db) + 0.5 * w) > 0.25 * w) continue;
      const double inwards = normal.dot(inner - outer) > 0.0 ? 1.0 : -1.0;
      const Eigen::Vector2d centre = outer + inwards * 0.5 * w * normal;
      if (std::abs(followed.signed_distance(centre)) > w) continue;  // not the followed leg
      centres.push_back(centre);
      (*used)[index] = true;
      break;
    }
  }
  return centres;
}

std::vector<Eigen::Vector2d> PathMemory::overlap_centres_along_course(
    const LineDetection& detection, std::vector<bool>* used) const {
  const double w = tape_width_m_;
  if (!(w > 0.0) || !last_course_) return {};
  const bool straight = detection.branch == BranchChoice::kStraight;
  const bool chosen_left = detection.branch == BranchChoice::kLeft;
  const DetectedLine& line = detection.lines[detection.followed];
  const CurveModel::Prepared model = line.model.prepared();
  CurveModel course_model = last_course_now();  // along the travel
  if (straight && std::abs(course_model.curvature_1_m) < options_.straight_course_line_below_1_m)
    course_model.curvature_1_m = 0.0;
  const CurveModel::Prepared course = course_model.prepared();
  std::vector<bool> clean(detection.chords.size(), false);
  for (int index : line.clean_chords) clean[index] = true;
  const double wider_than_tape_m = (1.0 + options_.chord_width_tolerance) * w;
  const double edge_tolerance_m = options_.overlap_edge_tolerance * w;
  struct Candidate {
    int index;
    double along_m, leaving_offset_m;
    Eigen::Vector2d centre;
    bool leaves_left;
  };
  // The chords whose leg leaving the course is the one taken (its centre half a width in from
  // its outer edge), and those whose leg leaving is the other (the one taken runs on along the
  // course: its centre half a width in from its edge on the course's edge; straight on, every
  // leg leaving); with the counts of each, and of those leaving left, before their centres are
  // checked against the line in view.
  std::vector<Candidate> taken_leaves, other_leaves;
  int taken_leaving = 0, other_leaving = 0, leaving_left = 0;
  const double slightly_wider_m =
      w + std::max(options_.overlap_slightly_wider_m, options_.overlap_slightly_wider * w);
  for (int index : line.chords) {
    if ((*used)[index]) continue;
    const Chord& chord = detection.chords[index];
    const Eigen::Vector2d across = chord.a - chord.b;
    const Eigen::Vector2d ahead = course.unit_direction_at(chord.centre());
    const Eigen::Vector2d left(-ahead.y(), ahead.x());
    const Eigen::Vector2d in_view = model.unit_direction_at(chord.centre());
    const double width_m = std::abs(left.dot(across));
    const double width_in_view_m = std::abs(in_view.x() * across.y() - in_view.y() * across.x());
    const double da = course.signed_distance(chord.a), db = course.signed_distance(chord.b);
    if (!(da * db < 0.0)) continue;  // both edges on one side of the course
    bool a_on = false;               // which edge lies on the course's edge
    if (!clean[index]) {
      // One edge on the course's edge, the other beyond its other edge: a leg leaving there.
      if (width_m <= wider_than_tape_m || width_m >= 2.0 * w ||
          width_in_view_m <= wider_than_tape_m)
        continue;
      a_on = std::abs(std::abs(da) - 0.5 * w) <= edge_tolerance_m;
      const bool b_on = std::abs(std::abs(db) - 0.5 * w) <= edge_tolerance_m;
      if (a_on == b_on || std::abs(a_on ? db : da) <= 0.5 * w + edge_tolerance_m) continue;
    } else {
      // A clean chord only a little wider than the tape (the overlap's first stretch, where its
      // midpoint would run at half the leaving leg's offset): the edge nearer the course's edge
      // on it, the other beyond the course's other edge by more than half the least excess and
      // twice the first edge's distance from its own.
      if (width_m <= slightly_wider_m || width_in_view_m <= slightly_wider_m) continue;
      const double a_out = std::abs(da) - 0.5 * w, b_out = std::abs(db) - 0.5 * w;
      a_on = std::abs(a_out) < std::abs(b_out);
      const double on_out = a_on ? a_out : b_out, off_out = a_on ? b_out : a_out;
      if (std::abs(on_out) > edge_tolerance_m || off_out <= 0.5 * (slightly_wider_m - w) ||
          off_out <= 2.0 * std::abs(on_out))
        continue;
    }
    const double off_m = a_on ? db : da;
    const double towards_leaving = off_m > 0.0 ? 1.0 : -1.0;
    const bool taken = !straight && (off_m > 0.0) == chosen_left;
    // The leaving leg's outer edge moved half a width back across the course, or the edge on
    // the course's edge moved half a width towards the leaving leg.
    const Eigen::Vector2d centre =
        taken ? Eigen::Vector2d((a_on ? chord.b : chord.a) - towards_leaving * 0.5 * w * left)
              : Eigen::Vector2d((a_on ? chord.a : chord.b) + towards_leaving * 0.5 * w * left);
    ++(taken ? taken_leaving : other_leaving);
    if (off_m > 0.0) ++leaving_left;
    if (std::abs(model.signed_distance(centre)) > w) continue;
    (taken ? taken_leaves : other_leaves)
        .push_back(
            {index, course.arc_position(chord.centre()), std::abs(off_m), centre, off_m > 0.0});
  }
  // Most such chords leave on one side (overlap_same_side of them, at least 3), and their
  // leaving edges run off the course as they go (the offsets' correlation with the distance
  // along it).
  constexpr size_t kMinChords = 3;
  auto agree = [&](const std::vector<Candidate>& found, int leaving_elsewhere) {
    const double agreeing = static_cast<double>(found.size());
    return found.size() >= kMinChords &&
           agreeing >= options_.overlap_same_side * (agreeing + leaving_elsewhere);
  };
  const std::vector<Candidate>* agreeing_chords = nullptr;
  if (straight) {
    // Straight on: the legs leaving on the side most leave on, against those on the other; not
    // on the outside of an arc's bend.
    const int leaving_right = other_leaving - leaving_left;
    const bool left = leaving_left >= leaving_right;
    const double bend_1_m = course_model.curvature_1_m;
    if (std::abs(bend_1_m) >= options_.straight_course_arc_from_1_m && (bend_1_m > 0.0) != left)
      return {};
    std::erase_if(other_leaves, [left](const Candidate& c) { return c.leaves_left != left; });
    if (agree(other_leaves, left ? leaving_right : leaving_left)) agreeing_chords = &other_leaves;
  } else if (agree(taken_leaves, other_leaving)) {
    agreeing_chords = &taken_leaves;
  } else if (agree(other_leaves, taken_leaving)) {
    agreeing_chords = &other_leaves;
  }
  if (!agreeing_chords) return {};
  const std::vector<Candidate>& candidates = *agreeing_chords;
  const double agreeing = static_cast<double>(candidates.size());
  double mean_along = 0.0, mean_offset = 0.0;
  for (const Candidate& c : candidates) {
    mean_along += c.along_m / agreeing;
    mean_offset += c.leaving_offset_m / agreeing;
  }
  double s_ao = 0.0, s_aa = 0.0, s_oo = 0.0;
  for (const Candidate& c : candidates) {
    const double da = c.along_m - mean_along, doff = c.leaving_offset_m - mean_offset;
    s_ao += da * doff;
    s_aa += da * da;
    s_oo += doff * doff;
  }
  if (!(s_ao > 0.0) || s_ao < options_.overlap_min_correlation * std::sqrt(s_aa * s_oo)) return {};
  // Straight on (on every path, junction or none), not a widening here and there: the agreeing
  // chords are most of the line's across the stretch they span.
  if (straight) {
    const auto [first, last] = std::minmax_element(
        candidates.begin(), candidates.end(),
        [](const Candidate& a, const Candidate& b) { return a.along_m < b.along_m; });
    const double from_m = first->along_m, to_m = last->along_m;
    const auto spanned = std::count_if(line.chords.begin(), line.chords.end(), [&](int index) {
      const double along_m = course.arc_position(detection.chords[index].centre());
      return along_m >= from_m && along_m <= to_m;
    });
    if (agreeing < options_.straight_min_coverage * static_cast<double>(spanned)) return {};
  }
  std::vector<Eigen::Vector2d> centres;
  for (const Candidate& c : candidates) {
    centres.push_back(c.centre);
    (*used)[c.index] = true;
  }
  return centres;
}

std::vector<Eigen::Vector2d> PathMemory::chord_centres(const LineDetection& detection,
                                                       const std::vector<bool>& overlapping,
                                                       std::vector<double>* widths) const {
  const DetectedLine& line = detection.lines[detection.followed];
  const std::vector<int>& chords = static_cast<int>(line.clean_chords.size()) >= options_.min_points
                                       ? line.clean_chords
                                       : line.chords;
  const CurveModel::Prepared model = line.model.prepared();
  std::vector<CurveModel::Prepared> others;  // every line, prepared once
  for (const DetectedLine& other : detection.lines) others.push_back(other.model.prepared());
  std::vector<Eigen::Vector2d> evidence;
  for (int index : chords) {
    if (overlapping[index]) continue;
    const Chord& chord = detection.chords[index];
    const Eigen::Vector2d middle = chord.centre();
    const Eigen::Vector2d ahead = model.unit_direction_at(middle);
    // A scan line crosses a bend obliquely: the middle of its chord lies inside the tape's centre
    // line (by up to w^2 / 8R, 0.07 mm for 25 mm tape on R 0.3 m, and changing from frame to
    // frame with the angle of the crossing). The centre is where the distance from the fitted
    // curve is the mean of the edges' (the same point on a straight tape).
    const double off_centre_m =
        model.signed_distance(middle) -
        0.5 * (model.signed_distance(chord.a) + model.signed_distance(chord.b));
    const Eigen::Vector2d centre = middle - off_centre_m * Eigen::Vector2d(-ahead.y(), ahead.x());
    const double width_m = std::abs(Eigen::Vector2d(-ahead.y(), ahead.x()).dot(chord.a - chord.b));
    if (tape_width_m_ > 0.0 &&
        std::abs(width_m - tape_width_m_) > options_.chord_width_tolerance * tape_width_m_)
      continue;
    bool near_other = false;
    for (size_t other = 0; other < detection.lines.size() && !near_other; ++other) {
      if (static_cast<int>(other) == detection.followed) continue;
      const double d = others[other].signed_distance(centre);
      near_other = std::abs(d) < std::max(tape_width_m_, line.width_m);
    }
    if (near_other) continue;
    evidence.push_back(centre);
    widths->push_back(width_m);
  }
  return evidence;
}

LineMeasurement PathMemory::update(const LineMeasurement& in_view, const LineDetection& detection,
                                   const std::optional<Pose2>& odometry, OdometryKind kind) {
  reading_held_ = false;
  refused_because_.clear();
  const LineMeasurement m = read(in_view, detection, odometry, kind);  // no odometry: reset
  if (odometry && m.line_found && !reading_held_) {
    const std::optional<double> offset_m = offset_from_recent_reading_m(m);
    last_reading_confirmed_ = offset_m && *offset_m <= options_.hold_course_offset_m;
    last_reading_ = course_of(m);
  }
  if (!odometry) return m;  // nothing to carry a refused line forward with
  return confirmed(m);
}

PathMemory::Course PathMemory::course_of(const LineMeasurement& m) const {
  return Course{vehicle_.transform(model_of(m).foot_point()), vehicle_.yaw_rad - m.e_theta_rad,
                m.curvature_1_m, odometer_m_};
}

LineMeasurement PathMemory::confirmed(const LineMeasurement& m) {
  if (!m.line_found) {
    ++frames_without_line_;
    return m;
  }
  // Blind: frames without a line since the last one reported (not merely frames far apart).
  const bool after_blind = frames_without_line_ > 0 && reported_at_m_ &&
                           odometer_m_ - *reported_at_m_ >= options_.confirm_after_blind_m;
  if (m.extrapolated && after_blind) {
    const CurveModel seen = model_of(m);
    bool agrees = false;
    if (unconfirmed_) {
      const CurveModel before = course_now(*unconfirmed_);
      agrees = std::abs(seen.e_d_m - before.e_d_m) <= options_.confirm_offset_m &&
               std::abs(wrap_angle_rad(seen.heading_rad - before.heading_rad)) <=
                   options_.confirm_heading_rad;
    }
    if (!agrees) {
      unconfirmed_ = course_of(m);
      refused_because_ =
          "line found again after a blind stretch and carried back from the view: not yet "
          "confirmed by the next frame";
      LineMeasurement refused;
      refused.stamp_s = m.stamp_s;
      ++frames_without_line_;
      return refused;
    }
  }
  unconfirmed_.reset();
  reported_at_m_ = odometer_m_;
  frames_without_line_ = 0;
  return m;
}

LineMeasurement PathMemory::read(const LineMeasurement& in_view, const LineDetection& detection,
                                 const std::optional<Pose2>& odometry, OdometryKind kind) {
  LineMeasurement carried_back = in_view;
  carried_back.extrapolated = in_view.line_found;
  // From one frame's from_tape_ahead to the next's only.
  const std::optional<double> ahead_before_rad = std::exchange(ahead_heading_rad_, std::nullopt);
  if (!odometry) {
    reset();
    return carried_back;
  }
  // The odometry's step, and the vehicle's move in its frame now (from where it was to here).
  const Pose2 step = last_odometry_ ? last_odometry_->inverse().compose(*odometry) : Pose2{};
  const double travelled_m = step.translation().norm();
  const Eigen::Vector2d moved_m = Turn(-step.yaw_rad)(step.translation());
  if (travelled_m > options_.max_jump_m) reset();
  odometer_m_ += travelled_m;
  last_odometry_ = odometry;
  ++frame_;
  vehicle_ = correction_.compose(*odometry);
  grow_misalignment(travelled_m, moved_m, kind);  // every frame, also those without tape in view
  // The rotation the wheel odometry's yaw drift (as estimated) added since the last frame, and
  // the part of its move its distance error (as estimated) added, taken out (about the
  // vehicle's origin, as a registration's correction is).
  if (kind == OdometryKind::wheels && !points_.empty() &&
      (yaw_drift_rad_per_m_ != 0.0 || distance_error_ != 0.0)) {
    const Eigen::Vector2d not_driven_m = distance_error_ * moved_m;
    vehicle_ = vehicle_.compose(
        Pose2{not_driven_m.x(), not_driven_m.y(), yaw_drift_rad_per_m_ * travelled_m}.inverse());
    correction_ = vehicle_.compose(odometry->inverse());
  }
  odometry_kind_ = kind;
  recent_headings_.emplace_back(odometer_m_, vehicle_.yaw_rad);
  view_before_ = std::exchange(
      view_, in_view.line_found ? std::optional<Course>(course_of(in_view)) : std::nullopt);
  while (odometer_m_ - recent_headings_.front().first > options_.bridge_after_corner_m)
    recent_headings_.pop_front();
  if (!in_view.line_found) return remembered_only(in_view, detection);
  if (detection.followed < 0 || detection.followed >= static_cast<int>(detection.lines.size()))
    return in_view;

  std::vector<Eigen::Vector2d> in_vehicle = points_in_vehicle_frame();
  const std::vector<Eigen::Vector2d> evidence = evidence_of(detection);
  register_to(evidence, detection.lines[detection.followed].model, travelled_m, &in_vehicle);
  correction_ = vehicle_.compose(odometry->inverse());

  // Keep what is not too far behind and not too old; add this frame's evidence.
  std::vector<Point> kept;
  kept.reserve(points_.size());
  const std::vector<bool> on_other = on_other_lines(detection, in_vehicle);
  const std::vector<bool> off_way = off_the_way_ahead(detection, in_vehicle);
  for (size_t i = 0; i < points_.size() && i < in_vehicle.size(); ++i) {
    if (in_vehicle[i].x() < -options_.keep_behind_m) continue;
    if (points_[i].frame <= frame_ - options_.keep_frames) continue;
    if (odometer_m_ - points_[i].seen_at_m > options_.keep_travel_m) continue;
    if (on_other[i] || off_way[i]) continue;
    kept.push_back(points_[i]);
  }
  points_ = std::move(kept);
  in_vehicle = points_in_vehicle_frame();
  add_evidence(evidence, &in_vehicle);
  std::optional<LineMeasurement> m = at_origin(in_view, in_vehicle);
  if (!m) m = across_gap(in_view, in_vehicle);
  if (!m) m = through_gap(in_view, in_vehicle);
  // Inside a corner never seen whole: after around_corner (a corner whose arc was measured in
  // part is that arc's: seed 8, sequence 11, 84 mm tape, 1.0 -> 2.9 mm read across it first),
  // except from the frame read across it on (the course that reading left is no arc measured,
  // for around_corner to carry on: seed 45, sequence 9, 0.5 -> 2.6 mm).
  bool off_corner = false, across_corner = false;
  if (!m && !read_across_corner_) {
    m = around_corner(in_view, in_vehicle);
    off_corner = m.has_value();
  }
  if (!m) {
    m = across_gap(in_view, in_vehicle, true);
    across_corner = m.has_value();
  }
  read_off_corner_ = off_corner;
  read_across_corner_ = across_corner;
  if (!m) {
    // Not yet on remembered tape: what is remembered nearest ahead, carried back.
    if (std::optional<LineMeasurement> ahead =
            from_tape_ahead(in_view, in_vehicle, ahead_before_rad)) {
      tape_heading_rad_.reset();
      ahead_heading_rad_ = vehicle_.yaw_rad - ahead->e_theta_rad;
      return *ahead;
    }
  }
  if (m) {
    add_preview(in_vehicle, &*m);
    remember_heading(*m);
    turns_out_of_view_ = turns_out_of_view(detection);
    return *m;
  }
  tape_heading_rad_.reset();
  fit_course_to_its_arc(in_vehicle);
  if (std::optional<LineMeasurement> forward = carried_forward(carried_back)) return *forward;
  if (std::optional<LineMeasurement> held = course_held(carried_back)) return *held;
  if (std::optional<LineMeasurement> held = reading_held(carried_back)) {
    reading_held_ = true;
    return *held;
  }
  const double width_m = carried_back.tape_width_m;
  if (options_.carried_back_width_tolerance > 0.0 && last_course_ && !points_.empty() &&
      tape_width_m_ > 0.0 && width_m > 0.0 &&
      std::abs(width_m - tape_width_m_) > options_.carried_back_width_tolerance * tape_width_m_) {
    char why[160];
    std::snprintf(why, sizeof(why),
                  "line %.1f mm wide, unlike the %.1f mm tape remembered, and no tape remembered "
                  "under the vehicle",
                  1e3 * width_m, 1e3 * tape_width_m_);
    refused_because_ = why;
    LineMeasurement refused;
    refused.stamp_s = carried_back.stamp_s;
    return refused;
  }
  return carried_back;
}

void PathMemory::add_evidence(const std::vector<Eigen::Vector2d>& evidence,
                              std::vector<Eigen::Vector2d>* in_vehicle) {
  const Pose2::Map to_memory = vehicle_.map();
  // The points remembered before this frame (none to fuse into with fuse_m 0), in cells as small
  // as their spread allows a dense grid.
  const std::vector<Eigen::Vector2d> none;
  const std::vector<Eigen::Vector2d>& remembered = options_.fuse_m > 0.0 ? *in_vehicle : none;
  const PointGrid grid(remembered,
                       PointGrid::dense_cell_m(remembered, std::max(options_.fuse_m, 1e-3), 0.0));
  // This frame's evidence first thinned to half the fusing distance: a full search scans every
  // row, and its evidence, 0.4 mm apart, added some 60 points a few centimetres long that the
  // later frames' evidence, 3 mm apart, left alone (agv bench: 312 points remembered, 223 thinned,
  // 194 with tracked frames only; the memory 67 -> 54 us a frame). Thinned to the whole fusing
  // distance, agv evaluate seeds 1-8 read 0.743 deg RMS, not 0.554 (two frames 16-24 mm off at
  // a fork); to half of it 0.545.
  for (const WeightedPoint& cluster : thinned(evidence, 0.5 * options_.fuse_m)) {
    const Eigen::Vector2d& centre = cluster.p;
    const int count = std::min(cluster.count, options_.fuse_max_observations);
    const size_t nearest = grid.nearest_index(*in_vehicle, centre, options_.fuse_m);
    if (nearest == PointGrid::kNone) {
      points_.push_back({to_memory(centre), frame_, odometer_m_, count});
      in_vehicle->push_back(centre);
      continue;
    }
    Point& point = points_[nearest];
    Eigen::Vector2d& p = (*in_vehicle)[nearest];
    const double n = point.observations;
    p = (n * p + count * centre) / (n + count);
    point.p = to_memory(p);
    point.frame = frame_;
    point.seen_at_m = odometer_m_;
    point.observations = std::min(point.observations + count, options_.fuse_max_observations);
  }
}

std::optional<LineMeasurement> PathMemory::course_held(const LineMeasurement& carried_back) const {
  if (!last_course_ || odometer_m_ - last_course_->odometer_m > options_.hold_course_m ||
      std::abs(carried_back.e_d_m - last_course_now().e_d_m) <= options_.hold_course_offset_m)
    return std::nullopt;
  return with_course(carried_back);
}

double PathMemory::offset_from_m(const LineMeasurement& m, const Course& course) const {
  return std::abs(m.e_d_m - course_now(course).e_d_m);
}

std::optional<double> PathMemory::offset_from_recent_reading_m(const LineMeasurement& m) const {
  if (!last_reading_ || odometer_m_ - last_reading_->odometer_m > options_.hold_reading_m)
    return std::nullopt;
  return offset_from_m(m, *last_reading_);
}

std::optional<LineMeasurement> PathMemory::reading_held(const LineMeasurement& carried_back) const {
  if (!last_reading_confirmed_ || !last_reading_) return std::nullopt;
  const double since_m = odometer_m_ - last_reading_->odometer_m;
  if (since_m > options_.hold_unsteady_view_m ||
      offset_from_m(carried_back, *last_reading_) <= options_.hold_course_offset_m)
    return std::nullopt;
  const bool view_jumps =
      view_before_ && offset_from_m(carried_back, *view_before_) > options_.hold_course_offset_m;
  if (since_m > options_.hold_reading_m && !view_jumps) return std::nullopt;
  LineMeasurement held = with_model(carried_back, course_now(*last_reading_));
  held.extrapolated = true;
  return held;
}

LineMeasurement PathMemory::with_course(const LineMeasurement& m) const {
  LineMeasurement carried = with_model(m, last_course_now());
  carried.extrapolated = true;
  return carried;
}

void PathMemory::remember_heading(const LineMeasurement& m) {
  tape_heading_rad_ = vehicle_.yaw_rad - m.e_theta_rad;  // e_theta = vehicle yaw - tape yaw
  Course course = course_of(m);
  course.runs_on =
      last_course_ && std::abs(wrap_angle_rad(*tape_heading_rad_ - last_course_->heading_rad -
                                              turn_since_last_course_rad())) <=
                          options_.carry_forward_turn_margin_rad;
  const double bend_1_m = options_.carry_forward_min_curvature_1_m;
  const bool on_arc = std::abs(course.curvature_1_m) >= bend_1_m;
  const bool was_on_arc = last_course_ && std::abs(last_course_->curvature_1_m) >= bend_1_m &&
                          (last_course_->curvature_1_m > 0.0) == (course.curvature_1_m > 0.0);
  if (!on_arc) {
    on_arc_from_m_.reset();
  } else if (!was_on_arc) {
    on_arc_from_m_ = odometer_m_;
  }
  last_course_ = course;
  course_fitted_to_arc_ = false;
  if (std::abs(m.curvature_1_m) >= options_.corner_min_curvature_1_m)
    last_corner_course_ = last_course_;
}

std::optional<LineMeasurement> PathMemory::course_carried_on(const LineMeasurement& m) const {
  if (!last_course_ || odometer_m_ - last_course_->odometer_m > options_.carry_forward_m ||
      std::abs(last_course_->curvature_1_m) < options_.carry_forward_min_curvature_1_m)
    return std::nullopt;
  return with_course(m);
}

void PathMemory::fit_course_to_its_arc(const std::vector<Eigen::Vector2d>& in_vehicle) {
  if (!last_course_ || course_fitted_to_arc_ || !on_arc_from_m_ ||
      !(options_.arc_fit_reach_m > 0.0) ||
      std::abs(last_course_->curvature_1_m) < options_.carry_forward_min_curvature_1_m)
    return;
  course_fitted_to_arc_ = true;
  // Only the arc the vehicle drove on (not the tape before it, which bends otherwise).
  const double reach_m =
      std::min(options_.arc_fit_reach_m, last_course_->odometer_m - *on_arc_from_m_);
  const CurveModel arc = last_course_now();
  const CurveModel::Prepared course = arc.prepared();
  const Eigen::Vector2d foot = vehicle_.inverse().transform(last_course_->foot_m);
  const double s_foot = course.arc_position(foot);
  const double width_m = std::max(tape_width_m_, kNarrowTape_m);
  std::vector<Eigen::Vector2d> along;
  for (const Eigen::Vector2d& p : in_vehicle) {
    const double s = course.arc_position(p);
    if (s <= s_foot && s >= s_foot - reach_m && std::abs(course.signed_distance(p)) <= width_m)
      along.push_back(p);
  }
  if (static_cast<int>(along.size()) < options_.min_points) return;
  CurveFitOptions fit_options;
  fit_options.inlier_threshold_m = options_.arc_fit_inlier_m;
  fit_options.forward = arc.tangent_at(s_foot);
  const CurveFit fit = fit_curve_robust(along, fit_options, nullptr, nullptr, &arc);
  if (!fit.ok || fit.is_line || fit.s_max_m - fit.s_min_m < options_.arc_fit_min_span_m) return;
  const CurveModel fitted = fit.model.oriented_like(arc, foot);
  if (std::abs(fitted.curvature_1_m - arc.curvature_1_m) > std::abs(arc.curvature_1_m) / 3.0)
    return;
  // The course's foot point moved onto the fitted arc, with its direction there.
  const double s = fitted.arc_position(foot);
  const Eigen::Vector2d direction = fitted.tangent_at(s);
  last_course_->foot_m = vehicle_.transform(fitted.point_at(s));
  last_course_->heading_rad = vehicle_.yaw_rad + std::atan2(direction.y(), direction.x());
  last_course_->curvature_1_m = fitted.curvature_1_m;
}

std::optional<LineMeasurement> PathMemory::carried_forward(
    const LineMeasurement& carried_back) const {
  std::optional<LineMeasurement> carried = course_carried_on(carried_back);
  if (!carried) return std::nullopt;
  const CurveModel course = last_course_now();
  // The line in view continues the course where it passes through the course's last foot point
  // (within a tape width), whichever way it turns there (the vehicle may have left an arc for the
  // line after it), or through the course's foot point now (within half a tape width: the tape
  // under the vehicle on either).
  const CurveModel in_view = model_of(carried_back);
  const Eigen::Vector2d last_foot = vehicle_.inverse().transform(last_course_->foot_m);
  const double width_m =
      std::min(std::max(tape_width_m_, kNarrowTape_m), options_.carry_forward_max_width_m);
  const CurveModel::Prepared view = in_view.prepared();
  const double max_turn_rad =
      std::abs(turn_since_last_course_rad()) + options_.carry_forward_turn_margin_rad;
  // Whether the line in view passes p within `near_m`, running within max_turn_rad of heading_rad
  // (vehicle frame) there where the course ran on from the one before it.
  auto continues = [&](const Eigen::Vector2d& p, double near_m, double heading_rad) {
    return passes_along(
        view, p, heading_rad, near_m,
        last_course_->runs_on ? max_turn_rad : std::numeric_limits<double>::infinity());
  };
  if (continues(last_foot, width_m, last_course_->heading_rad - vehicle_.yaw_rad) ||
      continues(course.foot_point(), 0.5 * width_m, course.heading_rad))
    return std::nullopt;
  return carried;
}

bool PathMemory::turns_out_of_view(const LineDetection& detection) const {
  // The followed tape's direction where its evidence ends farthest along the travel direction,
  // carried on by the lookahead with the curvature there.
  const DetectedLine& line = detection.lines[detection.followed];
  const CurveModel& travel = detection.followed_model;
  const double s_at_min = travel.arc_position(line.model.point_at(line.s_min_m));
  const double s_at_max = travel.arc_position(line.model.point_at(line.s_max_m));
  const double s_end = std::max(s_at_min, s_at_max);
  // The far end of the evidence at the image's left or right border: the tape turned out of the
  // view sideways (a low camera's narrow view on an arc of R 0.5 m).
  if (s_at_max >= s_at_min ? line.open_end_at_side : line.open_start_at_side) return true;
  const Eigen::Vector2d t = travel.tangent_at(s_end + options_.corner_lookahead_m);
  return std::abs(std::atan2(t.y(), t.x())) > M_PI / 4.0;
}

bool PathMemory::tape_seen_where_remembered(const LineDetection& detection,
                                            const std::vector<Eigen::Vector2d>& in_vehicle) const {
  // Chords about as wide as the tape whose centres lie on the remembered centre line or on the
  // course last measured carried on ahead (as the tape's do; floor texture's land there by
  // chance), over a stretch of the view.
  const double gate_m = options_.seen_again_gate_m;
  const PointGrid grid(in_vehicle, gate_m);
  const CurveModel::Prepared course = last_course_now().prepared();
  int on_tape = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Chord& chord : detection.chords) {
    if (std::abs((chord.a - chord.b).norm() - tape_width_m_) >
        options_.seen_again_width_tolerance * tape_width_m_)
      continue;
    const Eigen::Vector2d c = chord.centre();
    bool near = std::abs(course.signed_distance(c)) <= gate_m;
    grid.for_each_near(c, [&](size_t j) { near = near || (in_vehicle[j] - c).norm() <= gate_m; });
    if (!near) continue;
    ++on_tape;
    lo = std::min(lo, c.norm());
    hi = std::max(hi, c.norm());
  }
  return on_tape >= options_.min_points && hi - lo >= options_.seen_again_span_m;
}

bool PathMemory::near_course_carried_forward(const CurveModel& fitted) const {
  if (!last_course_) return false;  // none measured yet (the warm-up)
  const double driven_m = odometer_m_ - last_course_->odometer_m;
  const CurveModel course = last_course_now();
  const double turn_tolerance_rad =
      options_.ahead_course_turn_rad + std::abs(turn_since_last_course_rad());
  return std::abs(wrap_angle_rad(fitted.heading_rad - course.heading_rad)) <= turn_tolerance_rad &&
         std::abs(fitted.e_d_m - course.e_d_m) <=
             options_.ahead_course_offset_m + turn_tolerance_rad * driven_m;
}

CurveModel PathMemory::course_now(const Course& course) const {
  return curve_through_point(vehicle_.inverse().transform(course.foot_m),
                             course.heading_rad - vehicle_.yaw_rad, course.curvature_1_m);
}

CurveModel PathMemory::last_course_now() const { return course_now(*last_course_); }

double PathMemory::turn_since_last_course_rad() const {
  return last_course_->curvature_1_m * (odometer_m_ - last_course_->odometer_m);
}

LineMeasurement PathMemory::remembered_only(const LineMeasurement& in_view,
                                            const LineDetection& detection) {
  // No line in view. The remembered tape under the vehicle, while it reaches both sides of the
  // origin, where the camera (ahead of the vehicle) has passed a corner (the tape last seen
  // turned out of the view by more than 45 deg), or where the frame still shows the tape where
  // it is remembered (perception refused the line: a floor texture, glare); past a corner, beyond
  // the tape remembered, the corner's arc carried on (course_carried_on). Otherwise (a covered
  // lens, a gap, the tape's end) the line is lost.
  if (!tape_heading_rad_ || !last_course_ || points_.empty()) return in_view;
  const bool past_corner = turns_out_of_view_;
  const std::vector<Eigen::Vector2d> in_vehicle = points_in_vehicle_frame();
  if (!past_corner && !tape_seen_where_remembered(detection, in_vehicle)) return in_view;
  std::optional<LineMeasurement> m = at_origin(in_view, in_vehicle);
  if (!m && past_corner) {
    // Past the tape remembered, still in the corner: its arc carried on (the only way out of an
    // L corner) for a while, the heading kept for the frames after.
    fit_course_to_its_arc(in_vehicle);
    std::optional<LineMeasurement> carried = course_carried_on(in_view);
    if (carried) {
      carried->line_found = true;
      carried->remembered_only = true;
      carried->lines_seen = 0;
      carried->confidence = 0.25;  // neither evidence nor remembered tape
      carried->points_used = 0;
      return *carried;
    }
  }
  if (!m) {
    tape_heading_rad_.reset();
    return in_view;
  }
  m->line_found = true;
  m->remembered_only = true;
  if (past_corner) corner_passed_at_m_ = odometer_m_;
  m->lines_seen = 0;
  m->confidence = 0.5;  // no evidence in this frame
  m->points_used = 0;
  add_preview(in_vehicle, &*m);  // the remembered tape ahead
  remember_heading(*m);
  return *m;
}

}  // namespace agv::perception
