#include "pipeline/threaded_loop.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <thread>

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;
enum Watched { kCameraThread = 0, kControlThread = 1 };

// The run's clock: source seconds against wall-clock time.
class RunClock {
 public:
  RunClock(double start_s, double time_scale)
      : wall_start_(Clock::now()), start_s_(start_s), time_scale_(time_scale) {}
  Clock::time_point wall_start() const { return wall_start_; }
  double now_s() const {
    return start_s_ +
           std::chrono::duration<double>(Clock::now() - wall_start_).count() * time_scale_;
  }
  void sleep_until(double t_s) const {
    std::this_thread::sleep_until(
        wall_start_ + std::chrono::duration_cast<Clock::duration>(
                          std::chrono::duration<double>((t_s - start_s_) / time_scale_)));
  }

 private:
  Clock::time_point wall_start_;
  double start_s_, time_scale_;
};

// Each hang of `thread` happens once, when the thread's clock first reaches its time.
class Hangs {
 public:
  Hangs(const std::vector<InjectedHang>& hangs, LoopThread thread, double time_scale)
      : hangs_(hangs), thread_(thread), time_scale_(time_scale), done_(hangs.size(), false) {}
  void at(double t_s) {
    for (size_t h = 0; h < hangs_.size(); ++h) {
      if (hangs_[h].thread != thread_ || done_[h] || t_s < hangs_[h].at_s) continue;
      done_[h] = true;
      std::this_thread::sleep_for(std::chrono::duration<double>(hangs_[h].for_s / time_scale_));
    }
  }

 private:
  const std::vector<InjectedHang>& hangs_;
  LoopThread thread_;
  double time_scale_;
  std::vector<bool> done_;
};

// The camera thread: each frame when its time comes (or when a live source delivers it).
void run_camera(Loop& loop, const ThreadedSchedule& schedule, const RunClock& clock,
                Watchdog& watchdog, const std::atomic<bool>& stop) {
  Hangs hangs(schedule.hangs, LoopThread::kCamera, schedule.time_scale);
  FrameSource& source = loop.camera.source();
  const double frame_period_s = source.frame_period_s();
  while (!stop.load()) {
    std::optional<double> t_s = source.next_time_s();
    if (t_s) {
      clock.sleep_until(*t_s);
      while (schedule.drop_late_frames && t_s && clock.now_s() - *t_s > frame_period_s) {
        loop.camera.drop();
        t_s = source.next_time_s();
      }
    }
    hangs.at(t_s.value_or(clock.now_s()));
    if (stop.load() || !loop.camera.step()) break;
    watchdog.beat(kCameraThread);
  }
  watchdog.finished(kCameraThread);
}

// The control thread's loop: every ts_s until end_s, the source's end or a stop (then braking
// first where asked). Returns why it ended.
std::string run_control(Loop& loop, const ThreadedSchedule& schedule, const RunClock& clock,
                        Watchdog& watchdog, const std::atomic<bool>& camera_done, RunResult* result,
                        const Progress& progress) {
  Hangs hangs(schedule.hangs, LoopThread::kControl, schedule.time_scale);
  const double periods = std::floor((schedule.end_s - schedule.start_s) / schedule.ts_s + 1e-9) + 1;
  std::string ending;
  for (long k = 0;; ++k) {
    const double t_s = schedule.start_s + k * schedule.ts_s;
    if (ending.empty() && t_s > schedule.end_s + 1e-9) {
      if (!schedule.brake_at_end) return "duration";
      ending = "duration";
    }
    clock.sleep_until(t_s);
    hangs.at(t_s);
    watchdog.beat(kControlThread);
    result->max_tick_lateness_s =
        std::max(result->max_tick_lateness_s, (clock.now_s() - t_s) / schedule.time_scale);
    if (ending.empty()) {
      if (schedule.stop && schedule.stop->load()) ending = "stopped";
      if (schedule.end_with_source && camera_done.load()) ending = "end of source";
      if (!ending.empty() && !schedule.brake_at_end) return ending;
    }
    const double now_s = schedule.real_time_control ? clock.now_s() : t_s;
    std::optional<Pose2> pose;
    if (loop.vehicle) {
      if (k > 0) loop.vehicle->advance(t_s, schedule.ts_s);
      pose = loop.vehicle->state_at(t_s).pose;
    }
    result->rows.push_back(ending.empty() ? loop.control.step(now_s, pose)
                                          : loop.control.brake(now_s, pose));
    const TraceRow& row = result->rows.back();
    if (loop.vehicle) loop.vehicle->command(row.output.command);
    if (loop.on_period) loop.on_period(row);
    if (progress && std::isfinite(periods) && (k % 10 == 0 || k + 1 == periods))
      progress(std::min(1.0, (k + 1) / periods));
    const BodyTwist& c = row.output.command;
    if (!ending.empty() && c.vx_m_s == 0.0 && c.vy_m_s == 0.0 && c.wz_rad_s == 0.0) return ending;
  }
}

}  // namespace

RunResult run_threaded(Loop& loop, const ThreadedSchedule& schedule, const Progress& progress) {
  const RunClock clock(schedule.start_s, schedule.time_scale);
  loop.camera.source().start(clock.wall_start());
  const double frame_period_s = loop.camera.source().frame_period_s();
  // Each thread waits up to its own period between beats: the timeout is at least two of them.
  Watchdog watchdog(
      {"camera", "control"},
      std::max(schedule.watchdog_timeout_s, 2.0 * std::max(frame_period_s, schedule.ts_s)),
      clock.wall_start(), schedule.time_scale);
  std::atomic<bool> stop_camera{false}, camera_done{false};
  std::exception_ptr camera_error;  // no exception crosses the thread boundary by itself
  std::thread camera_thread([&] {
    try {
      run_camera(loop, schedule, clock, watchdog, stop_camera);
    } catch (...) {
      camera_error = std::current_exception();
      watchdog.finished(kCameraThread);
    }
    camera_done.store(true);
  });

  RunResult result;
  result.stop_reason = run_control(loop, schedule, clock, watchdog, camera_done, &result, progress);
  watchdog.finished(kControlThread);
  stop_camera.store(true);
  loop.camera.source().interrupt();
  loop.queue.close();
  camera_thread.join();
  watchdog.stop();
  if (camera_error) std::rethrow_exception(camera_error);
  result.stalls = watchdog.stalls();
  collect_results(loop, &result);
  return result;
}

}  // namespace agv::pipeline
