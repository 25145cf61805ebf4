#pragma once

#include <chrono>
#include <string>

namespace agv::tools {

// "about 1 min 40 s left" for work `fraction` done in elapsed_s, at the same pace; empty until
// there is enough to go by (1 % of the work and half a second).
std::string time_left_words(double elapsed_s, double fraction);

// A one-line progress bar on stderr, redrawn in place when stderr is a terminal; otherwise
// (logs, CI, batch jobs) one line per tenth of the work ("label: 30%") and the 100% mark. Both
// say how long the rest will take at the pace so far.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();
  void update(double fraction);
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool terminal_;
  int last_percent_ = -1;
  bool finished_ = false;
  int uncaught_at_start_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace agv::tools
