#include "perception/curve_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>

#include "common/angles.h"
#include "common/vector_clones.h"
#include "perception/autocorrelation.h"
#include "perception/kth_smallest.h"
#include "perception/log1p_sum.h"

namespace agv::perception {
namespace {

// Model from a point on a line and its direction.
CurveModel line_model(const Eigen::Vector2d& point, Eigen::Vector2d direction) {
  direction.normalize();
  CurveModel m;
  m.heading_rad = std::atan2(direction.y(), direction.x());
  m.e_d_m = direction.y() * point.x() - direction.x() * point.y();
  m.curvature_1_m = 0.0;
  return m;
}

// Orients a model so that its direction near `near` points along `forward`.
CurveModel oriented(const CurveModel& m, const Eigen::Vector2d& near,
                    const Eigen::Vector2d& forward) {
  return m.tangent_at(m.arc_position(near)).dot(forward) >= 0.0 ? m : m.reversed();
}

// One observation of a curve: a point that should lie at signed distance `offset` from it (0: on
// it, a chord's midpoint; plus or minus half the tape width: a tape edge), of chord `chord`.
struct Observation {
  Eigen::Vector2d p;
  double offset;
  int chord;
  bool first;  // the chord's first edge (for edges)
};

double residual(const CurveModel::Prepared& curve, const Observation& o) {
  return curve.signed_distance(o.p) - o.offset;
}

// Observations packed for passes over them, and per observation what a pass works out
// (residual r; for a Gauss-Newton pass the gradient g of the signed distance, z = (r / scale)^2
// and the Cauchy weight w = 1 / (1 + z)).
struct Packed {
  std::vector<double> x, y, offset;
  std::vector<double> r, g0, g1, g2, z, w;
};

// The observations marked in `use` (all without it), packed.
Packed packed(const std::vector<Observation>& obs, const std::vector<std::uint8_t>* use = nullptr) {
  const size_t n = use ? std::count(use->begin(), use->end(), 1) : obs.size();
  Packed out;
  for (std::vector<double>* v : {&out.x, &out.y, &out.offset, &out.r}) v->resize(n);
  size_t k = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (use && !(*use)[i]) continue;
    out.x[k] = obs[i].p.x();
    out.y[k] = obs[i].p.y();
    out.offset[k] = obs[i].offset;
    ++k;
  }
  return out;
}

// Residuals of n observations (x, y, offset) from a curve, in a loop that vectorises (restrict
// parameters: GCC does not trust restrict on local pointers).
AGV_VECTOR_CLONES
void residuals(const CurveModel::Prepared curve, size_t n, const double* __restrict x,
               const double* __restrict y, const double* __restrict offset, double* __restrict r) {
  for (size_t i = 0; i < n; ++i) r[i] = curve.signed_distance(x[i], y[i]) - offset[i];
}

struct Scored {
  std::vector<std::uint8_t> observation_inliers;  // 1: within (bytes: vector<bool> costs more)
  int count = 0;           // inlier observations
  double plain_rms = 0.0;  // root mean square: for uncertainties, which the tails belong to
  std::vector<double> magnitudes;  // of the inliers' residuals, in no particular order
};

// The observations within `threshold` of a model (all of them, packed).
Scored score(const CurveModel& m, Packed* all, double threshold) {
  const size_t n = all->x.size();
  residuals(m.prepared(), n, all->x.data(), all->y.data(), all->offset.data(), all->r.data());
  Scored s;
  s.observation_inliers.assign(n, 0);
  s.magnitudes.reserve(n);
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double r = all->r[i];
    if (std::abs(r) > threshold) continue;
    s.observation_inliers[i] = 1;
    ++s.count;
    sum += r * r;
    s.magnitudes.push_back(std::abs(r));
  }
  s.plain_rms = s.count ? std::sqrt(sum / s.count) : 0.0;
  return s;
}

// A robust scale of the inliers' residuals: 1.4826 x their median magnitude (inliers within a
// generous band still include some far edges of merged chords); for confidence.
double robust_scale(const Scored& s, std::vector<double>* scratch) {
  if (s.magnitudes.empty()) return 0.0;
  return 1.4826 *
         kth_smallest(s.magnitudes.data(), s.magnitudes.size(), s.magnitudes.size() / 2, scratch);
}

// The per-observation part of a pass over n observations (x, y, offset): no sums across them,
// so that it vectorises (restrict parameters: GCC does not trust restrict on local pointers).
AGV_VECTOR_CLONES
void residuals_and_weights(const CurveModel::Prepared curve, double inverse_scale2, size_t n,
                           const double* __restrict x, const double* __restrict y,
                           const double* __restrict offset, double* __restrict r,
                           double* __restrict g0, double* __restrict g1, double* __restrict g2,
                           double* __restrict z, double* __restrict w) {
  for (size_t i = 0; i < n; ++i) {
    r[i] = curve.signed_distance(x[i], y[i], &g0[i], &g1[i], &g2[i]) - offset[i];
    z[i] = r[i] * r[i] * inverse_scale2;
    w[i] = 1.0 / (1.0 + z[i]);
  }
}

// Cauchy cost of a model and its Gauss-Newton normal equations (weights 1 / (1 + (r/scale)^2)),
// in one pass over the observations.
struct Linearised {
  double cost = 0.0;
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
};

Linearised linearise(const CurveModel& model, Packed* obs, bool free_curvature, double scale) {
  for (std::vector<double>* v : {&obs->g0, &obs->g1, &obs->g2, &obs->z, &obs->w})
    v->resize(obs->x.size());
  residuals_and_weights(model.prepared(), 1.0 / (scale * scale), obs->x.size(), obs->x.data(),
                        obs->y.data(), obs->offset.data(), obs->r.data(), obs->g0.data(),
                        obs->g1.data(), obs->g2.data(), obs->z.data(), obs->w.data());
  double j00 = 0, j01 = 0, j02 = 0, j11 = 0, j12 = 0, j22 = 0, r0 = 0, r1 = 0, r2 = 0;
  const size_t n = obs->x.size();
  for (size_t i = 0; i < n; ++i) {
    const double w = obs->w[i], r = obs->r[i];
    const double g0 = obs->g0[i], g1 = obs->g1[i], g2 = free_curvature ? obs->g2[i] : 0.0;
    j00 += w * g0 * g0;
    j01 += w * g0 * g1;
    j02 += w * g0 * g2;
    j11 += w * g1 * g1;
    j12 += w * g1 * g2;
    j22 += w * g2 * g2;
    r0 += w * g0 * r;
    r1 += w * g1 * r;
    r2 += w * g2 * r;
  }
  Linearised l;
  l.cost = log1p_sum(obs->z.data(), n);  // the Cauchy loss whose weights are used
  l.jtj << j00, j01, j02, j01, j11, j12, j02, j12, j22;
  l.jtr << r0, r1, r2;
  if (!free_curvature) l.jtj(2, 2) = 1.0;
  return l;
}

// Weighted Levenberg-Marquardt on (e_d, heading, curvature), or (e_d, heading) with the
// curvature held, with Cauchy weights of scale `scale`. A step is taken only if it lowers the
// weighted cost; otherwise the damping grows. Returns the normal matrix at the solution (for the
// covariance).
Eigen::Matrix3d refine(CurveModel* m, const std::vector<Observation>& all,
                       const std::vector<std::uint8_t>& use, bool free_curvature, double scale) {
  Packed obs = packed(all, &use);
  Linearised current = linearise(*m, &obs, free_curvature, scale);
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 12; ++iteration) {
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Eigen::Matrix3d damped = current.jtj;
      damped.diagonal() += lambda * current.jtj.diagonal().cwiseMax(1e-12);
      const Eigen::Vector3d step = damped.ldlt().solve(-current.jtr);
      if (!step.allFinite()) return current.jtj;
      CurveModel trial = *m;
      trial.e_d_m += step[0];
      trial.heading_rad = wrap_angle_rad(trial.heading_rad + step[1]);
      if (free_curvature) trial.curvature_1_m += step[2];
      Linearised at_trial = linearise(trial, &obs, free_curvature, scale);
      if (at_trial.cost <= current.cost) {
        *m = trial;
        current = at_trial;
        lambda = std::max(1e-7, lambda * 0.1);
        improved = true;
        // Converged: steps of 1 micrometre, 1 microradian, 1e-4 1/m mean nothing here (the
        // noise of a fit is tens of micrometres).
        if (step.head<2>().norm() < 1e-6 && std::abs(step[2]) < 1e-4) return current.jtj;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  return current.jtj;
}

// Factor by which correlated residuals inflate a variance computed as if they were independent:
// 1 + 2 * sum of the residuals' autocorrelation over neighbours along the curve (the integrated
// autocorrelation time), summed until it falls below 0.05. Each side of the tape (sign of the
// distance) is one sequence.
double correlation_inflation(const CurveModel& m, const std::vector<Observation>& obs,
                             const std::vector<std::uint8_t>& use) {
  const CurveModel::Prepared curve = m.prepared();
  double total_tau = 0.0;
  int sequences = 0;
  for (int side : {-1, 0, 1}) {
    std::vector<std::pair<double, double>> by_position;  // (arc order key, residual)
    by_position.reserve(obs.size());
    for (size_t i = 0; i < obs.size(); ++i) {
      if (!use[i]) continue;
      const int obs_side = obs[i].offset == 0.0 ? 0 : (obs[i].offset > 0.0 ? 1 : -1);
      if (obs_side != side) continue;
      by_position.emplace_back(curve.arc_order_key(obs[i].p), residual(curve, obs[i]));
    }
    if (by_position.size() < 8) continue;
    // Chords come in scan order, mostly in order along the curve already (or against it).
    if (std::is_sorted(by_position.rbegin(), by_position.rend())) {
      std::reverse(by_position.begin(), by_position.end());
    } else if (!std::is_sorted(by_position.begin(), by_position.end())) {
      std::sort(by_position.begin(), by_position.end());
    }
    std::vector<double> residuals;
    residuals.reserve(by_position.size());
    for (const auto& [s, r] : by_position) residuals.push_back(r);
    total_tau += integrated_autocorrelation_time(residuals);
    ++sequences;
  }
  return sequences ? total_tau / sequences : 1.0;
}

}  // namespace

Eigen::Vector2d CurveModel::tangent() const {
  return {std::cos(heading_rad), std::sin(heading_rad)};
}
Eigen::Vector2d CurveModel::normal() const {
  return {-std::sin(heading_rad), std::cos(heading_rad)};
}
Eigen::Vector2d CurveModel::foot_point() const { return -e_d_m * normal(); }

double CurveModel::signed_distance(const Eigen::Vector2d& p) const {
  return prepared().signed_distance(p);
}

double CurveModel::arc_position(const Eigen::Vector2d& p) const {
  return prepared().arc_position(p);
}

Eigen::Vector2d CurveModel::point_at(double s_m) const {
  const double k = curvature_1_m;
  if (std::abs(k) < 1e-9) return foot_point() + s_m * tangent();
  const double angle = k * s_m;
  return foot_point() + (std::sin(angle) / k) * tangent() +
         ((1.0 - std::cos(angle)) / k) * normal();
}

Eigen::Vector2d CurveModel::tangent_at(double s_m) const {
  const double yaw = heading_rad + curvature_1_m * s_m;
  return {std::cos(yaw), std::sin(yaw)};
}

CurveModel CurveModel::reversed() const {
  return {-e_d_m, wrap_angle_rad(heading_rad + M_PI), -curvature_1_m};
}

CurveModel CurveModel::oriented_like(const CurveModel& reference,
                                     const Eigen::Vector2d& where) const {
  const Eigen::Vector2d along_reference = reference.tangent_at(reference.arc_position(where));
  return tangent_at(arc_position(where)).dot(along_reference) >= 0.0 ? *this : reversed();
}

std::optional<CurveModel> curve_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                        const Eigen::Vector2d& c, const Eigen::Vector2d& forward) {
  const Eigen::Vector2d ab = b - a, ac = c - a;
  const double cross = ab.x() * ac.y() - ab.y() * ac.x();
  const double span = std::max({ab.norm(), ac.norm(), (c - b).norm()});
  if (span < 1e-6) return std::nullopt;
  if (std::abs(cross) < 1e-9 * span * span) return oriented(line_model(a, c - a), b, forward);
  // Circumcentre.
  const double d = 2.0 * cross;
  const double ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm();
  const Eigen::Vector2d centre =
      a + Eigen::Vector2d(ac.y() * ab2 - ab.y() * ac2, ab.x() * ac2 - ac.x() * ab2) / d;
  const double radius = (a - centre).norm();
  Eigen::Vector2d to_origin = -centre;
  if (to_origin.norm() < 1e-12) return std::nullopt;  // the origin at the centre: no foot point
  const Eigen::Vector2d foot = centre + radius * to_origin.normalized();
  // Counter-clockwise tangent at the foot point; the curvature is positive (centre on the left).
  const Eigen::Vector2d radial = (foot - centre).normalized();
  const Eigen::Vector2d ccw(-radial.y(), radial.x());
  CurveModel m;
  m.heading_rad = std::atan2(ccw.y(), ccw.x());
  m.curvature_1_m = 1.0 / radius;
  m.e_d_m = -foot.dot(m.normal());
  return oriented(m, b, forward);
}

CurveFit fit_curve_robust(const std::vector<Eigen::Vector2d>& points,
                          const CurveFitOptions& options, const std::vector<bool>* mask,
                          const EdgeObservations* edges, const CurveModel* initial) {
  CurveFit fit;
  std::vector<int> usable;
  usable.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!mask || (*mask)[i]) usable.push_back(static_cast<int>(i));
  }
  const int n = static_cast<int>(usable.size());
  if (n < 3) return fit;
  // What the fit is scored and refined on: the points themselves, or the edges of their chords.
  std::vector<Observation> obs;
  obs.reserve(edges ? 2 * usable.size() : usable.size());
  for (int i : usable) {
    if (edges) {
      // An edge whose offset is NaN is left out.
      if (!std::isnan((*edges->first_offset_m)[i]))
        obs.push_back({(*edges->first)[i], (*edges->first_offset_m)[i], i, true});
      if (!std::isnan((*edges->second_offset_m)[i]))
        obs.push_back({(*edges->second)[i], (*edges->second_offset_m)[i], i, false});
    } else {
      obs.push_back({points[i], 0.0, i, false});
    }
  }
  const int m_obs = static_cast<int>(obs.size());
  Packed all = packed(obs);
  // Score hypotheses on at most ~400 observations; refine on all.
  const int stride = std::max(1, m_obs / 400);
  const double t = options.inlier_threshold_m, t2 = t * t;
  cv::RNG rng(0xC0FFEE);
  double best_cost = std::numeric_limits<double>::infinity();
  CurveModel best;
  // Adaptive stop: once the best hypothesis has a fraction w of the sampled observations within
  // the threshold, log(1 - 0.999) / log(1 - w^3) draws would have found an all-inlier sample.
  int needed = options.ransac_iterations;
  const int sampled = (m_obs + stride - 1) / stride;
  std::vector<std::uint8_t> in_sample(obs.size(), 0);  // the observations hypotheses are scored on
  for (int k = 0; k < m_obs && !initial; k += stride) in_sample[k] = 1;
  Packed sample = packed(obs, &in_sample);
  if (initial) {
    best = *initial;
    best_cost = 0.0;
    needed = 0;
  }
  for (int it = 0; it < std::min(needed, options.ransac_iterations); ++it) {
    const int a = usable[rng.uniform(0, n)], b = usable[rng.uniform(0, n)],
              c = usable[rng.uniform(0, n)];
    std::optional<CurveModel> model;
    if (it % 3 == 0) {  // a third of the hypotheses are lines (two points)
      if ((points[c] - points[a]).norm() < 1e-4) continue;
      model = oriented(line_model(points[a], points[c] - points[a]), points[a], options.forward);
    } else {
      model = curve_through(points[a], points[b], points[c], options.forward);
    }
    if (!model || std::abs(model->curvature_1_m) > options.max_curvature_1_m) continue;
    double cost = 0.0;
    int within = 0;
    residuals(model->prepared(), sample.x.size(), sample.x.data(), sample.y.data(),
              sample.offset.data(), sample.r.data());
    for (const double r : sample.r) {
      const double r2 = r * r;
      cost += std::min(r2, t2);
      if (r2 <= t2) ++within;
    }
    if (cost < best_cost) {
      best_cost = cost;
      best = *model;
      const double w = static_cast<double>(within) / sampled;
      if (w > 0.0) {
        const double draws = std::log(1.0 - 0.999) / std::log(std::max(1e-12, 1.0 - w * w * w));
        needed = std::max(12, static_cast<int>(std::ceil(draws)));
      }
    }
  }
  if (!std::isfinite(best_cost)) return fit;

  // Refine: curvature free, then kept only if significant.
  Scored scored = score(best, &all, t);
  std::vector<double> scratch;
  CurveModel model = best;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Identity();
  for (int round = 0; round < 4 && scored.count >= 3; ++round) {
    normal = refine(&model, obs, scored.observation_inliers, /*free_curvature=*/true, t / 2.0);
    Scored next = score(model, &all, t);
    const bool settled = next.observation_inliers == scored.observation_inliers;
    scored = std::move(next);
    if (settled) break;
  }
  if (scored.count < 3) return fit;
  // Tighten: the wide band (set for seams and wear) still holds spurious edges a few millimetres
  // off, which pull the curvature at Cauchy weights of that scale. Refine once more on the
  // observations within 4 robust sigmas (at least 0.3 mm) at that scale, when some lie beyond;
  // the inlier set reported stays the wide one.
  const double fine_m = std::clamp(4.0 * robust_scale(scored, &scratch), 0.0003, t);
  if (fine_m < t) {
    const Scored fine = score(model, &all, fine_m);
    if (fine.count < scored.count && fine.count >= std::max(3, scored.count / 2)) {
      CurveModel tight = model;
      const Eigen::Matrix3d tight_normal =
          refine(&tight, obs, fine.observation_inliers, /*free_curvature=*/true, fine_m / 2.0);
      model = tight;
      normal = tight_normal;
      scored = score(model, &all, t);
    }
  }
  // Residuals along a tape are correlated (floor texture, wear span many scan lines): the
  // independent-noise covariance is inflated by the integrated autocorrelation.
  const double variance = std::max(scored.plain_rms * scored.plain_rms, 1e-12) *
                          correlation_inflation(model, obs, scored.observation_inliers);
  const Eigen::Matrix3d covariance = normal.inverse() * variance;
  fit.curvature_sigma_1_m = std::sqrt(std::max(0.0, covariance(2, 2)));
  fit.is_line =
      std::abs(model.curvature_1_m) < options.curvature_significance * fit.curvature_sigma_1_m;
  if (fit.is_line) {
    model.curvature_1_m = 0.0;
    for (int round = 0; round < 3; ++round) {
      refine(&model, obs, scored.observation_inliers, /*free_curvature=*/false, t / 2.0);
      Scored next = score(model, &all, t);
      const bool settled = next.observation_inliers == scored.observation_inliers;
      scored = std::move(next);
      if (settled || scored.count < 3) break;
    }
  }
  if (scored.count < 3) return fit;
  // Chords with an inlier observation are the curve's; the orientation comes from their middle.
  fit.inliers.assign(points.size(), false);
  if (edges) fit.edge_inliers.assign(points.size(), 0);
  for (size_t k = 0; k < obs.size(); ++k) {
    if (!scored.observation_inliers[k]) continue;
    fit.inliers[obs[k].chord] = true;
    if (edges) fit.edge_inliers[obs[k].chord] |= obs[k].first ? 1 : 2;
  }
  fit.inlier_count = static_cast<int>(std::count(fit.inliers.begin(), fit.inliers.end(), true));
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    if (fit.inliers[i]) centroid += points[i];
  }
  centroid /= std::max(1, fit.inlier_count);
  model = oriented(model, centroid, options.forward);
  fit.ok = true;
  fit.model = model;
  fit.rms_m = robust_scale(scored, &scratch);
  fit.s_min_m = std::numeric_limits<double>::infinity();
  fit.s_max_m = -fit.s_min_m;
  const CurveModel::Prepared prepared = model.prepared();
  const double centroid_s_m = prepared.arc_position(centroid);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!fit.inliers[i]) continue;
    const double s = prepared.arc_position_near(points[i], centroid_s_m);
    fit.s_min_m = std::min(fit.s_min_m, s);
    fit.s_max_m = std::max(fit.s_max_m, s);
  }
  return fit;
}

// The curve through point p0 with direction heading0 and curvature k, as the model of the vehicle
// origin's foot point on it (CurveModel's parametrisation).
CurveModel curve_through_point(const Eigen::Vector2d& p0, double heading0, double k) {
  const Eigen::Vector2d t0(std::cos(heading0), std::sin(heading0));
  const Eigen::Vector2d n0(-t0.y(), t0.x());
  CurveModel m;
  m.curvature_1_m = k;
  // Signed distance of the origin from the circle through p0: that of -p0 from the same circle
  // moved to pass through the origin.
  m.e_d_m = CurveModel{0.0, heading0, k}.signed_distance(-p0);
  if (std::abs(k) < 1e-9) {
    m.heading_rad = heading0;
    return m;
  }
  // The tangent at the origin's foot point: the radius through the origin turned by 90 deg
  // towards the travel direction.
  const Eigen::Vector2d centre = p0 + n0 / k;
  Eigen::Vector2d radial = -centre;
  if (radial.norm() < 1e-12) radial = p0 - centre;  // the origin at the centre: any foot
  radial.normalize();
  const Eigen::Vector2d tangent =
      k > 0.0 ? Eigen::Vector2d(-radial.y(), radial.x()) : Eigen::Vector2d(radial.y(), -radial.x());
  m.heading_rad = std::atan2(tangent.y(), tangent.x());
  return m;
}

CurveModel curve_in_frame(double frame_rad, double offset_m, double slope, double second_1_m) {
  const double c = std::cos(frame_rad), s = std::sin(frame_rad);
  const double k = second_1_m / std::pow(1.0 + slope * slope, 1.5);
  return curve_through_point(Eigen::Vector2d(-s * offset_m, c * offset_m),
                             frame_rad + std::atan(slope), k);
}

}  // namespace agv::perception
