#include "perception/outlier_limit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace agv::perception {
namespace {

// The limit as the robust fits worked it out before: the median by selection, always.
double limit_from_the_median(std::vector<double> magnitudes, double sigmas) {
  std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                   magnitudes.end());
  return sigmas * std::max(1e-6, 1.4826 * magnitudes[magnitudes.size() / 2]);
}

// Whichever way the limit is found, the same magnitudes are kept: on Gaussian residuals (none
// beyond, mostly), with outliers (some beyond), on heavy tails, with ties and zeros, for odd and
// even counts down to one.
TEST(OutlierLimit, KeepsWhatTheMedianRuleKeeps) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss(0.0, 1e-4);
  std::cauchy_distribution<double> heavy(0.0, 1e-4);
  std::uniform_int_distribution<int> count(1, 200);
  int unchanged = 0, dropping = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    std::vector<double> magnitudes(count(rng));
    for (size_t i = 0; i < magnitudes.size(); ++i) {
      const int kind = trial % 4;
      double r = kind == 1 ? heavy(rng) : gauss(rng);
      if (kind == 2 && i % 7 == 0) r = 1e-3 * (1 + i % 3);  // outliers, repeated values
      if (kind == 3 && i % 2 == 0) r = 0.0;                 // half of them on the curve
      magnitudes[i] = std::abs(r);
    }
    const double sigmas = trial % 5 == 0 ? 2.5 : 4.0;
    const double limit = outlier_limit(magnitudes, sigmas);
    const double reference = limit_from_the_median(magnitudes, sigmas);
    bool drops = false;
    for (double r : magnitudes) {
      ASSERT_EQ(r <= limit, r <= reference) << "trial " << trial << " r " << r;
      drops = drops || r > reference;
    }
    (drops ? dropping : unchanged) += 1;
    if (std::isfinite(limit)) {
      EXPECT_EQ(limit, reference);  // the limit itself where it was worked out
    }
  }
  // Both cases were seen many times.
  EXPECT_GT(unchanged, 500);
  EXPECT_GT(dropping, 500);
}

// At the boundary: the largest exactly at the limit is kept, a little beyond it dropped.
TEST(OutlierLimit, TheLargestAtTheLimitIsKept) {
  std::vector<double> magnitudes(9, 1e-4);
  magnitudes.back() = 4.0 * 1.4826 * 1e-4;  // the limit itself
  double limit = outlier_limit(magnitudes, 4.0);
  EXPECT_LE(magnitudes.back(), limit);
  magnitudes.back() *= 1.0 + 1e-6;
  limit = outlier_limit(magnitudes, 4.0);
  EXPECT_GT(magnitudes.back(), limit);
  EXPECT_LE(1e-4, limit);
}

// A magnitude with weight n keeps and drops what n copies of it would: the weighted limit, on
// Gaussian residuals with outliers and on heavy tails, against the unweighted one over the
// magnitudes repeated; few magnitudes (sorted) and many (selected).
TEST(OutlierLimit, AWeightCountsAsThatManyCopies) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0.0, 1e-4);
  std::cauchy_distribution<double> heavy(0.0, 1e-4);
  std::uniform_int_distribution<int> count(1, 150), weight(1, 25);
  int dropping = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<double> magnitudes(count(rng)), weights, repeated;
    for (size_t i = 0; i < magnitudes.size(); ++i) {
      double r = trial % 2 == 0 ? gauss(rng) : heavy(rng);
      if (trial % 3 == 0 && i % 5 == 0) r = 2e-3;
      magnitudes[i] = std::abs(r);
      weights.push_back(weight(rng));
      repeated.insert(repeated.end(), static_cast<size_t>(weights.back()), magnitudes[i]);
    }
    const double sigmas = 4.0;
    const double limit = outlier_limit(magnitudes, weights, sigmas);
    const double reference = limit_from_the_median(repeated, sigmas);
    for (double r : magnitudes) {
      ASSERT_EQ(r <= limit, r <= reference) << "trial " << trial << " r " << r;
      dropping += r > reference ? 1 : 0;
    }
    if (std::isfinite(limit)) {
      EXPECT_EQ(limit, reference);
    }
  }
  EXPECT_GT(dropping, 500);
}

}  // namespace
}  // namespace agv::perception
