#pragma once

#include <vector>

namespace agv::perception {

// Which residuals a robust fit drops: those beyond outlier_sigmas robust sigmas, the robust sigma
// being 1.4826 times the median of `magnitudes` (the |residuals|, not empty; the upper median
// for an even count), at least 1e-6. Returns that limit, or infinity where no magnitude exceeds
// it (found without the median's selection, which was the fits' main cost, in most windows of a
// tape): either way, a magnitude is kept exactly when it is <= the value returned.
double outlier_limit(const std::vector<double>& magnitudes, double outlier_sigmas);
// The same with each magnitude counting `weights[i]` times (whole numbers: a point that stands for
// that many), the median that of all those counted (the weights empty: each once).
double outlier_limit(const std::vector<double>& magnitudes, const std::vector<double>& weights,
                     double outlier_sigmas);

}  // namespace agv::perception
