#pragma once

#include <string>

namespace agv::tools {

// A one-line progress bar on stderr, redrawn in place when stderr is a terminal; otherwise
// (logs, CI, batch jobs) one line per tenth of the work ("label: 30%") and the 100% mark.
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
};

}  // namespace agv::tools
