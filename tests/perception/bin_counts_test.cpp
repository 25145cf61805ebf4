#include "common/bin_counts.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <vector>

namespace agv {
namespace {

// The four interleaved lanes add up to a plain histogram: counts that leave 0-3 values after
// the last full group of four, bins crowded (all in one) and spread (the first and last bins
// included).
TEST(BinCounts, EqualsAPlainHistogram) {
  cv::RNG rng(11);
  for (int n : {0, 1, 3, 4, 5, 1001}) {
    for (int spread : {1, 443}) {
      std::vector<int> bins(n);
      for (int& b : bins) b = rng.uniform(0, spread);
      if (n >= 2 && spread > 1) {
        bins[0] = 0;
        bins[n - 1] = spread - 1;
      }
      std::vector<int> expected(443, 0);
      for (int b : bins) ++expected[b];
      EXPECT_EQ(bin_counts(bins.data(), bins.size(), 443), expected) << n << " values";
    }
  }
}

}  // namespace
}  // namespace agv
