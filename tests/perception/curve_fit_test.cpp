#include "perception/curve_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

namespace agv::perception {
namespace {

// A left-turning circle of radius 0.5 m centred at (0.3, 0.5), travelled counter-clockwise
// (forward, +x, at its lowest point (0.3, 0)). The vehicle origin lies outside it, so on the
// right of the path: e_d = -(|C| - R) = -(sqrt(0.34) - 0.5) = -0.083095 m.
TEST(CurveModel, CircleThroughThreePointsHandCase) {
  const Eigen::Vector2d c(0.3, 0.5);
  auto on_circle = [&](double angle) {
    return Eigen::Vector2d(c + 0.5 * Eigen::Vector2d(std::sin(angle), -std::cos(angle)));
  };
  const auto m =
      curve_through(on_circle(-0.2), on_circle(0.1), on_circle(0.4), Eigen::Vector2d::UnitX());
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->curvature_1_m, 2.0, 1e-9);
  EXPECT_NEAR(m->e_d_m, -(std::sqrt(0.34) - 0.5), 1e-9);
  // The foot point is where the ray from the centre to the origin meets the circle; the
  // heading there is perpendicular to that ray, counter-clockwise.
  const Eigen::Vector2d ray = -c.normalized();
  const Eigen::Vector2d foot = c + 0.5 * ray;
  EXPECT_NEAR((m->foot_point() - foot).norm(), 0.0, 1e-9);
  EXPECT_NEAR(m->heading_rad, std::atan2(ray.x(), -ray.y()), 1e-9);
  // Signed distances: 0 on the circle, positive inside (left of a left turn).
  EXPECT_NEAR(m->signed_distance(on_circle(0.7)), 0.0, 1e-12);
  EXPECT_NEAR(m->signed_distance(c + Eigen::Vector2d(0.0, -0.49)), 0.01, 1e-12);
  EXPECT_NEAR(m->signed_distance(c + Eigen::Vector2d(0.0, -0.52)), -0.02, 1e-12);
  // Arc positions: from the foot point to (0.3, 0) is R times the angle between them.
  const double angle = std::acos(ray.dot(Eigen::Vector2d(0.0, -1.0)));
  EXPECT_NEAR(m->arc_position({0.3, 0.0}), 0.5 * angle, 1e-9);
  EXPECT_NEAR((m->point_at(0.5 * angle) - Eigen::Vector2d(0.3, 0.0)).norm(), 0.0, 1e-9);
}

TEST(CurveModel, StraightLineIsTheZeroCurvatureCase) {
  // The line y = 0.01 along +x: the vehicle is 10 mm right of it.
  const auto m = curve_through({0.2, 0.01}, {0.3, 0.01}, {0.4, 0.01}, Eigen::Vector2d::UnitX());
  ASSERT_TRUE(m);
  EXPECT_DOUBLE_EQ(m->curvature_1_m, 0.0);
  EXPECT_NEAR(m->e_d_m, -0.01, 1e-12);
  EXPECT_NEAR(m->heading_rad, 0.0, 1e-12);
  EXPECT_NEAR(m->signed_distance({0.5, 0.03}), 0.02, 1e-12);
  // A tiny curvature gives nearly the same distances: no singularity at 0.
  CurveModel bent = *m;
  bent.curvature_1_m = 1e-9;
  EXPECT_NEAR(bent.signed_distance({0.5, 0.03}), 0.02, 1e-9);
}

// A left arc of radius 0.5 m heading along x: a quarter circle on (s = pi/4 m) it heads along
// +y; a line's direction is the same everywhere; and the direction is the derivative of
// point_at.
TEST(CurveModel, TangentAtTurnsWithTheCurvature) {
  const CurveModel arc{0.01, 0.0, 2.0};
  EXPECT_NEAR(arc.tangent_at(M_PI / 4).x(), 0.0, 1e-12);
  EXPECT_NEAR(arc.tangent_at(M_PI / 4).y(), 1.0, 1e-12);
  const CurveModel line{0.01, 0.3, 0.0};
  EXPECT_NEAR((line.tangent_at(5.0) - line.tangent()).norm(), 0.0, 1e-12);
  for (double s : {-0.3, 0.1, 0.7}) {
    const Eigen::Vector2d slope = (arc.point_at(s + 1e-6) - arc.point_at(s - 1e-6)) / 2e-6;
    EXPECT_NEAR((slope - arc.tangent_at(s)).norm(), 0.0, 1e-8) << s;
  }
}

// The order key sorts points as the arc position does: pairs of points on arcs of both turns
// (tight ones: R 0.1 m, where points half way round lie beyond the quarter turn a projection
// would stay monotonic over), a near-line and a line, near the curve and off it, all round the
// circle (the arc position's cut opposite the foot point included).
TEST(CurveModel, ArcOrderKeySortsAsTheArcPosition) {
  cv::RNG rng(17);
  for (const CurveModel& m :
       {CurveModel{0.01, 0.3, 10.0}, CurveModel{-0.02, -1.0, -10.0}, CurveModel{0.0, 2.0, 1.5},
        CurveModel{0.003, 0.2, 1e-10}, CurveModel{0.003, 0.2, 0.0}}) {
    const CurveModel::Prepared curve = m.prepared();
    const double radius = std::abs(m.curvature_1_m) > 1e-9 ? 1.0 / std::abs(m.curvature_1_m) : 1.0;
    for (int pair = 0; pair < 2000; ++pair) {
      Eigen::Vector2d p[2];
      for (Eigen::Vector2d& q : p) {
        const double s = rng.uniform(-3.0, 3.0) * radius, off = rng.uniform(-0.5, 0.5) * radius;
        q = m.point_at(s) + off * Eigen::Vector2d(-m.tangent_at(s).y(), m.tangent_at(s).x());
      }
      const double a0 = curve.arc_position(p[0]), a1 = curve.arc_position(p[1]);
      if (std::abs(a0 - a1) < 1e-9) continue;
      EXPECT_EQ(curve.arc_order_key(p[0]) < curve.arc_order_key(p[1]), a0 < a1)
          << "curvature " << m.curvature_1_m << ", arc positions " << a0 << ", " << a1;
    }
  }
}

TEST(CurveModel, ReversedIsTheSameCurve) {
  const CurveModel m{0.004, 0.1, 1.5};
  const CurveModel r = m.reversed();
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.3, 0.02), Eigen::Vector2d(0.25, -0.05)}) {
    EXPECT_NEAR(r.signed_distance(p), -m.signed_distance(p), 1e-12);
  }
}

// A circle of R 0.1 m about (0.25, 0) travelled anticlockwise, and the line x = 0.35 m
// travelled in +y: at (0.35, 0) they touch, running the same way. At the origin's foot points,
// (0.15, 0) on the circle and (0.35, 0) on the line, the circle runs in -y and the line in +y:
// compared there they would seem opposite (by hand).
TEST(CurveModel, OrientedLikeComparesWhereTheCurvesAreSeen) {
  const Eigen::Vector2d touch(0.35, 0.0);
  const CurveModel circle = curve_through_point(touch, M_PI / 2, 10.0);
  const CurveModel line = curve_through_point(touch, M_PI / 2, 0.0);
  ASSERT_LT(circle.tangent().dot(line.tangent()), -0.99);  // the trap at the foot points
  for (const CurveModel& m : {line, line.reversed()}) {
    const CurveModel oriented = m.oriented_like(circle, touch);
    EXPECT_NEAR(oriented.tangent_at(oriented.arc_position(touch)).y(), 1.0, 1e-9);
  }
  for (const CurveModel& m : {circle, circle.reversed()}) {
    const CurveModel oriented = m.oriented_like(line.reversed(), touch);
    EXPECT_NEAR(oriented.tangent_at(oriented.arc_position(touch)).y(), -1.0, 1e-9);
  }
}

// The gradient the fits' Gauss-Newton steps use, against central differences of the signed
// distance, on arcs of both turns, a line and a tight arc, at points on both sides. Central
// differences with steps of 1e-6 are good to ~1e-9 here (third derivatives of order 1-100);
// a wrong term of the gradient is off by 1e-4 or more at these points.
TEST(CurveModel, SignedDistanceGradientMatchesDifferences) {
  const std::vector<CurveModel> curves = {
      {0.004, 0.1, 1.5}, {-0.02, -0.4, -2.5}, {0.01, 0.3, 0.0}, {0.03, 2.0, 8.0}};
  const std::vector<Eigen::Vector2d> points = {
      {0.3, 0.02}, {0.25, -0.05}, {0.1, 0.08}, {-0.05, 0.01}};
  constexpr double h = 1e-6;
  for (const CurveModel& m : curves) {
    for (const Eigen::Vector2d& p : points) {
      Eigen::Vector3d gradient;
      const double d = m.prepared().signed_distance(p, &gradient);
      EXPECT_NEAR(d, m.signed_distance(p), 1e-15);
      for (int i = 0; i < 3; ++i) {
        CurveModel plus = m, minus = m;
        double* plus_parameter[3] = {&plus.e_d_m, &plus.heading_rad, &plus.curvature_1_m};
        double* minus_parameter[3] = {&minus.e_d_m, &minus.heading_rad, &minus.curvature_1_m};
        *plus_parameter[i] += h;
        *minus_parameter[i] -= h;
        const double difference = (plus.signed_distance(p) - minus.signed_distance(p)) / (2 * h);
        EXPECT_NEAR(gradient[i], difference, 1e-7)
            << "parameter " << i << " of (" << m.e_d_m << ", " << m.heading_rad << ", "
            << m.curvature_1_m << ") at (" << p.x() << ", " << p.y() << ")";
      }
    }
  }
}

struct Noisy {
  std::vector<Eigen::Vector2d> points;
};

Noisy sample(const CurveModel& truth, double s0, double s1, int count, double noise_m,
             double outlier_fraction, std::uint64_t seed) {
  cv::RNG rng(seed);
  Noisy out;
  for (int i = 0; i < count; ++i) {
    const double s = s0 + (s1 - s0) * i / (count - 1);
    Eigen::Vector2d p = truth.point_at(s);
    const Eigen::Vector2d n = truth.normal();
    if (rng.uniform(0.0, 1.0) < outlier_fraction) {
      p += Eigen::Vector2d(rng.uniform(-0.05, 0.05), rng.uniform(0.01, 0.05));
    } else {
      // Perpendicular noise: move along the curve's normal at s.
      const Eigen::Vector2d ahead = truth.point_at(s + 1e-4) - truth.point_at(s - 1e-4);
      const Eigen::Vector2d local_normal(-ahead.y(), ahead.x());
      p += rng.gaussian(noise_m) * local_normal.normalized();
      (void)n;
    }
    out.points.push_back(p);
  }
  return out;
}

// An arc of radius 0.4 m seen 0.2-0.4 m ahead, 0.05 mm noise, 20 % outliers: the fit recovers the
// curvature and extrapolates the errors back to the vehicle origin. Tolerances: 300 points of
// 0.05 mm noise over 0.2 m determine the curvature to ~0.01 1/m (sigma), so e_d at 0.3 m back
// to ~0.5 mm at 3 sigma and the heading to ~0.2 deg.
TEST(CurveFit, RecoversAnArcWithOutliers) {
  const CurveModel truth{0.006, -0.05, 2.5};
  const Noisy data = sample(truth, 0.2, 0.4, 300, 0.00005, 0.2, 1);
  const CurveFit fit = fit_curve_robust(data.points, CurveFitOptions{});
  ASSERT_TRUE(fit.ok);
  EXPECT_FALSE(fit.is_line);
  EXPECT_NEAR(fit.model.curvature_1_m, 2.5, 0.03);
  EXPECT_NEAR(fit.model.e_d_m, 0.006, 0.0005);
  EXPECT_NEAR(fit.model.heading_rad, -0.05, 0.004);
  EXPECT_GE(fit.inlier_count, 220);
  EXPECT_NEAR(fit.s_max_m - fit.s_min_m, 0.2, 0.01);
}

TEST(CurveFit, AStraightTapeStaysAStraightLine) {
  const CurveModel truth{-0.012, 0.08, 0.0};
  const Noisy data = sample(truth, 0.2, 0.4, 300, 0.00005, 0.0, 2);
  const CurveFit fit = fit_curve_robust(data.points, CurveFitOptions{});
  ASSERT_TRUE(fit.ok);
  EXPECT_TRUE(fit.is_line);
  EXPECT_DOUBLE_EQ(fit.model.curvature_1_m, 0.0);
  EXPECT_NEAR(fit.model.e_d_m, -0.012, 0.0001);
  EXPECT_NEAR(fit.model.heading_rad, 0.08, 0.0005);
}

TEST(CurveFit, MaskSelectsThePointsToUse) {
  const CurveModel a{0.0, 0.0, 0.0}, b{0.05, 0.6, 0.0};
  Noisy data = sample(a, 0.2, 0.4, 100, 0.00005, 0.0, 3);
  const Noisy other = sample(b, 0.2, 0.4, 150, 0.00005, 0.0, 4);
  data.points.insert(data.points.end(), other.points.begin(), other.points.end());
  std::vector<bool> mask(250, false);
  for (int i = 0; i < 100; ++i) mask[i] = true;
  const CurveFit fit = fit_curve_robust(data.points, CurveFitOptions{}, &mask);
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(fit.model.heading_rad, 0.0, 0.001);
  EXPECT_EQ(fit.inlier_count, 100);
}

}  // namespace
}  // namespace agv::perception
