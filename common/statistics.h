#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace agv {

// Root mean square; 0 for no values.
inline double rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (double x : values) sum += x * x;
  return values.empty() ? 0.0 : std::sqrt(sum / values.size());
}

// The p-quantile (0..1) by nearest rank: the sorted value at round(p * (n - 1)); 0 for none.
inline double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * (values.size() - 1) + 0.5))];
}

}  // namespace agv
