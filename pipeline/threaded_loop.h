#pragma once

#include <atomic>
#include <limits>
#include <vector>

#include "pipeline/loop.h"

namespace agv::pipeline {

enum class LoopThread { kCamera, kControl };

// For tests of the watchdog: the thread hangs for for_s once its clock reaches at_s.
struct InjectedHang {
  LoopThread thread = LoopThread::kCamera;
  double at_s = 0.0, for_s = 0.0;
};

struct ThreadedSchedule {
  double start_s = 0.0;  // the first control period, on the source's clock
  double ts_s = 0.1;
  // The last control period may be at end_s (infinite: until the source ends or stop is set).
  double end_s = std::numeric_limits<double>::infinity();
  double time_scale = 1.0;  // the source's seconds per wall-clock second
  double watchdog_timeout_s = 0.5;
  // Recorded and rendered frames are taken when the clock reaches their time; a live source
  // delivers frames when they come and is never waited for.
  // Recorded frames whose time has passed by more than a frame when the camera gets to them
  // are dropped and counted (a slow computer playing a video in real time).
  bool drop_late_frames = false;
  // Control periods act at the time they really run (a real vehicle), not at their nominal
  // time (a simulation, so that it matches the lockstep schedule).
  bool real_time_control = false;
  // The run ends when the source does (a recording, a live camera), not only at end_s.
  bool end_with_source = false;
  // When the run ends (end_s, the source's end, `stop`), brake to standstill within the
  // limits first (a real vehicle's last command is a stop).
  bool brake_at_end = false;
  const std::atomic<bool>* stop = nullptr;  // set from outside (Ctrl-C); may be null
  std::vector<InjectedHang> hangs;
};

// The stages on two threads with the bounded queue between them, on a clock that runs at
// time_scale times wall-clock time: the camera thread measures frames as they are taken, the
// control thread runs every ts_s on the newest usable measurement and logs its age. A watchdog
// reports a thread silent for longer than its timeout (or two of its periods). Bad input met by
// the camera thread (InputError from the source) is thrown again here once both have stopped.
RunResult run_threaded(Loop& loop, const ThreadedSchedule& schedule, const Progress& progress = {});

}  // namespace agv::pipeline
