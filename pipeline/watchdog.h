#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/stall_tracker.h"

namespace agv::pipeline {

// Watches threads that must beat regularly (the camera and control threads of the threaded
// loop): a StallTracker on the steady clock, checked by a monitor thread every timeout / 4.
// Times are run times: wall time since `start` times `time_scale` (simulated seconds per wall
// second). Thread-safe.
class Watchdog {
 public:
  using Clock = std::chrono::steady_clock;

  Watchdog(const std::vector<std::string>& threads, double timeout_s, Clock::time_point start,
           double time_scale = 1.0);
  ~Watchdog();  // stops the monitor
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  void beat(int thread);      // index into the names given
  void finished(int thread);  // no longer watched
  void stop();                // stops the monitor; silences still open are closed now
  std::vector<WatchdogStall> stalls() const;

 private:
  double now_s() const;
  void monitor();

  const Clock::time_point start_;
  const double time_scale_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  StallTracker tracker_;
  std::thread monitor_;
};

}  // namespace agv::pipeline
