#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/run_result.h"

namespace agv::tools {

// The tape's width as measured (every frame with a line) against the camera file's hint: a
// warning when the median of at least 5 frames differs from the hint by more than 15 %, naming
// both; none otherwise (or without a hint).
std::optional<std::string> tape_width_warning(const std::vector<double>& measured_m,
                                              const std::optional<double>& configured_m);

// Says it as soon as 15 frames with a line in a row show it, once, on stderr ("agv COMMAND:
// warning: ..."): fed by the camera stage's sink, one frame at a time, from one thread.
class TapeWidthWatch {
 public:
  TapeWidthWatch(std::optional<double> configured_m, std::string command);
  void add(const pipeline::FrameRecord& record);
  // The warning given (empty: none). Read after the run.
  const std::string& said() const { return said_; }

 private:
  static constexpr size_t kFramesToJudge = 15;
  std::optional<double> configured_m_;
  std::string command_;
  std::vector<double> measured_m_;
  std::string said_;
};

}  // namespace agv::tools
