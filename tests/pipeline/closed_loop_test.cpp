#include "pipeline/config/scenario_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/angles.h"
#include "pipeline/config/builtin_files.h"
#include "pipeline/config/scenario_loader.h"
#include "pipeline/evaluation/metrics.h"

namespace agv::pipeline {
namespace {

// ThreadSanitizer slows frames down 5-15 times: timings of the threaded loop mean nothing
// there (the runs still happen, for the sanitizer to check them). AddressSanitizer's build
// keeps up with real time; tools/setup.sh test runs the timing comparison there on its own.
#if defined(__SANITIZE_THREAD__)
constexpr bool kSlowedByThreadSanitizer = true;
#else
constexpr bool kSlowedByThreadSanitizer = false;
#endif

Scenario default_with(const std::vector<std::pair<std::string, std::string>>& overrides) {
  return load_scenario({pipeline::builtin_files().at("default_scenario.yaml"),
                        "built-in default scenario", "", pipeline::builtin_files()},
                       overrides);
}

struct Expectation {
  std::vector<std::pair<std::string, std::string>> overrides;
  double max_settle_s;
};

// Issue 3's bars, from camera images alone: the paper's bands (2 mm, 2 deg) reached within
// 1.2 s (the paper's own 0.8-1.2 s) and kept to the end; no period breaks a vehicle limit;
// perception within 0.5 mm / 0.2 deg RMS.
TEST(ClosedLoop, SettlesWithinThePapersTimeFromImages) {
  for (const Expectation& e :
       {Expectation{{}, 1.2}, Expectation{{{"path_speed_m_s", "0.5"}}, 1.2},
        Expectation{{{"initial_error.e_theta_rad", std::to_string(deg_to_rad(-7))},
                     {"initial_error.e_d_m", "-0.015"}},
                    1.2}}) {
    const Scenario s = default_with(e.overrides);
    const RunResult run = run_scenario(s);
    const RunMetrics m = compute_metrics(run, s);
    std::string label;
    for (const auto& [k, v] : e.overrides) label += k + "=" + v + " ";
    ASSERT_TRUE(m.settle_time_s.has_value()) << label;
    EXPECT_LE(*m.settle_time_s, e.max_settle_s) << label;
    EXPECT_EQ(m.limit_violations, 0) << label;
    EXPECT_EQ(m.frames_lost, 0) << label;
    EXPECT_LE(*m.perception_rms_e_d_m, 0.0005) << label;
    EXPECT_LE(rad_to_deg(*m.perception_rms_e_theta_rad), 0.2) << label;
  }
}

// Issue 21's bars for DWA from the camera: Tables 1 and 2 within the paper's bands in 2 s and
// kept; on the default suite's curve (1 m of line, a quarter circle of R 1 m, line) within the
// paper's 2 mm of the tape once settled on the first line (after 2 s; the issue asks for 5 mm,
// measured 0.7 mm; without the heading term's bend correction 5.0 mm); never a limit broken.
// Before, DWA never settled (57 mm inside a R 1.5 m arc: the bearing to a point 0.7 m ahead
// cuts the curve).
TEST(ClosedLoop, DwaFromTheCameraSettlesAndFollowsACurve) {
  const std::pair<std::string, std::string> curve{
      "path.segments",
      "[{kind: line, length_m: 1.0}, {kind: arc, radius_m: 1.0, angle_rad: 1.5707963268}, "
      "{kind: line, length_m: 1.0}]"};
  const std::vector<std::vector<std::pair<std::string, std::string>>> cases{
      {{"duration_s", "4.0"}},
      {{"duration_s", "4.0"}, {"path_speed_m_s", "0.5"}},
      {{"duration_s", "8.0"}, curve}};
  const char* case_names[] = {"table 1", "table 2", "curve"};
  for (const char* kind : {"dwa", "improved_dwa"}) {
    for (size_t c = 0; c < cases.size(); ++c) {
      std::vector<std::pair<std::string, std::string>> set = cases[c];
      set.push_back({"controller.kind", kind});
      const Scenario s = default_with(set);
      const RunResult run = run_scenario(s);
      const RunMetrics m = compute_metrics(run, s);
      const std::string label = std::string(kind) + " on " + case_names[c];
      EXPECT_EQ(m.limit_violations, 0) << label;
      if (c < 2) {
        ASSERT_TRUE(m.settle_time_s.has_value()) << label;
        EXPECT_LE(*m.settle_time_s, 2.0) << label;
        continue;
      }
      double worst_m = 0.0;
      for (const TraceRow& row : run.rows)
        if (row.t_s >= 2.0) worst_m = std::max(worst_m, std::abs(row.truth.e_d_m));
      EXPECT_LE(worst_m, 0.002) << label;
    }
  }
}

// The paper's a_max on every step: slower, but never a limit broken.
TEST(ClosedLoop, PaperAccelerationOnEveryStepNeverBreaksTheLimit) {
  const Scenario s = default_with({{"vehicle.a_max_m_s2", "0.05"}});
  const RunResult run = run_scenario(s);
  const RunMetrics m = compute_metrics(run, s);
  EXPECT_EQ(m.limit_violations, 0);
  // The limit bounds the change of the commanded (vx, vy) per period (the metric's acceleration
  // is the floor-frame one, turning included).
  BodyTwist previous{s.path_speed_m_s, 0.0, 0.0};
  for (const TraceRow& row : run.rows) {
    const BodyTwist& c = row.output.command;
    EXPECT_LE(std::hypot(c.vx_m_s - previous.vx_m_s, c.vy_m_s - previous.vy_m_s),
              0.05 * s.controller.ts_s * (1 + 1e-6))
        << "at " << row.t_s;
    previous = c;
  }
  ASSERT_TRUE(m.settle_time_s.has_value());
}

// The tape ends 1 m after the start: the vehicle holds, then stops within its acceleration
// limit: from 0.3 m/s at 0.5 m/s^2 it needs 0.09 m plus what it covers while holding.
TEST(ClosedLoop, StopsWhenTheTapeEnds) {
  const Scenario s = default_with({{"path.segments.0.length_m", "1.2"}, {"start_s_m", "0.2"}});
  const RunResult run = run_scenario(s);
  const RunMetrics m = compute_metrics(run, s);
  EXPECT_EQ(m.limit_violations, 0);
  EXPECT_GT(m.frames_lost, 0);
  const TraceRow& last = run.rows.back();
  EXPECT_NEAR(last.output.command.vx_m_s, 0.0, 1e-12);
  EXPECT_TRUE(last.output.flags & control::kStopping);
}

TEST(ClosedLoop, LockstepIsDeterministic) {
  const Scenario s = default_with({{"duration_s", "1.0"}});
  const RunResult a = run_scenario(s), b = run_scenario(s);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].pose.x_m, b.rows[i].pose.x_m);
    EXPECT_EQ(a.rows[i].measurement.e_d_m, b.rows[i].measurement.e_d_m);
  }
}

// Threaded, the same scenario gives the same behaviour within tolerance: camera and control run
// on their own threads and clocks, but the camera sees the plant's own pose between periods and
// latency is counted at the receiving end, so with an actuator lag and two frames of latency
// the two schedules agree to issue 16's bar (0.5 mm in max |e_d|, 0.15 s in settle time; the
// only difference left is rounding in the pose of a frame taken as a period starts). Real time
// leaves 100 ms a period, ample even for a sanitizer build, but there the timing is not
// compared (CI compares it in its unsanitized stage).
TEST(ClosedLoop, ThreadedModeMatchesLockstep) {
  const std::vector<std::pair<std::string, std::string>> lagged = {
      {"duration_s", "2.5"}, {"vehicle.actuator_lag_s", "0.05"}, {"latency_frames", "2"}};
  std::vector<std::pair<std::string, std::string>> threaded_overrides = lagged;
  threaded_overrides.push_back({"loop.mode", "threaded"});
  const Scenario lockstep = default_with(lagged);
  const Scenario threaded = default_with(threaded_overrides);
  const RunMetrics a = compute_metrics(run_scenario(lockstep), lockstep);
  const RunResult run = run_scenario(threaded);
  const RunMetrics b = compute_metrics(run, threaded);
  EXPECT_EQ(b.limit_violations, 0);
  std::printf("lockstep: max |e_d| %.2f mm, settle %.2f s; threaded: %.2f mm, %.2f s\n",
              1e3 * a.max_abs_e_d_m, a.settle_time_s.value_or(-1), 1e3 * b.max_abs_e_d_m,
              b.settle_time_s.value_or(-1));
  if (kSlowedByThreadSanitizer) GTEST_SKIP() << "timing comparison skipped under ThreadSanitizer";
  ASSERT_TRUE(a.settle_time_s && b.settle_time_s);
  EXPECT_NEAR(*b.settle_time_s, *a.settle_time_s, 0.15);
  EXPECT_NEAR(b.max_abs_e_d_m, a.max_abs_e_d_m, 0.0005);
  for (const TraceRow& row : run.rows) {
    if (row.has_measurement) {
      EXPECT_LE(row.measurement_age_s, 0.2 + 0.1);  // two frames, plus at most a period's wait
    }
  }
}

// A camera at 30 frames/s with Ts 0.1 s: two frames of latency are 67 ms, not 0.2 s; the
// controller acts on a measurement at most two frames plus one period old, and the run settles
// (as fast as Table 1's with its one 0.1 s frame of latency, 0.5 s, give or take a period).
// Lockstep keeps the queue's policy too: a queue of one that blocks refuses the later frames.
TEST(ClosedLoop, LatencyIsCountedInCameraFrames) {
  const Scenario s =
      default_with({{"duration_s", "3.0"}, {"loop.camera_fps", "30"}, {"latency_frames", "2"}});
  const RunResult run = run_scenario(s);
  const RunMetrics m = compute_metrics(run, s);
  ASSERT_TRUE(m.settle_time_s.has_value());
  EXPECT_LE(*m.settle_time_s, 0.8);
  EXPECT_EQ(m.limit_violations, 0);
  EXPECT_EQ(m.frames, 91);
  for (size_t k = 1; k < run.rows.size(); ++k) {
    ASSERT_TRUE(run.rows[k].has_measurement);
    EXPECT_GE(run.rows[k].measurement_age_s, 2.0 / 30.0 - 1e-9);
    EXPECT_LT(run.rows[k].measurement_age_s, 3.0 / 30.0 - 1e-9);
  }
  const Scenario blocking = default_with({{"duration_s", "1.0"},
                                          {"loop.camera_fps", "30"},
                                          {"loop.queue_capacity", "1"},
                                          {"loop.queue_policy", "block"}});
  const RunResult blocked = run_scenario(blocking);
  EXPECT_GT(blocked.queue.rejected, 0u);
  EXPECT_EQ(blocked.queue.dropped, 0u);
}

// Overload: the camera produces ten frames per control period, far faster than the control
// thread consumes them; the queue stays bounded and every frame is accounted for.
TEST(ClosedLoop, ThreadedOverloadLosesNothingUncounted) {
  const Scenario s = default_with({{"duration_s", "1.0"},
                                   {"loop.mode", "threaded"},
                                   {"loop.time_scale", "2"},
                                   {"loop.camera_fps", "100"},
                                   {"loop.queue_capacity", "3"},
                                   {"latency_frames", "0"}});
  const RunResult run = run_scenario(s);
  const QueueStats& q = run.queue;
  EXPECT_EQ(q.pushed + q.rejected, run.frames.size());
  // What was not popped or dropped was still queued at the end: at most capacity.
  EXPECT_GE(q.pushed, q.popped + q.dropped);
  EXPECT_LE(q.pushed - (q.popped + q.dropped), 3u);
  EXPECT_LE(q.max_depth, 3u);
  // Of what the controller took, it acts on at most one a period; with no latency nothing waits
  // in transit, so the rest was passed over as superseded.
  EXPECT_GE(run.measurements_superseded + run.rows.size(), q.popped);
  EXPECT_LE(run.measurements_superseded, q.popped);
  // Whatever was pushed beyond one a period and the queue's capacity shows up as dropped or
  // superseded.
  if (q.pushed > run.rows.size() + 3) {
    EXPECT_GT(q.dropped + run.measurements_superseded, 0u);
  }
  // How far the camera outruns control depends on scheduling (a loaded 2-core CI machine may
  // starve the camera thread), so only the accounting above is asserted.

  EXPECT_EQ(compute_metrics(run, s).limit_violations, 0);
}

// A camera thread that hangs for 1 s (a stuck driver or perception): the watchdog reports it
// with its silence, the controller holds and then brings the vehicle to a stop within the
// limits, and drives on once frames come again. A control thread that hangs is reported too.
TEST(ClosedLoop, WatchdogReportsAHungThreadAndTheVehicleStops) {
  const Scenario camera_hangs =
      default_with({{"duration_s", "4.0"},
                    {"loop.mode", "threaded"},
                    {"loop.hangs", "[{thread: camera, at_s: 1.0, for_s: 1.0}]"}});
  ASSERT_EQ(camera_hangs.loop.hangs.size(), 1u);
  const RunResult run = run_scenario(camera_hangs);
  bool camera_reported = false;
  for (const WatchdogStall& stall : run.stalls) {
    // (Under a sanitizer, slow frames may add shorter camera stalls of their own.)
    if (stall.thread == "camera") camera_reported = camera_reported || stall.silent_for_s >= 0.9;
  }
  EXPECT_TRUE(camera_reported);
  bool stopped = false;
  for (const TraceRow& row : run.rows) stopped = stopped || (row.output.flags & control::kStopping);
  EXPECT_TRUE(stopped) << "drove on stale measurements";
  EXPECT_EQ(compute_metrics(run, camera_hangs).limit_violations, 0);
  // Drives on once fresh frames come again: within the 2 s after the hang (the first frames
  // after it are searched in full; under ThreadSanitizer on a loaded 2-core machine a frame
  // takes a few hundred ms, and 1 s was once not enough).
  bool drove_on = false;
  for (const TraceRow& row : run.rows)
    drove_on = drove_on || (row.t_s > 2.0 && row.output.command.vx_m_s > 0.0 &&
                            !(row.output.flags & control::kStopping));
  EXPECT_TRUE(drove_on) << "did not drive on after the hang";

  const Scenario control_hangs =
      default_with({{"duration_s", "2.0"},
                    {"loop.mode", "threaded"},
                    {"loop.hangs", "[{thread: control, at_s: 0.5, for_s: 0.8}]"}});
  const RunResult hung = run_scenario(control_hangs);
  bool control_reported = false;
  for (const WatchdogStall& stall : hung.stalls) {
    if (stall.thread == "control") control_reported = control_reported || stall.silent_for_s >= 0.7;
  }
  EXPECT_TRUE(control_reported);
}

}  // namespace
}  // namespace agv::pipeline
