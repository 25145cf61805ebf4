#include "perception/joined_arcs_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace agv::perception {
namespace {

struct Solved {
  Eigen::Vector4d c = Eigen::Vector4d::Zero();  // a, b, k1, k2
  double rss = std::numeric_limits<double>::infinity();
};

// The model y = a + b x + k1 x^2/2 + (k2 - k1) (x - xb)_+^2 / 2 is linear in (a, b, k1, k2):
// y = basis(x) . (a, b, k1, k2).
Eigen::Vector4d basis(double x, std::optional<double> xb) {
  Eigen::Vector4d r(1.0, x, 0.5 * x * x, 0.0);
  if (xb && x > *xb) {
    const double h = 0.5 * (x - *xb) * (x - *xb);
    r[2] -= h;  // k1 x^2/2 - k1 h + k2 h
    r[3] = h;
  }
  return r;
}

// Least squares of the model over the points marked; without a breakpoint, k2 = k1 (three
// unknowns). The residual sum of squares summed over the points (exact), or, to rank
// breakpoints, from the normal equations, y'y - c'A'y, in the same pass (rounding: about 1e-16
// of y'y).
Solved solve(const std::vector<Eigen::Vector2d>& p, const std::vector<bool>& use,
             std::optional<double> xb, bool exact_rss = true) {
  const int n_params = xb ? 4 : 3;
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d aty = Eigen::Vector4d::Zero();
  double yty = 0.0;
  int used = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector4d r = basis(p[i].x(), xb);
    ata += r * r.transpose();
    aty += r * p[i].y();
    yty += p[i].y() * p[i].y();
    ++used;
  }
  Solved s;
  if (used < n_params + 2) return s;
  const Eigen::MatrixXd a = ata.topLeftCorner(n_params, n_params);
  const Eigen::VectorXd solution = a.ldlt().solve(aty.head(n_params));
  s.c.head(n_params) = solution;
  if (!xb) s.c[3] = s.c[2];
  if (!exact_rss) {
    s.rss = std::max(0.0, yty - solution.dot(aty.head(n_params)));
    return s;
  }
  s.rss = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    const double r = basis(p[i].x(), xb).head(n_params).dot(solution) - p[i].y();
    s.rss += r * r;
  }
  return s;
}

// The best model over the points marked: one piece, or two with the breakpoint that leaves the
// least residual, kept when it lowers n log(rss / n) by more than log n per extra parameter (two:
// the breakpoint and the second curvature).
std::pair<Solved, std::optional<double>> best_model(const std::vector<Eigen::Vector2d>& p,
                                                    const std::vector<bool>& use,
                                                    const JoinedArcsOptions& options) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  int n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    lo = std::min(lo, p[i].x());
    hi = std::max(hi, p[i].x());
    ++n;
  }
  Solved best = solve(p, use, std::nullopt);
  std::optional<double> best_xb;
  Solved two;
  std::optional<double> two_xb;
  for (double xb = lo + options.min_piece_m; xb <= hi - options.min_piece_m;
       xb += options.breakpoint_step_m) {
    const Solved s = solve(p, use, xb, /*exact_rss=*/false);
    if (s.rss < two.rss) {
      two = s;
      two_xb = xb;
    }
  }
  if (two_xb) two = solve(p, use, two_xb);  // the breakpoint chosen, its residual exact
  const double floor_rss = 1e-18 * n;       // noise-free points: no log of zero
  if (two_xb && n > 6 &&
      n * std::log((two.rss + floor_rss) / n) + 2.0 * std::log(n) <
          n * std::log((best.rss + floor_rss) / n)) {
    best = two;
    best_xb = two_xb;
  }
  return {best, best_xb};
}

}  // namespace

std::optional<JoinedArcs> fit_joined_arcs(const std::vector<Eigen::Vector2d>& points,
                                          const JoinedArcsOptions& options) {
  if (points.size() < 6) return std::nullopt;
  bool before = false, after = false;
  for (const Eigen::Vector2d& p : points) {
    before = before || p.x() < 0.0;
    after = after || p.x() > 0.0;
  }
  if (!before || !after) return std::nullopt;
  std::vector<bool> use(points.size(), true);
  auto [model, xb] = best_model(points, use, options);
  // Once: drop the points far off (a stray chord, a seam), then fit again.
  std::vector<double> residuals;
  for (const Eigen::Vector2d& p : points)
    residuals.push_back(std::abs(basis(p.x(), xb).dot(model.c) - p.y()));
  std::vector<double> sorted = residuals;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double sigma = std::max(1e-6, 1.4826 * sorted[sorted.size() / 2]);
  int kept = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    use[i] = residuals[i] <= options.outlier_sigmas * sigma;
    kept += use[i] ? 1 : 0;
  }
  if (kept < static_cast<int>(points.size()))
    std::tie(model, xb) = best_model(points, use, options);
  if (!std::isfinite(model.rss)) return std::nullopt;

  JoinedArcs out;
  out.offset_m = model.c[0];
  out.slope = model.c[1];
  // The curvature at x = 0 is the first piece's unless the breakpoint lies behind the origin.
  const bool second_holds = xb && *xb < 0.0;
  out.curvature_1_m = second_holds ? model.c[3] : model.c[2];
  if (second_holds) {
    // y = a + b x + k1 x^2/2 + (k2 - k1)(x - xb)^2/2 for x > xb: value and slope at 0.
    out.offset_m += 0.5 * (model.c[3] - model.c[2]) * (*xb) * (*xb);
    out.slope += -(model.c[3] - model.c[2]) * (*xb);
  }
  out.curvature_far_1_m = model.c[3];
  out.break_x_m = xb;
  out.points = kept;
  out.rms_m = std::sqrt(model.rss / std::max(1, kept));
  return out;
}

}  // namespace agv::perception
