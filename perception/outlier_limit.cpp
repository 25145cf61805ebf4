#include "perception/outlier_limit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "perception/kth_smallest.h"

namespace agv::perception {
namespace {
constexpr size_t kSortedUpTo = 64;
}  // namespace

double outlier_limit(const std::vector<double>& magnitudes, double outlier_sigmas) {
  return outlier_limit(magnitudes, {}, outlier_sigmas);
}

double outlier_limit(const std::vector<double>& magnitudes, const std::vector<double>& weights,
                     double outlier_sigmas) {
  auto weight = [&weights](size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  double total = 0.0;
  for (size_t i = 0; i < magnitudes.size(); ++i) total += weight(i);
  // The upper median's rank (from 0) among all counted: floor(total / 2).
  const double median_rank = std::floor(0.5 * total);
  // Without ordering them where at least half of the magnitudes reach the largest over
  // outlier_sigmas x 1.4826 (a little more, for rounding): then so does the median, and the
  // limit exceeds the largest.
  double largest = 0.0;
  for (double r : magnitudes) largest = std::max(largest, r);  // (NaN: never kept either way)
  if (outlier_sigmas > 0.0) {
    const double reach = largest / (outlier_sigmas * 1.4826) * (1.0 + 1e-9);
    double reaching = 0.0;
    for (size_t i = 0; i < magnitudes.size(); ++i)
      reaching += magnitudes[i] >= reach ? weight(i) : 0.0;
    if (reaching >= total - median_rank) return std::numeric_limits<double>::infinity();
  }
  double median = 0.0;
  if (weights.empty()) {
    std::vector<double> scratch;
    median = kth_smallest(magnitudes.data(), magnitudes.size(), magnitudes.size() / 2, &scratch);
  } else if (magnitudes.size() <= kSortedUpTo) {
    // Few (a window of the path memory's preview): sorted on the stack, then the weights counted
    // from the smallest until they exceed median_rank (the same magnitude as the selection below).
    std::array<std::pair<double, double>, kSortedUpTo> pairs;  // (magnitude, weight)
    for (size_t i = 0; i < magnitudes.size(); ++i) pairs[i] = {magnitudes[i], weight(i)};
    auto by_magnitude = [](const auto& a, const auto& b) { return a.first < b.first; };
    std::sort(pairs.begin(), pairs.begin() + magnitudes.size(), by_magnitude);
    double below = 0.0;
    if (!magnitudes.empty()) median = pairs[magnitudes.size() - 1].first;
    for (size_t i = 0; i < magnitudes.size(); ++i) {
      below += pairs[i].second;
      if (below > median_rank) {
        median = pairs[i].first;
        break;
      }
    }
  } else {
    // The magnitude at which the weights counted from the smallest first exceed median_rank, by
    // selection: split at the middle, keep the part that holds that rank.
    std::vector<std::pair<double, double>> pairs(magnitudes.size());  // (magnitude, weight)
    for (size_t i = 0; i < pairs.size(); ++i) pairs[i] = {magnitudes[i], weight(i)};
    auto by_magnitude = [](const auto& a, const auto& b) { return a.first < b.first; };
    auto lo = pairs.begin(), hi = pairs.end();
    double rank = median_rank;
    while (hi - lo > 1) {
      const auto middle = lo + (hi - lo) / 2;
      std::nth_element(lo, middle, hi, by_magnitude);
      double below = 0.0;
      for (auto it = lo; it != middle; ++it) below += it->second;
      if (below > rank) {
        hi = middle;
      } else if (below + middle->second > rank) {
        lo = middle;
        hi = middle + 1;
      } else {
        rank -= below + middle->second;
        lo = middle + 1;
      }
    }
    median = lo == pairs.end() ? pairs.back().first : lo->first;
  }
  return outlier_sigmas * std::max(1e-6, 1.4826 * median);
}

}  // namespace agv::perception
