#include "perception/log1p_sum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

namespace agv::perception {
namespace {

double term_by_term(const std::vector<double>& z) {
  double sum = 0.0;
  for (double v : z) sum += std::log1p(v);
  return sum;
}

// Against the sum of each value's log1p, to a relative 1e-13 (each of the ~n/16 logarithms and
// products rounds by a few 1e-16): counts that leave a partial group of 16, values from 1e-14
// (a fit's inliers at a fraction of a micrometre: 1 + z would drop them) to 4 (the inlier band's
// edge at half its width as scale).
TEST(Log1pSum, EqualsTheSumOfEachLogarithm) {
  cv::RNG rng(3);
  for (int n : {1, 15, 16, 17, 100, 961}) {
    for (double scale : {1e-14, 1e-6, 1e-2, 4.0}) {
      std::vector<double> z(n);
      for (double& v : z) v = scale * rng.uniform(0.0, 1.0);
      const double expected = term_by_term(z);
      EXPECT_NEAR(log1p_sum(z.data(), z.size()), expected, 1e-13 * expected)
          << n << " values up to " << scale;
    }
  }
  EXPECT_EQ(log1p_sum(nullptr, 0), 0.0);
}

// Sixteen values of 1e40 multiply past the largest double: that group is summed term by term,
// and the result stays finite and exact to rounding.
TEST(Log1pSum, AGroupWhoseProductOverflowsIsSummedTermByTerm) {
  std::vector<double> z(40, 1e-3);
  for (int i = 16; i < 32; ++i) z[i] = 1e40;
  const double expected = term_by_term(z);
  const double sum = log1p_sum(z.data(), z.size());
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_NEAR(sum, expected, 1e-13 * expected);
}

}  // namespace
}  // namespace agv::perception
