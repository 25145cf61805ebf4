#include "perception/line_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

namespace agv::perception {
namespace {

TEST(LineFit, TotalLeastSquaresIsExactOnPointsOfALine) {
  std::vector<Eigen::Vector2d> points;
  const Eigen::Vector2d direction = Eigen::Vector2d(0.9, 0.3).normalized();
  for (int i = 0; i < 20; ++i) points.push_back(Eigen::Vector2d(0.2, -0.01) + 0.01 * i * direction);
  const LineFit fit = fit_line_tls(points);
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(std::abs(fit.direction.dot(direction)), 1.0, 1e-12);
  EXPECT_NEAR(fit.rms_m, 0.0, 1e-12);
  EXPECT_NEAR(fit.span_m, 0.19, 1e-12);
}

// 30 % of the points are far off the line (a stray mark, a junction): the robust fit ignores
// them and recovers the line to the noise level (0.05 mm noise, 70 points: direction error
// well under 1e-3 rad).
TEST(LineFit, RobustFitIgnoresOutliers) {
  cv::RNG rng(3);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 100; ++i) {
    const double x = 0.2 + 0.002 * i;
    if (i % 10 < 3) {
      points.emplace_back(x, rng.uniform(0.02, 0.05));  // >= 7 mm off the line
    } else {
      points.emplace_back(x, 0.003 + 0.05 * (x - 0.2) + rng.gaussian(0.00005));
    }
  }
  const LineFit fit = fit_line_robust(points, 0.0015, 64);
  ASSERT_TRUE(fit.ok);
  EXPECT_EQ(fit.inlier_count, 70);
  EXPECT_NEAR(fit.direction.y() / fit.direction.x(), 0.05, 1e-3);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(fit.inliers[i], i % 10 >= 3) << i;
}

}  // namespace
}  // namespace agv::perception
