#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace agv::pipeline {

// A thread that did not show life for longer than the watchdog's timeout: who, when it was last
// seen (run time, seconds) and how long it stayed silent (until it beat again or finished, or
// until the watchdog stopped).
struct WatchdogStall {
  std::string thread;
  double last_seen_s = 0.0;
  double silent_for_s = 0.0;
};

// Watches threads that must beat regularly (the camera and control threads of the threaded
// loop). A monitor thread checks every timeout / 4; a thread silent for longer than the timeout
// is recorded once per silence, with its full length. Times are run times: wall time since
// `start` times `time_scale` (simulated seconds per wall second). Thread-safe.
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
  void check(double now_s);

  struct Watched {
    std::string name;
    double last_beat_s = 0.0;
    bool finished = false;
    int open_stall = -1;  // index in stalls_ while silent beyond the timeout
  };
  const double timeout_s_;
  const Clock::time_point start_;
  const double time_scale_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::vector<Watched> watched_;
  std::vector<WatchdogStall> stalls_;
  std::thread monitor_;
};

}  // namespace agv::pipeline
