#include "perception/joined_arcs_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <random>

namespace agv::perception {
namespace {

// Exact points of a tape that runs straight along x up to x_b and then turns left on an arc of
// curvature k (a line joined to an arc with a common tangent), from x0 to x1 every step, with
// Gaussian noise sigma across it.
std::vector<Eigen::Vector2d> line_then_arc(double offset_m, double x_b, double k, double x0,
                                           double x1, double sigma_m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::vector<Eigen::Vector2d> points;
  for (double s = x0; s <= x1; s += 0.0005) {
    Eigen::Vector2d p(s, offset_m);
    if (s > x_b) {  // on the arc, s the arc length from the joint
      const double a = k * (s - x_b);
      p = Eigen::Vector2d(x_b + std::sin(a) / k, offset_m + (1.0 - std::cos(a)) / k);
    }
    points.push_back(p + Eigen::Vector2d(0.0, noise(rng)));
  }
  return points;
}

// A line joined to an arc of R 0.5 m 12 mm ahead of x = 0: the fit keeps two pieces, puts the
// joint where it is (within two breakpoint steps, 8 mm: the arc departs from the line by only
// k d^2 / 2 = 0.06 mm after 8 mm, less than the noise of 0.05 mm times the few points there)
// and reports the line's curvature (0) and offset at x = 0, not the arc's.
TEST(JoinedArcsFit, FindsTheJointBetweenALineAndAnArc) {
  const double k = 2.0;
  const std::vector<Eigen::Vector2d> points = line_then_arc(0.004, 0.012, k, -0.05, 0.05, 5e-5, 3);
  const std::optional<JoinedArcs> fit = fit_joined_arcs(points);
  ASSERT_TRUE(fit);
  ASSERT_TRUE(fit->break_x_m);
  EXPECT_NEAR(*fit->break_x_m, 0.012, 0.008);
  EXPECT_NEAR(fit->offset_m, 0.004, 5e-5);    // 1 sigma of one point: many points average
  EXPECT_NEAR(fit->slope, 0.0, 0.003);        // 0.17 deg
  EXPECT_NEAR(fit->curvature_1_m, 0.0, 0.3);  // vs 2.0 on the arc
  EXPECT_NEAR(fit->curvature_far_1_m, k, 0.4);
  EXPECT_LT(fit->rms_m, 8e-5);
}

// The breakpoint chosen is the one of the grid (every 4 mm from 10 mm past the first point to 10
// mm before the last) whose two-piece least squares leaves the least residual, the residual
// here computed independently for each breakpoint by a QR least squares over the design matrix
// (the fit ranks them from running sums of the points' moments). Points without outliers
// (uniform noise: none is 4 robust sigmas off), so the fit keeps them all; arcs joined at
// several places and curvatures, the joint off the grid.
TEST(JoinedArcsFit, TheBreakpointIsTheGridsLeastSquaresBest) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> noise(-3e-5, 3e-5);
  int two_piece = 0;
  for (const double joint : {-0.021, 0.0037, 0.0185, 0.033}) {
    for (const double k : {-3.0, 1.2, 6.0}) {
      std::vector<Eigen::Vector2d> points;
      for (double s = -0.05; s <= 0.0601; s += 0.0007) {
        const double y = s > joint ? 0.5 * k * (s - joint) * (s - joint) : 0.0;
        points.emplace_back(s, 0.002 + 0.05 * s + y + noise(rng));
      }
      const std::optional<JoinedArcs> fit = fit_joined_arcs(points);
      ASSERT_TRUE(fit);
      ASSERT_EQ(fit->points, static_cast<int>(points.size()));
      double best_rss = INFINITY, best_xb = NAN;
      const double lo = points.front().x(), hi = points.back().x();
      for (double xb = lo + 0.01; xb <= hi - 0.01; xb += 0.004) {
        Eigen::MatrixXd a(points.size(), 4);
        Eigen::VectorXd y(points.size());
        for (size_t i = 0; i < points.size(); ++i) {
          const double x = points[i].x(), h = x > xb ? 0.5 * (x - xb) * (x - xb) : 0.0;
          a.row(i) << 1.0, x, 0.5 * x * x - h, h;
          y[i] = points[i].y();
        }
        const double rss = (a * a.householderQr().solve(y) - y).squaredNorm();
        if (rss < best_rss) {
          best_rss = rss;
          best_xb = xb;
        }
      }
      if (!fit->break_x_m) continue;  // the information criterion kept one piece
      ++two_piece;
      EXPECT_NEAR(*fit->break_x_m, best_xb, 1e-9) << "joint " << joint << " k " << k;
    }
  }
  EXPECT_GE(two_piece, 10);  // of 12: the joints are all clear (k >= 1.2 over >= 2 cm)
}

// One arc all through: no joint is invented (the two-piece model does not explain the points
// better by what the information criterion asks), and the curvature is the arc's.
TEST(JoinedArcsFit, OneArcHasNoJoint) {
  // The arc of R 1 m starts (tangent to x) just before the first point.
  const std::vector<Eigen::Vector2d> points =
      line_then_arc(-0.002, -0.0501, 1.0, -0.05, 0.05, 5e-5, 4);
  const std::optional<JoinedArcs> fit = fit_joined_arcs(points);
  ASSERT_TRUE(fit);
  EXPECT_FALSE(fit->break_x_m);
  // At x = 0, 50 mm along the arc: slope tan(0.05), y = -0.002 + (1 - cos 0.05); the fit's
  // curvature is y'' = k / cos^3 = 1.004 (the frame's slope is small).
  EXPECT_NEAR(fit->slope, std::tan(0.05), 0.003);
  EXPECT_NEAR(fit->offset_m, -0.002 + (1.0 - std::cos(0.05)), 5e-5);
  EXPECT_NEAR(fit->curvature_1_m, 1.0, 0.3);
  EXPECT_LT(fit->rms_m, 8e-5);
}

// The curvature's standard deviation is what the scatter of the curvature over many noisy sets
// of points is (an independent measure: 400 draws), for independent noise and for noise shared
// by runs of 8 neighbouring points (the same wear seen from 8 frames), which a variance for
// independent points would put at about sqrt(8) times too small (measured without the
// correlation's inflation: 0.019 against a scatter of 0.054 1/m). Within 25 %: the standard error
// of a standard deviation from 400 draws is 3.5 %, and the autocorrelation sum is itself an
// estimate from each set's 200 points. One arc only (pieces of at least 60 mm leave no room for
// a joint in 100 mm).
TEST(JoinedArcsFit, TheCurvaturesUncertaintyIsItsScatter) {
  JoinedArcsOptions options;
  options.curvature_sigma = true;
  options.min_piece_m = 0.06;
  for (int run_length : {1, 8}) {
    std::mt19937_64 rng(17);
    std::normal_distribution<double> noise(0.0, 1e-4);
    double sum = 0.0, sum2 = 0.0, sigma_sum = 0.0;
    constexpr int kDraws = 400;
    for (int draw = 0; draw < kDraws; ++draw) {
      std::vector<Eigen::Vector2d> points;
      double shared = 0.0;
      for (int i = 0; i < 200; ++i) {
        if (i % run_length == 0) shared = noise(rng);
        const double x = -0.05 + 0.1 * i / 199.0;
        points.emplace_back(x, 0.5 * x * x + shared);  // curvature 1 1/m
      }
      const std::optional<JoinedArcs> fit = fit_joined_arcs(points, options);
      ASSERT_TRUE(fit);
      ASSERT_FALSE(fit->break_x_m);
      sum += fit->curvature_1_m;
      sum2 += fit->curvature_1_m * fit->curvature_1_m;
      sigma_sum += fit->curvature_sigma_1_m;
    }
    const double mean = sum / kDraws;
    const double scatter = std::sqrt(sum2 / kDraws - mean * mean);
    const double reported = sigma_sum / kDraws;
    EXPECT_NEAR(mean, 1.0, 3.0 * scatter / std::sqrt(kDraws));
    EXPECT_NEAR(reported / scatter, 1.0, 0.25) << "runs of " << run_length;
    std::printf("runs of %d: curvature sigma %.4f, scatter %.4f 1/m\n", run_length, reported,
                scatter);
  }
}

// One piece only (`joint = false`, what the path memory's preview fits first): the least squares
// of y = a + b x + k x^2 / 2 over the points that are not far off, here computed independently by
// a QR least squares over the design matrix of the points known to be good. An arc of R 0.5 m
// with 0.05 mm of noise and four points 3 mm off (a stray chord): they are dropped, and the
// answer is that of the good points to rounding (1e-9 of a metre; with them in it moves by
// tens of micrometres). Its joint is never sought, even on a line joined to an arc.
TEST(JoinedArcsFit, OnePieceIsTheLeastSquaresOfTheGoodPoints) {
  // The arc starts at x = -0.03 m (y = 0.002 m + (x + 0.03 m)^2 for k = 2 / m).
  const std::vector<Eigen::Vector2d> good = line_then_arc(0.002, -0.03, 2.0, -0.03, 0.03, 5e-5, 17);
  std::vector<Eigen::Vector2d> points = good;
  for (double x : {-0.02, -0.005, 0.01, 0.025})
    points.push_back({x, 0.002 + (x + 0.03) * (x + 0.03) + 0.003});
  JoinedArcsOptions one_piece;
  one_piece.joint = false;
  const std::optional<JoinedArcs> fit = fit_joined_arcs(points, one_piece);
  ASSERT_TRUE(fit);
  Eigen::MatrixXd design(good.size(), 3);
  Eigen::VectorXd y(good.size());
  for (size_t i = 0; i < good.size(); ++i) {
    design.row(i) << 1.0, good[i].x(), 0.5 * good[i].x() * good[i].x();
    y[i] = good[i].y();
  }
  const Eigen::Vector3d c = design.colPivHouseholderQr().solve(y);
  EXPECT_EQ(fit->points, static_cast<int>(good.size()));
  EXPECT_NEAR(fit->offset_m, c[0], 1e-9);
  EXPECT_NEAR(fit->slope, c[1], 1e-9);
  EXPECT_NEAR(fit->curvature_1_m, c[2], 1e-6);
  EXPECT_NEAR(fit->rms_m, std::sqrt((design * c - y).squaredNorm() / good.size()), 1e-9);
  EXPECT_FALSE(fit->break_x_m);

  const std::optional<JoinedArcs> joined =
      fit_joined_arcs(line_then_arc(0.0, 0.0, 2.0, -0.03, 0.03, 0.0, 3), one_piece);
  ASSERT_TRUE(joined);
  EXPECT_FALSE(joined->break_x_m);
  EXPECT_EQ(joined->curvature_1_m, joined->curvature_far_1_m);
}

// A point with weight n counts as n copies of it: the weighted fit (one piece, and joined arcs
// with their breakpoint search and outlier pass) equals the plain fit of the points repeated, on
// a line joined to an arc with noise and a few points far off.
TEST(JoinedArcsFit, AWeightCountsAsThatManyCopies) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> weight(1, 20);
  std::vector<Eigen::Vector2d> points = line_then_arc(0.002, 0.01, 3.0, -0.05, 0.05, 5e-5, 9);
  for (size_t i = 0; i < points.size(); i += 37) points[i].y() += 0.002;  // far off
  std::vector<double> weights;
  std::vector<Eigen::Vector2d> repeated;
  for (const Eigen::Vector2d& p : points) {
    weights.push_back(weight(rng));
    repeated.insert(repeated.end(), static_cast<size_t>(weights.back()), p);
  }
  JoinedArcsOptions one_piece;
  one_piece.joint = false;
  for (const JoinedArcsOptions& options : {JoinedArcsOptions{}, one_piece}) {
    const std::optional<JoinedArcs> weighted = fit_joined_arcs(points, weights, options);
    const std::optional<JoinedArcs> copies = fit_joined_arcs(repeated, options);
    ASSERT_TRUE(weighted && copies);
    EXPECT_EQ(weighted->points, copies->points);
    EXPECT_LT(weighted->points, static_cast<int>(repeated.size()));  // the far points dropped
    EXPECT_EQ(weighted->break_x_m.has_value(), copies->break_x_m.has_value());
    if (weighted->break_x_m && copies->break_x_m) {
      EXPECT_NEAR(*weighted->break_x_m, *copies->break_x_m, 1e-12);
    }
    EXPECT_NEAR(weighted->offset_m, copies->offset_m, 1e-9);
    EXPECT_NEAR(weighted->slope, copies->slope, 1e-8);
    EXPECT_NEAR(weighted->curvature_1_m, copies->curvature_1_m, 1e-5);
    EXPECT_NEAR(weighted->curvature_far_1_m, copies->curvature_far_1_m, 1e-5);
    EXPECT_NEAR(weighted->rms_m, copies->rms_m, 1e-9);
  }
  // Where every weight is 1, the plain fit exactly.
  const std::optional<JoinedArcs> ones =
      fit_joined_arcs(points, std::vector<double>(points.size(), 1.0));
  const std::optional<JoinedArcs> plain = fit_joined_arcs(points);
  ASSERT_TRUE(ones && plain);
  EXPECT_EQ(ones->offset_m, plain->offset_m);
  EXPECT_EQ(ones->curvature_1_m, plain->curvature_1_m);
}

// Too few points, or points on one side of x = 0 only: no fit.
TEST(JoinedArcsFit, RefusesTooFewPointsOrOneSide) {
  EXPECT_FALSE(fit_joined_arcs(line_then_arc(0.0, 1.0, 1.0, -0.001, 0.001, 0.0, 5)));
  EXPECT_FALSE(fit_joined_arcs(line_then_arc(0.0, 1.0, 1.0, 0.01, 0.05, 0.0, 5)));
}

}  // namespace
}  // namespace agv::perception
