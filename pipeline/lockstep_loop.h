#pragma once

#include "pipeline/loop.h"

namespace agv::pipeline {

// Control periods at start_s + k ts_s, k = 0 .. periods - 1; with periods < 0, until the
// period that has measured the source's last frame.
struct LockstepSchedule {
  double start_s = 0.0;
  double ts_s = 0.1;
  long periods = 1;
  // Then brake to standstill within the limits, one period at a time (a real vehicle's last
  // command is a stop).
  bool brake_at_end = false;
};

// Deterministic: the stages run in turn on simulated time, as if the camera and the controller
// ran on their own clocks with no time needed to compute. Before each control period, every
// frame taken up to its time is measured (a frame between periods sees the vehicle as the
// last command moved it); the controller acts on the newest measurement usable by then.
RunResult run_lockstep(Loop& loop, const LockstepSchedule& schedule, const Progress& progress = {});

}  // namespace agv::pipeline
