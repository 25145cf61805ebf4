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
  for (std::size_t lag = 1; lag < n / 4; ++lag) {
    double sum = 0.0;
    for (std::size_t i = 0; i + lag < n; ++i) sum += centred[i] * centred[i + lag];
    const double rho = sum / variance;
    if (rho < 0.05) break;
    tau += 2.0 * rho;
  }
  return tau;
}

}  // namespace agv::perception
