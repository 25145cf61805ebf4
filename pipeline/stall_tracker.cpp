#include "pipeline/stall_tracker.h"

namespace agv::pipeline {

StallTracker::StallTracker(const std::vector<std::string>& threads, double timeout_s)
    : timeout_s_(timeout_s) {
  for (const std::string& name : threads) watched_.push_back({name});
}

void StallTracker::beat(int thread, double now_s) {
  Watched& w = watched_[thread];
  if (w.open_stall >= 0) {
    stalls_[w.open_stall].silent_for_s = now_s - w.last_beat_s;
    w.open_stall = -1;
  }
  w.last_beat_s = now_s;
}

void StallTracker::finished(int thread, double now_s) {
  beat(thread, now_s);
  watched_[thread].finished = true;
}

void StallTracker::check(double now_s) {
  for (Watched& w : watched_) {
    if (w.finished) continue;
    const double silent_s = now_s - w.last_beat_s;
    if (w.open_stall >= 0) {
      stalls_[w.open_stall].silent_for_s = silent_s;
    } else if (silent_s > timeout_s_) {
      w.open_stall = static_cast<int>(stalls_.size());
      stalls_.push_back({w.name, w.last_beat_s, silent_s});
    }
  }
}

void StallTracker::close(double now_s) {
  for (Watched& w : watched_) {
    if (w.open_stall >= 0) stalls_[w.open_stall].silent_for_s = now_s - w.last_beat_s;
    w.open_stall = -1;
  }
}

}  // namespace agv::pipeline
