#include "control/path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/angles.h"

namespace agv::control {
namespace {

// Line along +x from the origin, then a left quarter circle of radius 0.5 around (1.0, 0.5),
// then a line along +y from (1.5, 0.5).
Path l_turn() {
  return Path::starting_at({0.0, 0.0, 0.0}).add_line(1.0).add_arc(0.5, kPi / 2).add_line(1.0);
}

TEST(Path, GeometryOfLineArcLine) {
  const Path path = l_turn();
  EXPECT_NEAR(path.length_m(), 2.0 + 0.5 * kPi / 2, 1e-12);
  const Eigen::Vector2d end_of_arc = path.point_at(1.0 + 0.25 * kPi);
  EXPECT_NEAR(end_of_arc.x(), 1.5, 1e-12);
  EXPECT_NEAR(end_of_arc.y(), 0.5, 1e-12);
  EXPECT_NEAR(path.heading_at(1.0 + 0.25 * kPi), kPi / 2, 1e-12);
  EXPECT_NEAR(path.curvature_at(1.2), 2.0, 1e-12);
  // Half-way round the arc: 45 deg from the centre (1.0, 0.5).
  const Eigen::Vector2d mid = path.point_at(1.0 + 0.125 * kPi);
  EXPECT_NEAR(mid.x(), 1.0 + 0.5 * std::sin(kPi / 4), 1e-12);
  EXPECT_NEAR(mid.y(), 0.5 - 0.5 * std::cos(kPi / 4), 1e-12);
}

// Foot points worked by hand; lateral is positive on the left of the travel direction.
TEST(Path, FootPointsOnLinesAndArcs) {
  const Path path = l_turn();
  PathProjection p = path.project({0.4, 0.03});
  EXPECT_NEAR(p.s_m, 0.4, 1e-12);
  EXPECT_NEAR(p.lateral_m, 0.03, 1e-12);
  p = path.project({0.4, -0.02});
  EXPECT_NEAR(p.lateral_m, -0.02, 1e-12);
  // Inside the arc (towards the centre) is the left of a left turn: lateral > 0.
  const Eigen::Vector2d centre(1.0, 0.5);
  p = path.project(centre + 0.45 * Eigen::Vector2d(std::sin(kPi / 6), -std::cos(kPi / 6)));
  EXPECT_NEAR(p.s_m, 1.0 + 0.5 * kPi / 6, 1e-12);
  EXPECT_NEAR(p.lateral_m, 0.05, 1e-12);
  EXPECT_NEAR(p.heading_rad, kPi / 6, 1e-12);
  EXPECT_EQ(p.segment, 1);
  // Near the joint of the first line and the arc, just before and just after.
  p = path.project({0.999, -0.01});
  EXPECT_NEAR(p.s_m, 0.999, 1e-12);
  EXPECT_NEAR(p.lateral_m, -0.01, 1e-12);
  p = path.project({1.001, -0.01});
  EXPECT_EQ(p.segment, 1);
  EXPECT_NEAR(p.lateral_m, -(std::hypot(0.001, 0.51) - 0.5), 1e-12);
}

TEST(Path, PointsBeyondTheEnds) {
  const Path path = l_turn();
  PathProjection p = path.project({-0.2, 0.0});
  EXPECT_TRUE(p.before_start);
  EXPECT_NEAR(p.s_m, 0.0, 1e-12);
  p = path.project({1.5, 2.0});
  EXPECT_TRUE(p.after_end);
  EXPECT_NEAR(p.s_m, path.length_m(), 1e-12);
}

// Against brute force on a path of lines, left and right arcs and a Hermite piece: the foot
// point of random points within 0.3 m is as near as the nearest of samples 0.1 mm apart (to
// 1e-6 m: the samples' spacing squared over the radius), and |lateral| is that distance where the
// foot lies inside a piece (the offset is perpendicular there), positive to the left of the
// heading there.
TEST(Path, ProjectionIsTheNearestPointOfDenseSamples) {
  const Path path = Path::starting_at({0.2, -0.1, 0.3})
                        .add_line(0.5)
                        .add_arc(0.4, kPi / 3)
                        .add_arc(0.25, -kPi / 2)
                        .add_hermite_to({1.6, 0.2, -0.4})
                        .add_line(0.3);
  std::vector<Eigen::Vector2d> samples;
  for (double s = 0.0; s <= path.length_m(); s += 1e-4) samples.push_back(path.point_at(s));
  samples.push_back(path.point_at(path.length_m()));
  unsigned state = 12345;
  auto uniform = [&](double lo, double hi) {
    state = state * 1103515245u + 12345u;
    return lo + (hi - lo) * ((state >> 8) & 0xffff) / 65535.0;
  };
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d on = path.point_at(uniform(0.0, path.length_m()));
    const Eigen::Vector2d p = on + Eigen::Vector2d(uniform(-0.3, 0.3), uniform(-0.3, 0.3));
    double nearest_m = 1e9;
    for (const Eigen::Vector2d& q : samples) nearest_m = std::min(nearest_m, (p - q).norm());
    const PathProjection foot = path.project(p);
    EXPECT_NEAR(foot.distance_m, nearest_m, 1e-6) << i;
    EXPECT_NEAR((p - foot.point).norm(), foot.distance_m, 1e-12) << i;
    if (!foot.before_start && !foot.after_end) {
      EXPECT_NEAR(std::abs(foot.lateral_m), foot.distance_m, 1e-6) << i;
    }
    // Left of the heading at the foot is positive.
    const Eigen::Vector2d left(-std::sin(foot.heading_rad), std::cos(foot.heading_rad));
    EXPECT_NEAR(foot.lateral_m, (p - foot.point).dot(left), 1e-9) << i;
  }
}

// The hint keeps the foot point on the piece the vehicle is on where the path passes near itself.
TEST(Path, HintKeepsTheFootLocal) {
  const Path loop =
      Path::starting_at({0.0, 0.0, 0.0}).add_line(1.0).add_arc(0.1, kPi).add_line(1.0);
  // (0.5, 0.09) is 0.09 from the first line and 0.11 from the return line.
  EXPECT_EQ(loop.project({0.5, 0.11}).segment, 2);
  EXPECT_EQ(loop.project({0.5, 0.11}, 0.5, 0.3).segment, 0);
}

// DESIGN.md: e_theta = vehicle yaw - path heading (CCW positive); e_d > 0 left of the path.
TEST(Path, TrackingErrorSigns) {
  const Path path = Path::starting_at({0.0, 0.0, kPi / 2}).add_line(2.0);  // along +y
  const Pose2 vehicle{-0.01, 1.0, kPi / 2 + 0.1};  // x = -0.01 is left of travel along +y
  const TrackingError e = path.tracking_error(vehicle, path.project(vehicle.translation()));
  EXPECT_NEAR(e.e_theta_rad, 0.1, 1e-12);
  EXPECT_NEAR(e.e_d_m, 0.01, 1e-12);
}

}  // namespace
}  // namespace agv::control
