#include "perception/autocorrelation.h"

#include <cstddef>

namespace agv::perception {

double integrated_autocorrelation_time(const std::vector<double>& values) {
  const std::size_t n = values.size();
  if (n == 0) return 1.0;
  double mean = 0.0, variance = 0.0;
  for (double v : values) mean += v;
  mean /= n;
  std::vector<double> centred(n);
  for (std::size_t i = 0; i < n; ++i) centred[i] = values[i] - mean;
  for (double c : centred) variance += c * c;
  double tau = 1.0;
  if (!(variance > 0.0)) return tau;
  // Four lags at a time: each lag's sum in the order of the values, as one at a time would
  // add them, but four sums side by side (one sum waits for each addition before the next).
  constexpr std::size_t kLags = 4;
  for (std::size_t first_lag = 1; first_lag < n / 4; first_lag += kLags) {
    double sum[kLags] = {0.0, 0.0, 0.0, 0.0};
    const std::size_t last_lag = first_lag + kLags - 1;
    std::size_t i = 0;
    for (; i + last_lag < n; ++i) {
      for (std::size_t j = 0; j < kLags; ++j) sum[j] += centred[i] * centred[i + first_lag + j];
    }
    for (std::size_t j = 0; j < kLags; ++j) {
      for (std::size_t tail = i; tail + first_lag + j < n; ++tail)
        sum[j] += centred[tail] * centred[tail + first_lag + j];
    }
    for (std::size_t j = 0; j < kLags && first_lag + j < n / 4; ++j) {
      const double rho = sum[j] / variance;
      if (rho < 0.05) return tau;
      tau += 2.0 * rho;
    }
  }
  return tau;
}

}  // namespace agv::perception
