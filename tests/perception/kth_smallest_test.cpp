#include "perception/kth_smallest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

namespace agv::perception {
namespace {

double by_nth_element(std::vector<double> values, size_t k) {
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

// The same element as std::nth_element, exactly, at every rank: few values and many (the
// histogram path), spread evenly, crowded near zero with a long tail (residual magnitudes), with
// ties, all equal, and with an infinite one; the values themselves left as they were.
TEST(KthSmallest, IsTheElementNthElementPutsThere) {
  cv::RNG rng(5);
  std::vector<double> scratch;
  for (size_t n : {1, 2, 63, 64, 65, 700, 5000}) {
    for (int kind = 0; kind < 5; ++kind) {
      std::vector<double> values(n);
      for (double& v : values) {
        switch (kind) {
          case 0:
            v = rng.uniform(-1.0, 1.0);
            break;
          case 1:
            v = 1e-5 * std::exp(rng.uniform(0.0, 8.0));
            break;
          case 2:
            v = rng.uniform(0, 5) * 0.25;
            break;  // ties
          case 3:
            v = 0.7;
            break;
          default:
            v = rng.uniform(0.0, 1.0);
            break;
        }
      }
      if (kind == 4) values[n / 3] = std::numeric_limits<double>::infinity();
      const std::vector<double> before = values;
      for (size_t k = 0; k < n; k += std::max<size_t>(1, n / 97)) {
        ASSERT_EQ(kth_smallest(values.data(), n, k, &scratch), by_nth_element(values, k))
            << n << " values of kind " << kind << ", rank " << k;
      }
      EXPECT_EQ(values, before);
    }
  }
}

}  // namespace
}  // namespace agv::perception
