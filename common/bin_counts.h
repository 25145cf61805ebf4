#pragma once

#include <cstddef>
#include <vector>

namespace agv {

// How many of the n values bins[i] (each in [0, bin_count)) fall into each bin. Counted into
// four interleaved histograms and summed at the end: values crowd into a few bins, and one
// counter incremented again and again waits for its own last store.
inline std::vector<int> bin_counts(const int* bins, size_t n, int bin_count) {
  std::vector<int> lanes(4 * static_cast<size_t>(bin_count), 0);
  for (size_t i = 0; i < n; ++i) ++lanes[(i & 3) * bin_count + bins[i]];
  std::vector<int> counts(bin_count);
  for (int b = 0; b < bin_count; ++b)
    counts[b] = lanes[b] + lanes[bin_count + b] + lanes[2 * bin_count + b] +
                lanes[3 * bin_count + b];
  return counts;
}

}  // namespace agv
