#include "control/hermite_cubic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/angles.h"
#include "control/path.h"

namespace agv::control {
namespace {

// The exact arc of hermite_arc_pieces: start (1, 2) heading 0.3 rad, radius 0.5, turning left;
// its centre is 0.5 m to the left of the start.
const Pose2 kStart{1.0, 2.0, 0.3};
constexpr double kRadius = 0.5;
Eigen::Vector2d centre() {
  return kStart.translation() +
         kRadius * Eigen::Vector2d(-std::sin(kStart.yaw_rad), std::cos(kStart.yaw_rad));
}
Eigen::Vector2d arc_point(double turned_rad) {
  const double h = kStart.yaw_rad + turned_rad;
  return centre() + kRadius * Eigen::Vector2d(std::sin(h), -std::cos(h));
}

TEST(HermiteCubic, BasisMeetsItsEndConditions) {
  const HermiteCubic c{{0.0, 0.0}, {1.0, 2.0}, {3.0, -1.0}, {-2.0, 0.5}};
  EXPECT_TRUE(c.point(0.0).isApprox(c.p0));
  EXPECT_TRUE(c.point(1.0).isApprox(c.p1));
  EXPECT_TRUE(c.derivative(0.0).isApprox(c.d0));
  EXPECT_TRUE(c.derivative(1.0).isApprox(c.d1));
  // A straight piece with equal end tangents is the straight line at constant speed.
  const HermiteCubic line{{0.0, 0.0}, {2.0, 0.0}, {2.0, 0.0}, {2.0, 0.0}};
  EXPECT_NEAR(line.point(0.25).x(), 0.5, 1e-15);
  EXPECT_NEAR(line.length_m(0.0, 1.0), 2.0, 1e-12);
  EXPECT_NEAR(line.curvature_1_m(0.4), 0.0, 1e-15);
}

// Seed 004 S1: each piece matches the exact arc's position and derivative at both ends.
TEST(HermiteCubic, ArcPiecesMatchTheArcAtTheirEnds) {
  for (int m : {1, 2, 3, 4}) {
    const double piece_rad = (kPi / 2) / m;
    const auto pieces = hermite_arc_pieces(kStart, kRadius, kPi / 2, m);
    ASSERT_EQ(static_cast<int>(pieces.size()), m);
    for (int i = 0; i < m; ++i) {
      for (int end = 0; end <= 1; ++end) {
        const double turned = (i + end) * piece_rad;
        const double h = kStart.yaw_rad + turned;
        const Eigen::Vector2d expected_derivative =
            kRadius * piece_rad * Eigen::Vector2d(std::cos(h), std::sin(h));
        EXPECT_LT((pieces[i].point(end) - arc_point(turned)).norm(), 1e-12) << m << " " << i;
        EXPECT_LT((pieces[i].derivative(end) - expected_derivative).norm(), 1e-12);
      }
    }
  }
}

// The deviation from the exact arc at the same parameter stays under the derived bound
// r theta^4 / 384 and falls with the fourth power of the number of pieces.
TEST(HermiteCubic, DeviationFromTheArcWithinTheDerivedBound) {
  double previous_m = 0.0;
  for (int m : {1, 2, 4}) {
    const double piece_rad = (kPi / 2) / m;
    const auto pieces = hermite_arc_pieces(kStart, kRadius, kPi / 2, m);
    double worst_m = 0.0, worst_radial_m = 0.0;
    for (int i = 0; i < m; ++i) {
      for (int k = 0; k <= 200; ++k) {
        const double u = k / 200.0;
        const Eigen::Vector2d h = pieces[i].point(u);
        worst_m = std::max(worst_m, (h - arc_point((i + u) * piece_rad)).norm());
        worst_radial_m = std::max(worst_radial_m, std::abs((h - centre()).norm() - kRadius));
      }
    }
    const double bound_m = hermite_arc_deviation_bound_m(kRadius, piece_rad);
    std::printf("m = %d: max deviation %.4f mm (radial %.4f mm), bound %.4f mm\n", m, 1e3 * worst_m,
                1e3 * worst_radial_m, 1e3 * bound_m);
    EXPECT_LE(worst_m, bound_m);
    EXPECT_LE(worst_radial_m, worst_m);
    // Fourth order: halving the piece angle divides the error by about 2^4 = 16.
    if (previous_m > 0.0) {
      EXPECT_NEAR(previous_m / worst_m, 16.0, 3.0);
    }
    previous_m = worst_m;
  }
  // The bound itself for a quarter turn of 0.5 m in one piece: 0.5 (pi/2)^4 / 384 = 7.93 mm.
  EXPECT_NEAR(hermite_arc_deviation_bound_m(0.5, kPi / 2), 7.927e-3, 1e-6);
}

// A path built from Hermite pieces: length and foot points close to the exact arc's.
TEST(HermiteCubic, PathOfHermitePiecesProjectsLikeTheArc) {
  const Path exact =
      Path::starting_at({0.0, 0.0, 0.0}).add_line(1.0).add_arc(0.5, kPi / 2).add_line(1.0);
  const Path hermite = Path::starting_at({0.0, 0.0, 0.0})
                           .add_line(1.0)
                           .add_hermite_arc(0.5, kPi / 2, 4)
                           .add_line(1.0);
  ASSERT_EQ(hermite.segments().size(), 6u);
  // Four pieces of 22.5 deg: bound 0.5 * 0.3927^4 / 384 = 0.031 mm on position, so the
  // length and every foot point agree with the arc's to well under 0.1 mm.
  EXPECT_NEAR(hermite.length_m(), exact.length_m(), 1e-4);
  EXPECT_LT((hermite.end_pose().translation() - Eigen::Vector2d(1.5, 1.5)).norm(), 1e-9);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(1.2, 0.3), Eigen::Vector2d(1.001, -0.01),
                                   Eigen::Vector2d(1.49, 0.52), Eigen::Vector2d(1.3, 0.1)}) {
    const PathProjection a = exact.project(p), b = hermite.project(p);
    EXPECT_NEAR(a.lateral_m, b.lateral_m, 1e-4) << p.transpose();
    EXPECT_NEAR(a.s_m, b.s_m, 2e-4) << p.transpose();
    EXPECT_NEAR(a.heading_rad, b.heading_rad, 2e-3) << p.transpose();
    EXPECT_NEAR(b.curvature_1_m, a.curvature_1_m, 0.2) << p.transpose();
  }
  // Point (1.2, 0.3), worked by hand on the exact arc: 0.2828 m from the centre (1, 0.5) at
  // -45 deg, so s = 1 + 0.5 pi/4 and lateral = 0.5 - 0.2828 (inside a left turn: left).
  const PathProjection p = hermite.project({1.2, 0.3});
  EXPECT_NEAR(p.s_m, 1.0 + 0.125 * kPi, 2e-4);
  EXPECT_NEAR(p.lateral_m, 0.5 - std::sqrt(0.08), 1e-4);
  // Arc length and point agree: walking along s reaches the points of the curve.
  for (double s = 0.0; s <= hermite.length_m(); s += 0.05) {
    const PathProjection back = hermite.project(hermite.point_at(s), s, 0.2);
    EXPECT_NEAR(back.s_m, s, 1e-9);
    EXPECT_NEAR(back.distance_m, 0.0, 1e-9);
  }
}

TEST(HermiteCubic, GeneralPieceToAnEndPose) {
  Path path = Path::starting_at({0.0, 0.0, 0.0});
  path.add_hermite_to({1.0, 0.5, kPi / 2});
  const Pose2 end = path.end_pose();
  EXPECT_NEAR(end.x_m, 1.0, 1e-12);
  EXPECT_NEAR(end.y_m, 0.5, 1e-12);
  EXPECT_NEAR(end.yaw_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(path.heading_at(0.0), 0.0, 1e-12);
  EXPECT_GT(path.curvature_at(0.5 * path.length_m()), 0.0);  // turns left
  // Longer than the chord, shorter than the two legs of the box around it.
  EXPECT_GT(path.length_m(), std::hypot(1.0, 0.5));
  EXPECT_LT(path.length_m(), 1.5);
}

}  // namespace
}  // namespace agv::control
