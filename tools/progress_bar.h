#pragma once

#include <string>

namespace agv::tools {

// A one-line progress bar on stderr, redrawn in place when stderr is a terminal; otherwise
// (logs, CI) it prints the label once and the 100% mark at the end.
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
};

}  // namespace agv::tools
