#include "perception/tape_width_memory.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/statistics.h"

namespace agv::perception {

void TapeWidthMemory::update(std::optional<double> width_m) {
  if (!width_m || !(*width_m > 0.0)) {
    if (++frames_without_line_ >= kForgetAfterFrames) {
      widths_m_.clear();
      last_settled_m_.reset();
      narrowest_settled_m_.reset();
    }
    return;
  }
  frames_without_line_ = 0;
  widths_m_.push_back(*width_m);
  if (static_cast<int>(widths_m_.size()) > kKeptFrames) widths_m_.pop_front();
  if (const std::optional<double> settled_m = settled_width_m()) {
    last_settled_m_ = settled_m;
    narrowest_settled_m_ = std::min(narrowest_settled_m_.value_or(*settled_m), *settled_m);
  }
}

std::optional<double> TapeWidthMemory::settled_width_m() const {
  if (static_cast<int>(widths_m_.size()) < kSettleFrames) return std::nullopt;
  const std::vector<double> widths(widths_m_.begin(), widths_m_.end());
  const double median_m = percentile(widths, 0.5);
  const double spread_m = percentile(widths, 0.9) - percentile(widths, 0.1);
  if (spread_m > kSettledSpread * median_m) return std::nullopt;
  return median_m;
}

bool TapeWidthMemory::unlike(double width_m) const {
  return unlike_width(width_m, settled_width_m());
}

bool TapeWidthMemory::unlike_last_settled(double width_m) const {
  return unlike_width(width_m, last_settled_m_);
}

bool TapeWidthMemory::unlike_width(double width_m, std::optional<double> settled_m) const {
  if (!settled_m || !(width_m > 0.0)) return false;
  const double tolerance_m = std::max(kTolerance * *settled_m, kToleranceFloor_m);
  const double narrowest_m = std::min(*settled_m, narrowest_settled_m_.value_or(*settled_m));
  const double narrow_tolerance_m = std::max(kTolerance * narrowest_m, kToleranceFloor_m);
  return width_m < narrowest_m - narrow_tolerance_m || width_m > 2.0 * *settled_m + tolerance_m;
}

}  // namespace agv::perception
