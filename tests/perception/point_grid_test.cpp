#include "perception/point_grid.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <optional>
#include <random>
#include <vector>

namespace agv::perception {
namespace {

// Tape-like points: a noisy arc sampled every 0.4 mm (a full search's density), some of them
// repeated (equal distances: the lowest index must win), and a few strays.
std::vector<Eigen::Vector2d> tape_points(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.0002);
  std::uniform_real_distribution<double> stray(-0.1, 0.3);
  std::vector<Eigen::Vector2d> points;
  for (double s = 0.0; s < 0.2; s += 0.0004) {
    const double a = 3.0 * s;  // R 0.33 m
    points.emplace_back(0.1 + std::sin(a) / 3.0 + noise(rng), (1.0 - std::cos(a)) / 3.0);
    if (points.size() % 17 == 0) points.push_back(points.back());
    if (points.size() % 41 == 0) points.emplace_back(stray(rng), stray(rng));
  }
  return points;
}

// What nearest() promises, by looking at every point.
std::optional<size_t> brute_force_nearest(const std::vector<Eigen::Vector2d>& points,
                                          const Eigen::Vector2d& p, double radius_m) {
  std::optional<size_t> found;
  for (size_t j = 0; j < points.size(); ++j) {
    const double d2 = (points[j] - p).squaredNorm();
    if (d2 > radius_m * radius_m) continue;
    if (!found || d2 < (points[*found] - p).squaredNorm()) found = j;
  }
  return found;
}

// The ring search stops once the rings left lie farther than the nearest found: it must give
// the same point as looking at all of them, for cells much smaller than the radius (many rings),
// about as large (one ring) and larger, and for points spread too far for a dense grid.
TEST(PointGrid, NearestIsThePointNearestOfAll) {
  const std::vector<Eigen::Vector2d> points = tape_points(5);
  std::vector<Eigen::Vector2d> spread = points;
  spread.emplace_back(50.0, -50.0);  // no dense grid: every lookup scans all
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> x(0.05, 0.35), y(-0.05, 0.15), jitter(-0.003, 0.003);
  const double radius_m = 0.008;
  int found = 0;
  const std::vector<Eigen::Vector2d>* sets[] = {&points, &spread};
  for (const std::vector<Eigen::Vector2d>* set : sets) {
    for (double cell_m : {0.0011, 0.002, 0.008, 0.03}) {
      const PointGrid grid(*set, cell_m);
      for (int i = 0; i < 3000; ++i) {
        // Queries anywhere, near the points, and on them (distance 0; repeated points).
        const Eigen::Vector2d p =
            i % 3 == 0   ? Eigen::Vector2d(x(rng), y(rng))
            : i % 3 == 1 ? (*set)[i % set->size()] + Eigen::Vector2d(jitter(rng), jitter(rng))
                         : (*set)[i % set->size()];
        const std::optional<size_t> expected = brute_force_nearest(*set, p, radius_m);
        const std::optional<size_t> got = grid.nearest(*set, p, radius_m);
        ASSERT_EQ(expected.has_value(), got.has_value()) << "cell " << cell_m << " query " << i;
        if (expected) {
          ASSERT_EQ(*expected, *got) << "cell " << cell_m << " query " << i;
          ++found;
        }
      }
    }
  }
  EXPECT_GT(found, 10000);  // most queries lie near the tape
}

// A point exactly at the radius counts (as in brute_force_nearest); beyond it, none.
TEST(PointGrid, NearestCountsAPointAtTheRadius) {
  const std::vector<Eigen::Vector2d> points = {{0.0, 0.0}, {0.25, 0.0}};
  const PointGrid grid(points, 0.0625);
  EXPECT_EQ(grid.nearest(points, {0.5, 0.0}, 0.25), std::optional<size_t>(1));
  EXPECT_EQ(grid.nearest(points, {0.5 + 1e-9, 0.0}, 0.25), std::nullopt);
  EXPECT_EQ(grid.nearest(points, {10.0, 10.0}, 0.25), std::nullopt);
}

// p near the right side of its cell: a point one ring out on the left lies farther than one two
// rings out on the right, which the search must still look at (a ring r cells out lies only
// r - 1 cells away).
TEST(PointGrid, NearestLooksAtTheRingThatMayHoldANearerPoint) {
  const std::vector<Eigen::Vector2d> points = {{-0.9, 0.5}, {2.5, 0.5}};
  const PointGrid grid(points, 1.0);
  EXPECT_EQ(grid.nearest(points, {0.99, 0.5}, 3.0), std::optional<size_t>(1));
}

// The box visit gives the points for_each_near gives that lie in the box, in the same order
// (the fits summed over them stay bit for bit the same), and may skip only points outside it.
TEST(PointGrid, BoxVisitKeepsEveryPointInTheBoxInOrder) {
  const std::vector<Eigen::Vector2d> points = tape_points(8);
  const double cell_m = 0.036;
  const PointGrid grid(points, cell_m);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> x(0.05, 0.35), y(-0.05, 0.15), half(0.0, 0.036);
  int in_box = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d p(x(rng), y(rng)), reach(half(rng), half(rng));
    const Eigen::Vector2d lo = p - reach, hi = p + reach;
    std::vector<size_t> all, boxed;
    grid.for_each_near(p, [&](size_t j) { all.push_back(j); });
    grid.for_each_near_in_box(p, lo, hi, [&](size_t j) { boxed.push_back(j); });
    auto inside = [&](size_t j) {
      return (points[j].array() >= lo.array()).all() && (points[j].array() <= hi.array()).all();
    };
    // boxed is a subsequence of all ...
    size_t k = 0;
    for (size_t j : all)
      if (k < boxed.size() && boxed[k] == j) ++k;
    ASSERT_EQ(k, boxed.size()) << "query " << i;
    // ... holding every point of all in the box.
    std::vector<size_t> all_inside, boxed_inside;
    for (size_t j : all)
      if (inside(j)) all_inside.push_back(j);
    for (size_t j : boxed)
      if (inside(j)) boxed_inside.push_back(j);
    ASSERT_EQ(all_inside, boxed_inside) << "query " << i;
    in_box += static_cast<int>(boxed_inside.size());
  }
  EXPECT_GT(in_box, 1000);
}

}  // namespace
}  // namespace agv::perception
