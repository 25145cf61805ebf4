#pragma once

#include <cstddef>
#include <vector>

namespace agv {

// Counts of values into bins (each in [0, bin_count)), added in batches. Counted into four
// interleaved histograms and summed at the end: values crowd into a few bins, and one counter
// incremented again and again waits for its own last store.
class BinCounter {
 public:
  explicit BinCounter(int bin_count)
      : bin_count_(bin_count), lanes_(4 * static_cast<size_t>(bin_count), 0) {}
  void add(const int* bins, size_t n) {
    for (size_t i = 0; i < n; ++i) ++lanes_[(i & 3) * bin_count_ + bins[i]];
  }
  // How many of the values added fall into each bin.
  std::vector<int> counts() const {
    std::vector<int> counts(bin_count_);
    for (size_t b = 0; b < bin_count_; ++b)
      counts[b] = lanes_[b] + lanes_[bin_count_ + b] + lanes_[2 * bin_count_ + b] +
                  lanes_[3 * bin_count_ + b];
    return counts;
  }

 private:
  size_t bin_count_;
  std::vector<int> lanes_;
};

// How many of the n values bins[i] (each in [0, bin_count)) fall into each bin.
inline std::vector<int> bin_counts(const int* bins, size_t n, int bin_count) {
  BinCounter counter(bin_count);
  counter.add(bins, n);
  return counter.counts();
}

}  // namespace agv
