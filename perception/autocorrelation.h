#pragma once

#include <vector>

namespace agv::perception {

// The integrated autocorrelation time of a sequence (residuals in order along a tape): 1 + 2 x
// the sum of its autocorrelation about the mean over lags 1, 2, ... until it falls below 0.05 (at
// most a quarter of its length). How many neighbours share one value's error: 1 for independent
// values; a variance computed as if they were independent is that much too small.
double integrated_autocorrelation_time(const std::vector<double>& values);

}  // namespace agv::perception
