#include "pipeline/watchdog.h"

namespace agv::pipeline {

Watchdog::Watchdog(const std::vector<std::string>& threads, double timeout_s,
                   Clock::time_point start, double time_scale)
    : timeout_s_(timeout_s), start_(start), time_scale_(time_scale) {
  for (const std::string& name : threads) watched_.push_back({name});
  monitor_ = std::thread([this] { monitor(); });
}

Watchdog::~Watchdog() { stop(); }

double Watchdog::now_s() const {
  return std::chrono::duration<double>(Clock::now() - start_).count() * time_scale_;
}

void Watchdog::beat(int thread) {
  const double now = now_s();
  std::lock_guard<std::mutex> lock(mutex_);
  Watched& w = watched_[thread];
  if (w.open_stall >= 0) {
    stalls_[w.open_stall].silent_for_s = now - w.last_beat_s;
    w.open_stall = -1;
  }
  w.last_beat_s = now;
}

void Watchdog::finished(int thread) {
  beat(thread);
  std::lock_guard<std::mutex> lock(mutex_);
  watched_[thread].finished = true;
}

void Watchdog::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (monitor_.joinable()) monitor_.join();
  const double now = now_s();
  std::lock_guard<std::mutex> lock(mutex_);
  for (Watched& w : watched_) {
    if (w.open_stall >= 0) stalls_[w.open_stall].silent_for_s = now - w.last_beat_s;
    w.open_stall = -1;
  }
}

std::vector<WatchdogStall> Watchdog::stalls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stalls_;
}

void Watchdog::check(double now) {
  for (Watched& w : watched_) {
    if (w.finished) continue;
    const double silent_s = now - w.last_beat_s;
    if (w.open_stall >= 0) {
      stalls_[w.open_stall].silent_for_s = silent_s;
    } else if (silent_s > timeout_s_) {
      w.open_stall = static_cast<int>(stalls_.size());
      stalls_.push_back({w.name, w.last_beat_s, silent_s});
    }
  }
}

void Watchdog::monitor() {
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(timeout_s_ / 4.0 / time_scale_));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, period, [this] { return stopping_; });
    if (!stopping_) check(now_s());
  }
}

}  // namespace agv::pipeline
