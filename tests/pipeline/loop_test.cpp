// The loop's two stages and its two schedules, on hand-made sources whose frames say when they
// were taken: latency, queue policies, a source that stalls, a stop from outside, errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "common/input_error.h"
#include "control/finite_step_controller.h"
#include "pipeline/lockstep_loop.h"
#include "pipeline/threaded_loop.h"

namespace agv::pipeline {
namespace {

// Frames at i * period_s, i < count, without pictures. With stall_after >= 0 the source stops
// delivering after that many frames and waits, as a camera whose driver hangs does, until it is
// interrupted. With fail_at >= 0 that frame is bad input.
class TimedSource : public FrameSource {
 public:
  TimedSource(double period_s, long count, long stall_after = -1, long fail_at = -1)
      : period_s_(period_s), count_(count), stall_after_(stall_after), fail_at_(fail_at) {}

  std::optional<SourceFrame> next() override {
    if (next_ == stall_after_) {
      std::unique_lock<std::mutex> lock(mutex_);
      woken_.wait(lock, [this] { return interrupted_; });
      return std::nullopt;
    }
    if (next_ >= count_) return std::nullopt;
    if (next_ == fail_at_) throw InputError("frame " + std::to_string(next_) + ": unreadable");
    SourceFrame frame;
    frame.index = static_cast<std::uint64_t>(next_);
    frame.t_s = next_ * period_s_;
    ++next_;
    return frame;
  }
  std::optional<double> next_time_s() const override {
    if (next_ >= count_ || next_ == stall_after_) return std::nullopt;
    return next_ * period_s_;
  }
  void interrupt() override {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
    woken_.notify_all();
  }
  double frame_period_s() const override { return period_s_; }
  long frame_count() const override { return count_; }
  std::string describe() const override { return "timed source"; }

 private:
  double period_s_;
  long count_, stall_after_, fail_at_, next_ = 0;
  std::mutex mutex_;
  std::condition_variable woken_;
  bool interrupted_ = false;
};

// Sees the line dead ahead in every frame, at the frame's time.
class StraightAhead : public Perceiver {
 public:
  LineMeasurement measure(const SourceFrame& frame, perception::LineDetection*) override {
    LineMeasurement m;
    m.stamp_s = frame.t_s;
    m.line_found = true;
    m.confidence = 1.0;
    m.lines_seen = 1;
    return m;
  }
};

constexpr double kTs = 0.1;
constexpr double kSpeed_m_s = 0.3;

// The stages around one source, as run_scenario builds them for a simulation.
struct Stages {
  Stages(FrameSource& source, QueuePolicy policy, std::size_t capacity, double latency_s,
         double hold_s = 0.3)
      : queue(capacity, policy),
        camera(source, perceiver, queue, {{}, latency_s, std::chrono::nanoseconds(0)}),
        control(tracker(hold_s), queue,
                {control::MecanumDrive{}, control::VehicleLimits{}, kTs, {kSpeed_m_s, 0.0, 0.0}}) {}
  static control::LineTracker tracker(double hold_s) {
    control::LineTracker::Options options;
    options.ts_s = kTs;
    options.path_speed_m_s = kSpeed_m_s;
    options.line_lost_hold_s = hold_s;
    return control::LineTracker(
        std::make_unique<control::FiniteStepController>(control::FiniteStepController::Options{}),
        control::VehicleLimits{}, options, {kSpeed_m_s, 0.0, 0.0});
  }
  Loop loop() { return Loop{camera, queue, control, nullptr, {}}; }

  StraightAhead perceiver;
  BoundedQueue<StampedMeasurement> queue;
  CameraStage camera;
  ControlStage control;
};

// Latency is counted in camera frames: with the camera at 30 frames/s, Ts 0.1 s and two frames
// of latency, the controller at t acts on the newest frame taken at or before t - 2/30 s (in
// Ts it would be t - 0.2 s).
TEST(Loop, LockstepLatencyIsCountedInCameraFrames) {
  const double frame_period_s = 1.0 / 30.0;
  TimedSource source(frame_period_s, 61);
  Stages stages(source, QueuePolicy::kDropOldest, 8, 2 * frame_period_s);
  Loop loop = stages.loop();
  const RunResult run = run_lockstep(loop, {0.0, kTs, 21});
  ASSERT_EQ(run.rows.size(), 21u);
  EXPECT_FALSE(run.rows[0].has_measurement);  // nothing is usable before 2/30 s
  for (size_t k = 1; k < run.rows.size(); ++k) {
    const double t_s = k * kTs;
    const double expected_stamp_s =
        std::floor((t_s - 2 * frame_period_s) / frame_period_s + 1e-6) * frame_period_s;
    ASSERT_TRUE(run.rows[k].has_measurement) << "period " << k;
    EXPECT_NEAR(run.rows[k].measurement.stamp_s, expected_stamp_s, 1e-9) << "period " << k;
    EXPECT_NEAR(run.rows[k].measurement_age_s, t_s - expected_stamp_s, 1e-9);
  }
  EXPECT_EQ(run.frames.size(), 61u);
  // Three frames a period reach the controller: two of them are passed over for the newest.
  EXPECT_GE(run.measurements_superseded, 35u);
}

// Lockstep keeps the queue's policy: three frames a period into a queue of one. Dropping the
// oldest, the controller acts on the newest frame of each period; blocking (with no time to
// wait in lockstep), the later frames are refused and it acts on the first.
TEST(Loop, LockstepKeepsTheQueuePolicy) {
  for (const QueuePolicy policy : {QueuePolicy::kDropOldest, QueuePolicy::kBlock}) {
    TimedSource source(kTs / 3.0, 31);
    Stages stages(source, policy, 1, 0.0);
    Loop loop = stages.loop();
    const RunResult run = run_lockstep(loop, {0.0, kTs, 11});
    const bool drops = policy == QueuePolicy::kDropOldest;
    EXPECT_EQ(run.queue.dropped, drops ? 20u : 0u);
    EXPECT_EQ(run.queue.rejected, drops ? 0u : 20u);
    EXPECT_EQ(run.queue.pushed, drops ? 31u : 11u);
    for (size_t k = 1; k < run.rows.size(); ++k) {
      // The frames of period k are taken at (k - 1) Ts + Ts/3, + 2 Ts/3 and k Ts.
      const double expected_s = drops ? k * kTs : (k - 1) * kTs + kTs / 3.0;
      EXPECT_NEAR(run.rows[k].measurement.stamp_s, expected_s, 1e-9)
          << (drops ? "drop oldest" : "block") << ", period " << k;
    }
  }
}

// A source that stops delivering at 0.5 s (a hung camera driver): the watchdog reports the
// camera thread silent, the controller holds for its hold time and then brakes the vehicle to
// a stop within the acceleration limit, and the run still ends on time.
TEST(Loop, ThreadedStallingSourceIsReportedAndTheVehicleStops) {
  TimedSource source(0.05, 1000, /*stall_after=*/10);
  Stages stages(source, QueuePolicy::kDropOldest, 4, 0.0);
  Loop loop = stages.loop();
  ThreadedSchedule schedule;
  schedule.ts_s = kTs;
  schedule.end_s = 2.0;
  schedule.watchdog_timeout_s = 0.3;
  const RunResult run = run_threaded(loop, schedule);
  bool camera_reported = false;
  for (const WatchdogStall& stall : run.stalls) {
    if (stall.thread == "camera") camera_reported = stall.silent_for_s >= 1.0;
  }
  EXPECT_TRUE(camera_reported);
  ASSERT_FALSE(run.rows.empty());
  EXPECT_NEAR(run.rows.back().t_s, 2.0, 1e-9);
  EXPECT_TRUE(run.rows.back().output.flags & control::kStopping);
  EXPECT_EQ(run.rows.back().output.command.vx_m_s, 0.0);
  const control::VehicleLimits limits;
  for (size_t k = 1; k < run.rows.size(); ++k) {
    EXPECT_EQ(run.rows[k].violations, 0u) << "period " << k;
    EXPECT_LE(std::abs(run.rows[k].output.command.vx_m_s - run.rows[k - 1].output.command.vx_m_s),
              limits.a_max_m_s2 * kTs * (1 + 1e-9));
  }
}

// A stop asked from outside (Ctrl-C): the vehicle is braked within its limits, the last
// command is a stop, and the run says why it ended.
TEST(Loop, ThreadedStopBrakesToAStandstill) {
  TimedSource source(0.05, 1000000);
  Stages stages(source, QueuePolicy::kDropOldest, 4, 0.0);
  Loop loop = stages.loop();
  std::atomic<bool> stop{false};
  ThreadedSchedule schedule;
  schedule.ts_s = kTs;
  schedule.end_with_source = true;
  schedule.brake_at_end = true;
  schedule.real_time_control = true;
  schedule.stop = &stop;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    stop.store(true);
  });
  const RunResult run = run_threaded(loop, schedule);
  stopper.join();
  EXPECT_EQ(run.stop_reason, "stopped");
  ASSERT_GE(run.rows.size(), 3u);
  const BodyTwist& last = run.rows.back().output.command;
  EXPECT_EQ(last.vx_m_s, 0.0);
  EXPECT_EQ(last.vy_m_s, 0.0);
  EXPECT_EQ(last.wz_rad_s, 0.0);
  // From 0.3 m/s at 0.5 m/s^2 and Ts 0.1 s: 0.05 m/s less each period, so six periods of
  // braking (a seventh when rounding leaves a speck of speed after the sixth), never faster.
  int braking = 0;
  for (size_t k = 0; k < run.rows.size(); ++k) {
    const TraceRow& row = run.rows[k];
    EXPECT_EQ(row.violations, 0u);
    if (!(row.output.flags & control::kStopping)) continue;
    ++braking;
    EXPECT_LT(row.output.command.vx_m_s, run.rows[k - 1].output.command.vx_m_s);
  }
  EXPECT_GE(braking, 6);
  EXPECT_LE(braking, 7);
}

// The end of a recording ends the run (braking first where asked); bad input met by the
// camera thread comes back to the caller as the InputError it was, after both threads stop.
TEST(Loop, ThreadedEndOfSourceAndBadInput) {
  {
    TimedSource source(0.05, 6);
    Stages stages(source, QueuePolicy::kDropOldest, 4, 0.0);
    Loop loop = stages.loop();
    ThreadedSchedule schedule;
    schedule.ts_s = kTs;
    schedule.end_with_source = true;
    const RunResult run = run_threaded(loop, schedule);
    EXPECT_EQ(run.stop_reason, "end of source");
    EXPECT_EQ(run.frames.size(), 6u);
  }
  TimedSource failing(0.05, 100, -1, /*fail_at=*/3);
  Stages stages(failing, QueuePolicy::kDropOldest, 4, 0.0);
  Loop loop = stages.loop();
  ThreadedSchedule schedule;
  schedule.ts_s = kTs;
  schedule.end_with_source = true;
  EXPECT_THROW(run_threaded(loop, schedule), InputError);
}

}  // namespace
}  // namespace agv::pipeline
