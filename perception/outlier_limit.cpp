#include "perception/outlier_limit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace agv::perception {

double outlier_limit(const std::vector<double>& magnitudes, double outlier_sigmas) {
  // Without ordering them where at least half of the magnitudes reach the largest over
  // outlier_sigmas x 1.4826 (a little more, for rounding): then so does the median, and the
  // limit exceeds the largest.
  double largest = 0.0;
  for (double r : magnitudes) largest = std::max(largest, r);  // (NaN: never kept either way)
  if (outlier_sigmas > 0.0) {
    const double reach = largest / (outlier_sigmas * 1.4826) * (1.0 + 1e-9);
    size_t reaching = 0;
    for (double r : magnitudes) reaching += r >= reach ? 1 : 0;
    if (reaching >= magnitudes.size() - magnitudes.size() / 2)
      return std::numeric_limits<double>::infinity();
  }
  std::vector<double> sorted = magnitudes;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return outlier_sigmas * std::max(1e-6, 1.4826 * sorted[sorted.size() / 2]);
}

}  // namespace agv::perception
