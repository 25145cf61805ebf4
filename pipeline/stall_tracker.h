#pragma once

#include <string>
#include <vector>

namespace agv::pipeline {

// A thread that did not show life for longer than the timeout: who, when it was last seen (run
// time, seconds) and how long it stayed silent (until it beat again or finished, or until the
// tracking was closed).
struct WatchdogStall {
  std::string thread;
  double last_seen_s = 0.0;
  double silent_for_s = 0.0;
};

// The watchdog's bookkeeping, on times the caller gives (so that it can be driven by a fake
// clock): a thread silent for longer than the timeout when `check` runs is recorded once per
// silence, and that record's length follows the silence until the thread beats again, finishes
// or `close` is called. Not thread-safe (Watchdog adds the lock, the clock and the monitor).
class StallTracker {
 public:
  StallTracker(const std::vector<std::string>& threads, double timeout_s);

  void beat(int thread, double now_s);      // index into the names given
  void finished(int thread, double now_s);  // no longer watched
  void check(double now_s);
  void close(double now_s);  // silences still open end now
  const std::vector<WatchdogStall>& stalls() const { return stalls_; }
  double timeout_s() const { return timeout_s_; }

 private:
  struct Watched {
    std::string name;
    double last_beat_s = 0.0;
    bool finished = false;
    int open_stall = -1;  // index in stalls_ while silent beyond the timeout
  };
  double timeout_s_;
  std::vector<Watched> watched_;
  std::vector<WatchdogStall> stalls_;
};

}  // namespace agv::pipeline
