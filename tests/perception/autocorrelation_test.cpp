#include "perception/autocorrelation.h"

#include <gtest/gtest.h>

#include <random>

namespace agv::perception {
namespace {

// Independent values share nothing (time 1); values repeated in runs of k, each run drawn anew,
// share their error with k - 1 neighbours: the time is k (the autocorrelation falls linearly,
// 1 - lag / k, and 1 + 2 sum_{lag<k} (1 - lag/k) = k). Within 15 % from 4000 values: the sum is
// cut where the estimate falls below 0.05, which leaves out a tail of about 0.05 k.
TEST(Autocorrelation, RunsOfSharedErrorsCountAsOne) {
  for (int run : {1, 4, 10}) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<double> values;
    double shared = 0.0;
    for (int i = 0; i < 4000; ++i) {
      if (i % run == 0) shared = noise(rng);
      values.push_back(5.0 + shared);  // the mean is not the error's
    }
    EXPECT_NEAR(integrated_autocorrelation_time(values), run, 0.15 * run) << "runs of " << run;
  }
  EXPECT_DOUBLE_EQ(integrated_autocorrelation_time({}), 1.0);
  EXPECT_DOUBLE_EQ(integrated_autocorrelation_time({2.0, 2.0, 2.0}), 1.0);  // no variance
}

// The definition, one lag at a time, as a plain reference.
double one_lag_at_a_time(const std::vector<double>& values) {
  const size_t n = values.size();
  double mean = 0.0, variance = 0.0;
  for (double v : values) mean += v;
  mean /= n;
  for (double v : values) variance += (v - mean) * (v - mean);
  double tau = 1.0;
  for (size_t lag = 1; lag < n / 4; ++lag) {
    double sum = 0.0;
    for (size_t i = 0; i + lag < n; ++i) sum += (values[i] - mean) * (values[i + lag] - mean);
    if (sum / variance < 0.05) break;
    tau += 2.0 * sum / variance;
  }
  return tau;
}

// Lags taken four at a time give the same sum, to the last bit: short sequences (fewer lags than
// four, tails shorter than a group), the cut at any lag (runs of 1-40), and a time that runs to
// the quarter of the length (a slow drift).
TEST(Autocorrelation, IsTheDefinitionToTheLastBit) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int n : {8, 9, 13, 40, 97, 480}) {
    for (int run : {1, 3, 7, 40, 1000}) {
      std::vector<double> values;
      double shared = 0.0;
      for (int i = 0; i < n; ++i) {
        if (i % run == 0) shared = noise(rng);
        values.push_back(run == 1000 ? 0.01 * i + 0.001 * noise(rng) : shared + 0.1 * noise(rng));
      }
      EXPECT_EQ(integrated_autocorrelation_time(values), one_lag_at_a_time(values))
          << n << " values, runs of " << run;
    }
  }
}

}  // namespace
}  // namespace agv::perception
