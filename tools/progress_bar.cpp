#include "tools/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace agv::tools {

std::string time_left_words(double elapsed_s, double fraction) {
  if (!(fraction >= 0.01) || fraction >= 1.0 || !(elapsed_s >= 0.5)) return "";
  const long left_s = std::lround(elapsed_s * (1.0 - fraction) / fraction);
  char text[64];
  if (left_s < 60)
    std::snprintf(text, sizeof(text), "about %ld s left", left_s);
  else if (left_s < 3600)
    std::snprintf(text, sizeof(text), "about %ld min %ld s left", left_s / 60, left_s % 60);
  else
    std::snprintf(text, sizeof(text), "about %ld h %ld min left", left_s / 3600,
                  left_s % 3600 / 60);
  return text;
}

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
  auto time_left = [&] {
    const double elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return time_left_words(elapsed_s, fraction);
  };
  if (!terminal_) {  // a log: a line per tenth, the last one by finish()
    if (percent / 10 > last_percent_ / 10 && percent < 100) {
      const std::string left = time_left();
      std::fprintf(stderr, "%s: %d%%%s%s\n", label_.c_str(), percent / 10 * 10,
                   left.empty() ? "" : ", ", left.c_str());
      last_percent_ = percent;
    }
    return;
  }
  if (percent == last_percent_) return;
  last_percent_ = percent;
  const std::string left = time_left();
  constexpr int kWidth = 30;
  const int filled = percent * kWidth / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %-26s", label_.c_str(), filled,
               "##############################", kWidth - filled, "", percent, left.c_str());
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
