#include "perception/kth_smallest.h"

#include <algorithm>
#include <cmath>

#include "common/bin_counts.h"

namespace agv::perception {

double kth_smallest(const double* values, size_t n, size_t k, std::vector<double>* scratch) {
  constexpr size_t kFew = 64;
  constexpr int kBins = 1024;
  const auto [lo_at, hi_at] = std::minmax_element(values, values + n);
  const double lo = *lo_at, hi = *hi_at;
  if (n <= kFew || !std::isfinite(hi - lo) || !(hi > lo)) {
    if (!(hi > lo)) return lo;  // all equal
    scratch->assign(values, values + n);
    std::nth_element(scratch->begin(), scratch->begin() + k, scratch->end());
    return (*scratch)[k];
  }
  // bin(v) = min(bin_count - 1, (v - lo) x scale): non-decreasing in v. About one bin a value
  // (the answer does not depend on the bins; zeroing 1024 bins' counters for a hundred values
  // was most of the cost: 3 % of a tracked frame).
  const int bin_count = static_cast<int>(std::min<size_t>(n, kBins));
  const double scale = bin_count / (hi - lo);
  auto bin_of = [&](double v) {
    return std::min(bin_count - 1, static_cast<int>((v - lo) * scale));
  };
  std::vector<int> bins(n);
  for (size_t i = 0; i < n; ++i) bins[i] = bin_of(values[i]);
  const std::vector<int> counts = bin_counts(bins.data(), n, bin_count);
  int bin = 0;
  size_t below = 0;
  while (below + counts[bin] <= k) below += counts[bin++];
  scratch->clear();
  for (size_t i = 0; i < n; ++i)
    if (bins[i] == bin) scratch->push_back(values[i]);
  const auto at = scratch->begin() + (k - below);
  std::nth_element(scratch->begin(), at, scratch->end());
  return *at;
}

}  // namespace agv::perception
