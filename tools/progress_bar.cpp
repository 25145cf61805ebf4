#include "tools/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>

namespace agv::tools {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled),
      terminal_(isatty(STDERR_FILENO) != 0),
      uncaught_at_start_(std::uncaught_exceptions()) {
  if (enabled_ && !terminal_) std::fprintf(stderr, "%s ...\n", label_.c_str());
}

// Unwinding from an error: end the line, but do not claim the work was done.
ProgressBar::~ProgressBar() {
  if (std::uncaught_exceptions() > uncaught_at_start_) {
    if (enabled_ && terminal_ && !finished_) std::fprintf(stderr, "\n");
    finished_ = true;
    return;
  }
  finish();
}

void ProgressBar::update(double fraction) {
  if (!enabled_ || finished_) return;
  const int percent = static_cast<int>(100.0 * std::clamp(fraction, 0.0, 1.0));
  if (!terminal_) {  // a log: a line per tenth, the last one by finish()
    if (percent / 10 > last_percent_ / 10 && percent < 100) {
      std::fprintf(stderr, "%s: %d%%\n", label_.c_str(), percent / 10 * 10);
      last_percent_ = percent;
    }
    return;
  }
  if (percent == last_percent_) return;
  last_percent_ = percent;
  constexpr int kWidth = 30;
  const int filled = percent * kWidth / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled,
               "##############################", kWidth - filled, "", percent);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  if (terminal_) {
    update(1.0);
    std::fprintf(stderr, "\n");
  } else {
    std::fprintf(stderr, "%s: 100%%\n", label_.c_str());
  }
  finished_ = true;
}

}  // namespace agv::tools
