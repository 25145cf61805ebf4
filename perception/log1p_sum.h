#pragma once

#include <cstddef>

namespace agv::perception {

// The sum of log(1 + z[i]) over n values z[i] >= 0 (a Cauchy loss), with one logarithm per 16
// values: log1p of the product of their (1 + z), less 1, which is carried as such (exact to
// rounding at small z, where 1 + z would lose z's digits). Where a product overflows, its values'
// logarithms are summed one by one.
double log1p_sum(const double* z, size_t n);

}  // namespace agv::perception
