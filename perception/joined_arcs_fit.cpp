#include "perception/joined_arcs_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "perception/autocorrelation.h"
#include "perception/outlier_limit.h"

namespace agv::perception {
namespace {

// Each point's weight (how many observations it stands for): 1 where none are given.
class Weights {
 public:
  explicit Weights(const std::vector<double>& weights) : weights_(weights) {}
  double operator()(size_t i) const { return weights_.empty() ? 1.0 : weights_[i]; }
  const std::vector<double>& all() const { return weights_; }

 private:
  const std::vector<double>& weights_;
};

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

// basis(x, xb).dot(c) term by term, without the vector (one returned per point went through
// memory: most of the fit's time).
double model_y(const Eigen::Vector4d& c, double x, std::optional<double> xb) {
  const double h = xb && x > *xb ? 0.5 * (x - *xb) * (x - *xb) : 0.0;
  return c[0] + x * c[1] + (0.5 * x * x - h) * c[2] + h * c[3];
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

// The normal equations of the one-piece model y = a + b x + k x^2 / 2 from the sums of x^0..x^4
// (x) and of x^0..x^2 y (xy) over the points.
void one_piece_normal_equations(const double* x, const double* xy, Eigen::Matrix3d* ata,
                                Eigen::Vector3d* aty) {
  *ata << x[0], x[1], 0.5 * x[2], x[1], x[2], 0.5 * x[3], 0.5 * x[2], 0.5 * x[3], 0.25 * x[4];
  *aty << xy[0], xy[1], 0.5 * xy[2];
}

// The points marked, sorted by x, with suffix sums of their moments: the normal equations of the
// model for any breakpoint from a handful of sums. The points beyond a breakpoint add h = (x -
// xb)^2 / 2 terms whose sums are polynomials in xb over the moments of those points (x^0..x^4,
// x^0..x^2 y), so each breakpoint costs a 4 x 4 solve, not a pass over the points.
class PointMoments {
 public:
  // `by_x`: all the points, in order along x; those marked in `use` (by index into p) count,
  // each with its weight.
  PointMoments(const std::vector<Eigen::Vector2d>& p,
               const std::vector<const Eigen::Vector2d*>& by_x, const std::vector<bool>& use,
               const Weights& weight) {
    for (const Eigen::Vector2d* q : by_x)
      if (use[q - p.data()]) sorted_.push_back(q);
    suffix_.assign(sorted_.size() + 1, std::array<double, 8>{});
    for (size_t j = sorted_.size(); j-- > 0;) {
      const double x = sorted_[j]->x(), y = sorted_[j]->y();
      const double w = weight(sorted_[j] - p.data());
      const double powers[5] = {w, w * x, w * x * x, w * x * x * x, w * x * x * x * x};
      for (int k = 0; k < 5; ++k) suffix_[j][k] = suffix_[j + 1][k] + powers[k];
      for (int k = 0; k < 3; ++k) suffix_[j][5 + k] = suffix_[j + 1][5 + k] + powers[k] * y;
      yty_ += w * y * y;
    }
  }

  size_t size() const { return sorted_.size(); }
  double total_weight() const { return suffix_[0][0]; }
  double lo() const { return sorted_.front()->x(); }
  double hi() const { return sorted_.back()->x(); }
  double yty() const { return yty_; }
  const std::vector<const Eigen::Vector2d*>& sorted() const { return sorted_; }

  // a'a and a'y of the model with the breakpoint xb (none: one piece), the points beyond it
  // from index `first` of the sorted points on.
  void normal_equations(std::optional<double> xb, size_t first, Eigen::Matrix4d* ata,
                        Eigen::Vector4d* aty) const {
    const std::array<double, 8>& all = suffix_[0];
    Eigen::Matrix4d& g = *ata;
    g.setZero();
    Eigen::Matrix3d one_ata;
    Eigen::Vector3d one_aty;
    one_piece_normal_equations(all.data(), all.data() + 5, &one_ata, &one_aty);
    g.topLeftCorner<3, 3>() = one_ata;
    *aty << one_aty, 0.0;
    if (!xb) return;
    const std::array<double, 8>& m = suffix_[first];
    const double b1 = *xb, b2 = b1 * b1, b3 = b2 * b1, b4 = b2 * b2;
    const double s_h = 0.5 * (m[2] - 2.0 * b1 * m[1] + b2 * m[0]);
    const double s_hx = 0.5 * (m[3] - 2.0 * b1 * m[2] + b2 * m[1]);
    const double s_hx2 = 0.25 * (m[4] - 2.0 * b1 * m[3] + b2 * m[2]);  // sum of h x^2 / 2
    const double s_hh =
        0.25 * (m[4] - 4.0 * b1 * m[3] + 6.0 * b2 * m[2] - 4.0 * b3 * m[1] + b4 * m[0]);
    const double s_hy = 0.5 * (m[7] - 2.0 * b1 * m[6] + b2 * m[5]);
    g(0, 2) = g(2, 0) = g(0, 2) - s_h;
    g(1, 2) = g(2, 1) = g(1, 2) - s_hx;
    g(2, 2) = g(2, 2) - 2.0 * s_hx2 + s_hh;
    g(0, 3) = g(3, 0) = s_h;
    g(1, 3) = g(3, 1) = s_hx;
    g(2, 3) = g(3, 2) = s_hx2 - s_hh;
    g(3, 3) = s_hh;
    (*aty)[2] -= s_hy;
    (*aty)[3] = s_hy;
  }

  // The sums the term h = (x - xb)_+^2 / 2 adds to the one-piece normal equations, the points
  // beyond xb from index `first` of the sorted points on: u = (sum h, sum h x, sum h x^2 / 2),
  // s = sum h^2, t = sum h y.
  void breakpoint_terms(double xb, size_t first, Eigen::Vector3d* u, double* s, double* t) const {
    const std::array<double, 8>& m = suffix_[first];
    const double b1 = xb, b2 = b1 * b1, b3 = b2 * b1, b4 = b2 * b2;
    *u << 0.5 * (m[2] - 2.0 * b1 * m[1] + b2 * m[0]), 0.5 * (m[3] - 2.0 * b1 * m[2] + b2 * m[1]),
        0.25 * (m[4] - 2.0 * b1 * m[3] + b2 * m[2]);
    *s = 0.25 * (m[4] - 4.0 * b1 * m[3] + 6.0 * b2 * m[2] - 4.0 * b3 * m[1] + b4 * m[0]);
    *t = 0.5 * (m[7] - 2.0 * b1 * m[6] + b2 * m[5]);
  }

  // The first sorted point beyond xb (x > xb), searched from `from` on.
  size_t first_beyond(double xb, size_t from = 0) const {
    while (from < sorted_.size() && sorted_[from]->x() <= xb) ++from;
    return from;
  }

 private:
  std::vector<const Eigen::Vector2d*> sorted_;
  std::vector<std::array<double, 8>> suffix_;  // suffix_[j]: moments of sorted_[j..]
  double yty_ = 0.0;
};

// The breakpoints lo + min_piece, then every breakpoint_step, up to hi - min_piece, ranked by
// their residual y'y - c'a'y. Nullopt when there is none. The residual from the basis (1, x,
// x^2/2, h), h = (x - xb)_+^2 / 2, which spans what the model's does: the one-piece normal
// equations A c = b are the same for every breakpoint, h adds a row and column (u, s) and a
// right-hand side t, and by the Schur complement the residual is y'y - b'A^-1 b - (t - u'A^-1
// b)^2 / (s - u'A^-1 u): A factored once, not a 4 x 4 system solved per breakpoint (12 % of the
// path memory's time).
std::optional<double> best_breakpoint(const PointMoments& m, const JoinedArcsOptions& options) {
  std::optional<double> best;
  double best_rss = std::numeric_limits<double>::infinity();
  size_t first = 0;
  Eigen::Matrix4d ata;
  Eigen::Vector4d aty;
  m.normal_equations(std::nullopt, 0, &ata, &aty);
  const Eigen::LDLT<Eigen::Matrix3d> one_piece(ata.topLeftCorner<3, 3>());
  const Eigen::Vector3d a_inv_b = one_piece.solve(aty.head<3>());
  const Eigen::Matrix3d a_inv = one_piece.solve(Eigen::Matrix3d::Identity());
  const double one_piece_rss = m.yty() - a_inv_b.dot(aty.head<3>());
  for (double xb = m.lo() + options.min_piece_m; xb <= m.hi() - options.min_piece_m;
       xb += options.breakpoint_step_m) {
    first = m.first_beyond(xb, first);
    Eigen::Vector3d u;
    double s, t;
    m.breakpoint_terms(xb, first, &u, &s, &t);
    const double across = s - u.dot(a_inv * u);  // what h adds beyond the one piece's span
    const double unexplained = t - u.dot(a_inv_b);
    const double gain = across > 1e-12 * s ? unexplained * unexplained / across : 0.0;
    const double rss = std::max(0.0, one_piece_rss - gain);
    if (rss < best_rss) {
      best_rss = rss;
      best = xb;
    }
  }
  return best;
}

// The best model over the points marked: one piece, or two with the breakpoint that leaves the
// least residual, kept when it lowers n log(rss / n) by more than log n per extra parameter (two:
// the breakpoint and the second curvature). The residuals of the two models compared are summed
// over the points (exact).
std::pair<Solved, std::optional<double>> best_model(const std::vector<Eigen::Vector2d>& p,
                                                    const std::vector<const Eigen::Vector2d*>& by_x,
                                                    const std::vector<bool>& use,
                                                    const Weights& weight,
                                                    const JoinedArcsOptions& options) {
  const PointMoments m(p, by_x, use, weight);
  const int n = static_cast<int>(m.size());
  if (n < 5) return {Solved{}, std::nullopt};  // three unknowns and two more points
  const double counted = m.total_weight();     // the observations the criterion counts
  Eigen::Matrix4d ata;
  Eigen::Vector4d aty;
  Solved one;
  m.normal_equations(std::nullopt, 0, &ata, &aty);
  one.c = solve_normal(ata, aty, 3);
  one.c[3] = one.c[2];
  const std::optional<double> xb =
      options.joint && n >= 6 ? best_breakpoint(m, options) : std::nullopt;
  Solved two;
  if (xb) {
    m.normal_equations(xb, m.first_beyond(*xb), &ata, &aty);
    two.c = solve_normal(ata, aty, 4);
  }
  one.rss = two.rss = 0.0;
  for (const Eigen::Vector2d* q : m.sorted()) {
    const double w = weight(q - p.data());
    const double r1 = model_y(one.c, q->x(), std::nullopt) - q->y();
    one.rss += w * r1 * r1;
    if (!xb) continue;
    const double r2 = model_y(two.c, q->x(), xb) - q->y();
    two.rss += w * r2 * r2;
  }
  const double floor_rss = 1e-18 * counted;  // noise-free points: no log of zero
  if (xb && n > 6 &&
      counted * std::log((two.rss + floor_rss) / counted) + 2.0 * std::log(counted) <
          counted * std::log((one.rss + floor_rss) / counted))
    return {two, xb};
  return {one, std::nullopt};
}

// Standard deviation of the model's coefficient `index` over the points marked (in order along
// x): (a'Wa)^-1 times the residual variance per observation, inflated by the residuals'
// autocorrelation time and by the mean weight (the observations a point stands for saw the same
// stretch of tape: their wear and the floor's texture are one, which more of them do not average
// out; with every weight 1, the plain estimate).
double coefficient_sigma(const std::vector<Eigen::Vector2d>& p,
                         const std::vector<const Eigen::Vector2d*>& by_x,
                         const std::vector<bool>& use, const Weights& weight, const Solved& model,
                         std::optional<double> xb, int index) {
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  std::vector<double> residuals;
  residuals.reserve(by_x.size());
  double rss = 0.0, counted = 0.0;
  for (const Eigen::Vector2d* q : by_x) {
    if (!use[q - p.data()]) continue;
    const double w = weight(q - p.data());
    const Eigen::Vector4d row = basis(q->x(), xb);
    ata += w * row * row.transpose();
    residuals.push_back(model_y(model.c, q->x(), xb) - q->y());
    rss += w * residuals.back() * residuals.back();
    counted += w;
  }
  const int n_params = xb ? 4 : 3, n = static_cast<int>(residuals.size());
  if (n <= n_params || counted <= n_params) return std::numeric_limits<double>::infinity();
  if (!xb) ata(3, 3) = 1.0;  // the one-piece model has no fourth unknown
  const double inverse = ata.inverse()(index, index);
  const double mean_weight = counted / n;
  return std::sqrt(std::max(0.0, inverse * integrated_autocorrelation_time(residuals) *
                                     mean_weight * rss / (counted - n_params)));
}

// The moments of points for the one-piece model: sums of x^0..x^4 and of x^0..x^2 y
// (one_piece_normal_equations).
struct OnePieceMoments {
  double x[5] = {0.0, 0.0, 0.0, 0.0, 0.0}, xy[3] = {0.0, 0.0, 0.0};

  void add(const Eigen::Vector2d& p, double weight) {
    const double x1 = p.x(), x2 = x1 * x1;
    x[0] += weight;
    x[1] += weight * x1;
    x[2] += weight * x2;
    x[3] += weight * x2 * x1;
    x[4] += weight * x2 * x2;
    xy[0] += weight * p.y();
    xy[1] += weight * x1 * p.y();
    xy[2] += weight * x2 * p.y();
  }
  // (a, b, k) of the least-squares fit.
  Eigen::Vector3d solve() const {
    Eigen::Matrix3d ata;
    Eigen::Vector3d aty;
    one_piece_normal_equations(x, xy, &ata, &aty);
    return ata.ldlt().solve(aty);
  }
};

double one_piece_residual(const Eigen::Vector3d& c, const Eigen::Vector2d& p) {
  return c[0] + p.x() * (c[1] + 0.5 * c[2] * p.x()) - p.y();
}

// One piece from the points' moments in one pass; the points far off dropped once by taking
// their moments out again: what best_model and the outlier pass below do for one piece, without
// ordering the points.
std::optional<JoinedArcs> fit_one_piece(const std::vector<Eigen::Vector2d>& points,
                                        const Weights& weight, double outlier_sigmas) {
  OnePieceMoments moments;
  double counted = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    moments.add(points[i], weight(i));
    counted += weight(i);
  }
  Eigen::Vector3d c = moments.solve();
  std::vector<double> residuals(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    residuals[i] = std::abs(one_piece_residual(c, points[i]));
  const double limit = outlier_limit(residuals, weight.all(), outlier_sigmas);
  int kept = static_cast<int>(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (residuals[i] <= limit) continue;
    moments.add(points[i], -weight(i));
    counted -= weight(i);
    --kept;
  }
  if (kept < 5) return std::nullopt;  // three unknowns and two more points
  if (kept < static_cast<int>(points.size())) c = moments.solve();
  double rss = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (residuals[i] > limit) continue;
    const double r = one_piece_residual(c, points[i]);
    rss += weight(i) * r * r;
  }
  if (!std::isfinite(rss)) return std::nullopt;
  JoinedArcs out;
  out.offset_m = c[0];
  out.slope = c[1];
  out.curvature_1_m = out.curvature_far_1_m = c[2];
  out.points = static_cast<int>(std::lround(counted));
  out.rms_m = std::sqrt(rss / counted);
  return out;
}

}  // namespace

std::optional<JoinedArcs> fit_joined_arcs(const std::vector<Eigen::Vector2d>& points,
                                          const JoinedArcsOptions& options) {
  return fit_joined_arcs(points, {}, options);
}

std::optional<JoinedArcs> fit_joined_arcs(const std::vector<Eigen::Vector2d>& points,
                                          const std::vector<double>& weights,
                                          const JoinedArcsOptions& options) {
  if (points.size() < 6) return std::nullopt;
  const Weights weight(weights);
  bool before = false, after = false;
  for (const Eigen::Vector2d& p : points) {
    before = before || p.x() < 0.0;
    after = after || p.x() > 0.0;
  }
  if (options.both_sides && (!before || !after)) return std::nullopt;
  if (!options.joint && !options.curvature_sigma)
    return fit_one_piece(points, weight, options.outlier_sigmas);
  std::vector<bool> use(points.size(), true);
  // The points in order along x, once for both fits (the breakpoint search and the residuals'
  // autocorrelation need the order; one piece alone does not).
  std::vector<const Eigen::Vector2d*> by_x;
  by_x.reserve(points.size());
  for (const Eigen::Vector2d& p : points) by_x.push_back(&p);
  if (options.joint || options.curvature_sigma)
    std::sort(by_x.begin(), by_x.end(),
              [](const Eigen::Vector2d* a, const Eigen::Vector2d* b) { return a->x() < b->x(); });
  auto [model, xb] = best_model(points, by_x, use, weight, options);
  // Once: drop the points far off (a stray chord, a seam), then fit again.
  std::vector<double> residuals;
  residuals.reserve(points.size());
  for (const Eigen::Vector2d& p : points)
    residuals.push_back(std::abs(model_y(model.c, p.x(), xb) - p.y()));
  const double limit = outlier_limit(residuals, weights, options.outlier_sigmas);
  int kept = 0;
  double counted = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    use[i] = residuals[i] <= limit;
    kept += use[i] ? 1 : 0;
    counted += use[i] ? weight(i) : 0.0;
  }
  if (kept < static_cast<int>(points.size()))
    std::tie(model, xb) = best_model(points, by_x, use, weight, options);
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
  out.points = static_cast<int>(std::lround(counted));
  out.rms_m = std::sqrt(model.rss / std::max(1.0, counted));
  if (options.curvature_sigma)
    out.curvature_sigma_1_m =
        coefficient_sigma(points, by_x, use, weight, model, xb, second_holds ? 3 : 2);
  return out;
}

}  // namespace agv::perception
