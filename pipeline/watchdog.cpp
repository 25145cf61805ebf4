#include "pipeline/watchdog.h"

namespace agv::pipeline {

Watchdog::Watchdog(const std::vector<std::string>& threads, double timeout_s,
                   Clock::time_point start, double time_scale)
    : start_(start), time_scale_(time_scale), tracker_(threads, timeout_s) {
  monitor_ = std::thread([this] { monitor(); });
}

Watchdog::~Watchdog() { stop(); }

double Watchdog::now_s() const {
  return std::chrono::duration<double>(Clock::now() - start_).count() * time_scale_;
}

void Watchdog::beat(int thread) {
  const double now = now_s();
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_.beat(thread, now);
}

void Watchdog::finished(int thread) {
  const double now = now_s();
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_.finished(thread, now);
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
  tracker_.close(now);
}

std::vector<WatchdogStall> Watchdog::stalls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tracker_.stalls();
}

void Watchdog::monitor() {
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(tracker_.timeout_s() / 4.0 / time_scale_));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, period, [this] { return stopping_; });
    if (!stopping_) tracker_.check(now_s());
  }
}

}  // namespace agv::pipeline
