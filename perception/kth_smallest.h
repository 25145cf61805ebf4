#pragma once

#include <cstddef>
#include <vector>

namespace agv::perception {

// The k-th smallest (from 0) of n > k values, none NaN: the element std::nth_element puts at k,
// without reordering them. Where there are many, through a histogram of about one bin a value
// (at most 1024) over their range (bins follow the values' order: rounding is monotonic), so
// that only the few values in the bin that holds rank k are ordered: about a third of
// nth_element's cost on a few hundred values. `scratch` is reused (no allocation once it has
// grown).
double kth_smallest(const double* values, size_t n, size_t k, std::vector<double>* scratch);

}  // namespace agv::perception
