#include "perception/log1p_sum.h"

#include <cmath>

namespace agv::perception {

double log1p_sum(const double* z, size_t n) {
  constexpr size_t kTerms = 16;
  double sum = 0.0;
  for (size_t first = 0; first < n; first += kTerms) {
    const size_t last = first + kTerms < n ? first + kTerms : n;
    // (1 + p)(1 + z) - 1 = p + z + p z.
    double product_less_1 = 0.0;
    for (size_t i = first; i < last; ++i) product_less_1 += z[i] + product_less_1 * z[i];
    if (std::isfinite(product_less_1)) {
      sum += std::log1p(product_less_1);
    } else {
      for (size_t i = first; i < last; ++i) sum += std::log1p(z[i]);
    }
  }
  return sum;
}

}  // namespace agv::perception
