#include "perception/joined_arcs_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
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

// The solution of the normal equations (a'a) c = a'y over the first n_params unknowns.
Eigen::Vector4d solve_normal(const Eigen::Matrix4d& ata, const Eigen::Vector4d& aty, int n_params) {
  Eigen::Vector4d c = Eigen::Vector4d::Zero();
  if (n_params == 3) {
    c.head<3>() = ata.topLeftCorner<3, 3>().ldlt().solve(aty.head<3>());
  } else {
    c = ata.ldlt().solve(aty);
  }
  return c;
}

// Least squares of the model over the points marked; without a breakpoint, k2 = k1 (three
// unknowns). The residual sum of squares summed over the points.
Solved solve(const std::vector<Eigen::Vector2d>& p, const std::vector<bool>& use,
             std::optional<double> xb) {
  const int n_params = xb ? 4 : 3;
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d aty = Eigen::Vector4d::Zero();
  int used = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector4d r = basis(p[i].x(), xb);
    ata += r * r.transpose();
    aty += r * p[i].y();
    ++used;
  }
  Solved s;
  if (used < n_params + 2) return s;
  s.c = solve_normal(ata, aty, n_params);
  if (!xb) s.c[3] = s.c[2];
  s.rss = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!use[i]) continue;
    const double r = basis(p[i].x(), xb).dot(s.c) - p[i].y();
    s.rss += r * r;
  }
  return s;
}

// The breakpoints lo + min_piece, then every breakpoint_step, up to hi - min_piece, ranked by
// their residual from the normal equations, y'y - c'a'y. The points beyond a breakpoint add h =
// (x - xb)^2 / 2 terms whose sums are polynomials in xb over the moments of those points (sums
// of x^0..x^4 and x^0..x^2 y), kept as suffix sums over the points sorted by x: each breakpoint
// costs a 4 x 4 solve, not a pass over the points. Nullopt when none leaves each piece enough.
std::optional<double> best_breakpoint(const std::vector<Eigen::Vector2d>& p,
                                      const std::vector<bool>& use, double lo, double hi,
                                      const JoinedArcsOptions& options) {
  std::vector<const Eigen::Vector2d*> sorted;
  for (size_t i = 0; i < p.size(); ++i)
    if (use[i]) sorted.push_back(&p[i]);
  std::sort(sorted.begin(), sorted.end(),
            [](const Eigen::Vector2d* a, const Eigen::Vector2d* b) { return a->x() < b->x(); });
  const size_t n = sorted.size();
  if (n < 6) return std::nullopt;
  // suffix[j]: the moments of sorted[j..n): x^0..x^4 (0-4), x^0..x^2 y (5-7).
  std::vector<std::array<double, 8>> suffix(n + 1, std::array<double, 8>{});
  for (size_t j = n; j-- > 0;) {
    const double x = sorted[j]->x(), y = sorted[j]->y();
    const double powers[5] = {1.0, x, x * x, x * x * x, x * x * x * x};
    for (int k = 0; k < 5; ++k) suffix[j][k] = suffix[j + 1][k] + powers[k];
    for (int k = 0; k < 3; ++k) suffix[j][5 + k] = suffix[j + 1][5 + k] + powers[k] * y;
  }
  // The model without a breakpoint's sums: r0 = (1, x, x^2 / 2).
  const std::array<double, 8>& all = suffix[0];
  double yty = 0.0;
  for (const Eigen::Vector2d* q : sorted) yty += q->y() * q->y();
  Eigen::Matrix4d g0 = Eigen::Matrix4d::Zero();
  g0(0, 0) = all[0];
  g0(0, 1) = g0(1, 0) = all[1];
  g0(1, 1) = all[2];
  g0(0, 2) = g0(2, 0) = 0.5 * all[2];
  g0(1, 2) = g0(2, 1) = 0.5 * all[3];
  g0(2, 2) = 0.25 * all[4];
  std::optional<double> best;
  double best_rss = std::numeric_limits<double>::infinity();
  size_t first = 0;  // sorted[first..n) lie beyond the breakpoint (x > xb)
  for (double xb = lo + options.min_piece_m; xb <= hi - options.min_piece_m;
       xb += options.breakpoint_step_m) {
    while (first < n && sorted[first]->x() <= xb) ++first;
    const std::array<double, 8>& m = suffix[first];
    const double b1 = xb, b2 = xb * xb, b3 = b2 * xb, b4 = b2 * b2;
    const double s_h = 0.5 * (m[2] - 2.0 * b1 * m[1] + b2 * m[0]);
    const double s_hx = 0.5 * (m[3] - 2.0 * b1 * m[2] + b2 * m[1]);
    const double s_hx2 = 0.25 * (m[4] - 2.0 * b1 * m[3] + b2 * m[2]);  // sum of h x^2 / 2
    const double s_hh =
        0.25 * (m[4] - 4.0 * b1 * m[3] + 6.0 * b2 * m[2] - 4.0 * b3 * m[1] + b4 * m[0]);
    const double s_hy = 0.5 * (m[7] - 2.0 * b1 * m[6] + b2 * m[5]);
    Eigen::Matrix4d ata = g0;
    ata(0, 2) = ata(2, 0) = g0(0, 2) - s_h;
    ata(1, 2) = ata(2, 1) = g0(1, 2) - s_hx;
    ata(2, 2) = g0(2, 2) - 2.0 * s_hx2 + s_hh;
    ata(0, 3) = ata(3, 0) = s_h;
    ata(1, 3) = ata(3, 1) = s_hx;
    ata(2, 3) = ata(3, 2) = s_hx2 - s_hh;
    ata(3, 3) = s_hh;
    const Eigen::Vector4d aty(all[5], all[6], 0.5 * all[7] - s_hy, s_hy);
    const Eigen::Vector4d c = solve_normal(ata, aty, 4);
    const double rss = std::max(0.0, yty - c.dot(aty));
    if (rss < best_rss) {
      best_rss = rss;
      best = xb;
    }
  }
  return best;
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
  const std::optional<double> two_xb = best_breakpoint(p, use, lo, hi, options);
  Solved two;
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
