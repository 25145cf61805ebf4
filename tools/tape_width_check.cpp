#include "tools/tape_width_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace agv::tools {

std::optional<std::string> tape_width_warning(const std::vector<double>& measured_m,
                                              const std::optional<double>& configured_m) {
  if (!configured_m || measured_m.size() < 5) return std::nullopt;
  std::vector<double> sorted = measured_m;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median_m = sorted[sorted.size() / 2];
  if (std::abs(median_m - *configured_m) <= 0.15 * *configured_m) return std::nullopt;
  char text[256];
  std::snprintf(text, sizeof(text),
                "the tape measures %.1f mm wide (median of %zu frames), the camera file says "
                "%.1f mm (tape_width_m): correct it, or remove it to have the width measured",
                1e3 * median_m, measured_m.size(), 1e3 * *configured_m);
  return std::string(text);
}

TapeWidthWatch::TapeWidthWatch(std::optional<double> configured_m, std::string command)
    : configured_m_(configured_m), command_(std::move(command)) {}

void TapeWidthWatch::add(const pipeline::FrameRecord& record) {
  if (!said_.empty() || !configured_m_) return;
  const LineMeasurement& m = record.measurement;
  if (!m.line_found || !(m.tape_width_m > 0.0)) return;
  // The last kFramesToJudge frames with a line: consistently unlike the hint, not once.
  measured_m_.push_back(m.tape_width_m);
  if (measured_m_.size() > kFramesToJudge) measured_m_.erase(measured_m_.begin());
  if (measured_m_.size() < kFramesToJudge) return;
  if (const std::optional<std::string> warning = tape_width_warning(measured_m_, configured_m_)) {
    said_ = *warning;
    std::fprintf(stderr, "agv %s: warning: %s\n", command_.c_str(), said_.c_str());
  }
}

}  // namespace agv::tools
