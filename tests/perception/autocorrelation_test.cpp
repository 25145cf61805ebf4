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

}  // namespace
}  // namespace agv::perception
