#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "common/angles.h"
#include "pipeline/config/scenario_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/metrics.h"

namespace agv::pipeline {
namespace {

// The worst |e_d| from t = 1 s on (the initial error is gone) and at the end of a run.
struct OnTape {
  double worst_m = 0.0, end_m = 0.0;
};
OnTape on_tape(const RunResult& run) {
  OnTape r;
  for (const TraceRow& row : run.rows) {
    if (row.t_s >= 1.0) r.worst_m = std::max(r.worst_m, std::abs(row.truth.e_d_m));
  }
  r.end_m = std::abs(run.rows.back().truth.e_d_m);
  return r;
}

// A shipped scenario with `sets` ("key=value") applied as --set would.
Scenario shipped_scenario(const std::string& name, const std::vector<std::string>& sets = {}) {
  return load_scenario_for_command(std::string(AGV_SOURCE_DIR) + "/scenarios/" + name + ".yaml",
                                   sets);
}

// A Y fork whose branch leaves tangentially (overlapping the tape for its first 0.17 m), taken
// each way the caller can choose, from the camera: once the initial error is gone (1 s) the
// vehicle's centre stays over the tape it chose (within half the 25 mm tape's width; the other
// tape is 100 mm away 0.35 m past the fork and 0.5 m away at the end) and ends on it (within
// the 2 mm band); no frame is lost and no limit is broken.
TEST(Forks, TheVehicleTakesTheWayChosen) {
  for (const char* name : {"fork_left", "fork_right", "fork_straight"}) {
    const Scenario s = shipped_scenario(name);
    const RunResult run = run_scenario(s);
    const RunMetrics m = compute_metrics(run, s);
    const OnTape r = on_tape(run);
    EXPECT_LT(r.worst_m, 0.0125) << name;
    EXPECT_LT(r.end_m, 0.002) << name;
    EXPECT_EQ(m.limit_violations, 0) << name;
    EXPECT_EQ(m.frames_lost, 0) << name;
    // Every frame with a junction in view reports its ways out, and the way chosen is the one
    // the choice names among them: the leftmost, the rightmost or the nearest straight ahead.
    int junction_frames = 0;
    for (const FrameRecord& f : run.frames) {
      if (f.legs_rad.size() < 2) continue;
      ++junction_frames;
      ASSERT_TRUE(f.chosen_leg_rad) << name << " frame " << f.index;
      const auto [lo, hi] = std::minmax_element(f.legs_rad.begin(), f.legs_rad.end());
      const double expected = s.perception_branch == perception::BranchChoice::kLeft    ? *hi
                              : s.perception_branch == perception::BranchChoice::kRight ? *lo
                                                                                        : 0.0;
      const double tolerance = s.perception_branch == perception::BranchChoice::kStraight
                                   ? 0.5 * std::abs(*hi - *lo)  // nearer straight than the other
                                   : 1e-9;
      EXPECT_NEAR(*f.chosen_leg_rad, expected, tolerance) << name << " frame " << f.index;
    }
    EXPECT_GT(junction_frames, 0) << name;
    std::printf(
        "%s: after 1 s within %.1f mm of the chosen tape, %.2f mm at the end; %d frames "
        "with the junction in view\n",
        name, 1e3 * r.worst_m, 1e3 * r.end_m, junction_frames);
  }
}

// scenarios/fork_left.yaml started 0.54 m along at 0.30 m/s, and 0.50 m along at 0.32 m/s: where
// the legs part under the vehicle the remembered tape holds points of both, and in one frame a
// fit through them, with a residual of 1.2-1.3 mm, read 13.9 and 9.6 mm off the leg taken (such
// a fit is refused now: PathMemoryOptions::max_fit_rms_m 1 mm, not 2). No frame's measurement is
// off by more than 1 mm (measured 0.57 and 0.15 mm at worst).
TEST(Forks, NoFrameReadsAFitThroughBothLegs) {
  for (const std::vector<std::string>& sets :
       {std::vector<std::string>{"start_s_m=0.54", "path_speed_m_s=0.30"},
        std::vector<std::string>{"start_s_m=0.50", "path_speed_m_s=0.32"}}) {
    const Scenario s = shipped_scenario("fork_left", sets);
    const RunResult run = run_scenario(s);
    double worst_m = 0.0;
    for (const FrameRecord& f : run.frames) {
      if (!f.truth || !f.measurement.line_found) continue;
      worst_m = std::max(worst_m, std::abs(f.measurement.e_d_m - f.truth->e_d_m));
    }
    EXPECT_LT(worst_m, 0.001) << sets[0];
    std::printf("fork_left %s %s: perception off by %.2f mm at worst\n", sets[0].c_str(),
                sets[1].c_str(), 1e3 * worst_m);
  }
}

// scenarios/dataset_yellow_junction.yaml (worn 40 mm tape, a branch leaving left at 30 deg, taken
// straight on): the course under the vehicle, fitted over a few centimetres as the vehicle
// weaves, bent by up to 0.1 1/m (4.5 mm at 0.3 m ahead); carried so, the tape running on looked
// like a leg leaving to the right, and its chords were read half a width from the wrong edge: a
// frame 2.2 deg off (1.4 deg before the way straight on was read from such chords at all).
// Straight on, a course bending less than PathMemoryOptions::straight_course_line_below_1_m is
// the line: measured 0.34 mm and 0.36 deg at worst. Bounds: 0.5 mm and 1 deg (twice issue 3's
// RMS bar, for single frames).
TEST(Forks, StraightOnPastAWornForkNoFrameReadsTheTapeRunningOnAsALegLeaving) {
  const Scenario s = shipped_scenario("dataset_yellow_junction");
  const RunResult run = run_scenario(s);
  double worst_m = 0.0, worst_rad = 0.0;
  for (const FrameRecord& f : run.frames) {
    if (!f.truth || !f.measurement.line_found) continue;
    worst_m = std::max(worst_m, std::abs(f.measurement.e_d_m - f.truth->e_d_m));
    worst_rad = std::max(
        worst_rad, std::abs(wrap_angle_rad(f.measurement.e_theta_rad - f.truth->e_theta_rad)));
  }
  EXPECT_LT(worst_m, 0.0005);
  EXPECT_LT(rad_to_deg(worst_rad), 1.0);
  std::printf("dataset_yellow_junction: perception off by %.2f mm and %.2f deg at worst\n",
              1e3 * worst_m, rad_to_deg(worst_rad));
}

// A shipped turn run from the camera: no frame lost, the vehicle's centre within `within_m` of
// the tape from the first second on and within the 2 mm band at the end, no limit broken.
RunMetrics expect_turn_kept(const std::string& name, double within_m,
                            const std::vector<std::string>& sets = {}) {
  const Scenario s = shipped_scenario(name, sets);
  const RunResult run = run_scenario(s);
  const RunMetrics m = compute_metrics(run, s);
  const OnTape r = on_tape(run);
  EXPECT_EQ(m.frames_lost, 0) << name;
  EXPECT_LT(r.worst_m, within_m) << name;
  EXPECT_LT(r.end_m, 0.002) << name;
  EXPECT_EQ(m.limit_violations, 0) << name;
  std::printf(
      "%s: after 1 s within %.1f mm; perception %.2f mm / %.2f deg; %d frames on the "
      "remembered tape only\n",
      name.c_str(), 1e3 * r.worst_m, 1e3 * m.perception_rms_e_d_m.value_or(0.0),
      rad_to_deg(m.perception_rms_e_theta_rad.value_or(0.0)), m.frames_remembered_only);
  return m;
}

// A 90 deg corner rounded to R 0.1 m at a path speed of 0.3 m/s: the vehicle brakes for it in
// time (it cannot turn through it faster than w_max * R = 0.1 m/s), the camera (0.3 m ahead)
// passes it and sees no tape for a while, the vehicle turns on the remembered tape and stays in
// the middle 40 % of the 25 mm tape (5 mm). At 0.15 m/s the outgoing leg once came back turned
// by 180 deg after the corner, and the vehicle left the tape.
TEST(Corners, TheVehicleTurnsOnTheRememberedTapeWhenTheViewIsPast) {
  EXPECT_GT(expect_turn_kept("corner_r01", 0.005).frames_remembered_only, 0);
  EXPECT_GT(expect_turn_kept("corner_r01", 0.005, {"path_speed_m_s=0.15", "duration_s=17"})
                .frames_remembered_only,
            0);
}

// A 90 deg turn of R 0.3 m at 0.3 m/s (both joints pass the view in a few frames): the
// vehicle's centre within the middle 40 % of the 25 mm tape (5 mm).
TEST(Corners, ATightTurnAtPathSpeed) { expect_turn_kept("curve_turn_r03", 0.005); }

}  // namespace
}  // namespace agv::pipeline
