// Closed-loop runs of issue 6's vehicles and controllers on the shipped example scenarios.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/config/factory.h"
#include "pipeline/config/scenario_loader.h"
#include "pipeline/config/scenario_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/metrics.h"

namespace agv::pipeline {
namespace {

Scenario shipped(const std::string& name,
                 const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  std::vector<std::string> sets;
  for (const auto& [key, value] : overrides) sets.push_back(key + "=" + value);
  return pipeline::load_scenario_for_command(std::string(AGV_SOURCE_DIR) + "/scenarios/" + name,
                                             sets);
}

// Seed 004's claim: a 90 deg turn of radius 0.5 m between two straights at 0.3 m/s without
// stopping to spin, ending at the end pose; wheel speeds and wheel accelerations within the
// limits on every tick.
TEST(VehiclesAndControllers, Seed004TurnsWithoutStoppingAndEndsAtTheEndPose) {
  const Scenario s = shipped("mecanum_seed004_pose.yaml");
  const RunResult run = run_scenario(s);
  const RunMetrics m = compute_metrics(run, s);
  // 5 mm: the feed-forward turn rate jumps at the joints and the wheel acceleration limit
  // (20 rad/s^2) ramps it over 0.24 s; the omni vehicle keeps its centre on the path while the
  // heading catches up, so the lateral error stays a few millimetres.
  EXPECT_LT(m.max_abs_e_d_m, 0.005);
  EXPECT_EQ(m.limit_violations, 0);
  const double turn_from_s = 1.0, turn_to_s = 1.0 + 0.5 * M_PI / 2;
  const auto& drive = std::get<control::MecanumDrive>(s.vehicle.drive);
  control::MecanumWheelSpeeds previous =
      control::mecanum_inverse(drive.geometry, {s.path_speed_m_s, 0.0, 0.0});
  for (const TraceRow& row : run.rows) {
    const control::PathProjection foot = s.path.project(row.pose.translation());
    if (foot.s_m > turn_from_s && foot.s_m < turn_to_s) {
      EXPECT_GT(row.output.command.vx_m_s, 0.25) << "slowed down in the turn at " << row.t_s;
    }
    const auto& wheels = std::get<control::MecanumWheelSpeeds>(row.wheels);
    EXPECT_LE(wheels.cwiseAbs().maxCoeff(), drive.wheel_limits.max_wheel_speed_rad_s * (1 + 1e-9));
    EXPECT_LE((wheels - previous).cwiseAbs().maxCoeff(),
              drive.wheel_limits.max_wheel_accel_rad_s2 * s.controller.ts_s * (1 + 1e-9))
        << "at " << row.t_s;
    previous = wheels;
  }
  const Eigen::Vector2d end = s.path.point_at(s.path.length_m());
  EXPECT_LT((run.rows.back().pose.translation() - end).norm(), 0.005);
  EXPECT_NEAR(run.rows.back().output.command.vx_m_s, 0.0, 0.01);
}

// Seed 002: on a line-arc-line path (R 3 m) with improved DWA, drive form 1 (both wheels steer,
// centre reference) sweeps far less coverage area than forms 2 and 3. Bounds from geometry:
// in forms 2 and 3 the reference wheel follows the path, so the other wheel, 1 m away along
// the heading, runs sqrt(3^2 + 1^2) - 3 = 0.16 m off it for the 4.7 m of arc (> 0.6 m^2 with
// the approach); in form 1 both wheels are 0.5 m from the centre: at most 2 x 0.041 m x 4.7 m
// = 0.39 m^2 when the centre follows the path, less when the planner balances them.
TEST(VehiclesAndControllers, DriveFormOneSweepsTheLeastCoverageArea) {
  double area_m2[3] = {};
  const char* forms[3] = {"both_steer", "rear_drive", "front_drive"};
  for (int i = 0; i < 3; ++i) {
    const Scenario s =
        shipped("dual_steer_improved_dwa_pose.yaml", {{"vehicle.dual_steer.drive_form", forms[i]}});
    const RunResult run = run_scenario(s);
    const RunMetrics m = compute_metrics(run, s);
    area_m2[i] = m.coverage_area_m2;
    EXPECT_EQ(m.limit_violations, 0) << forms[i];
    // Reaches the end of the 10.7 m path within 24 s and stops there.
    const Eigen::Vector2d end = s.path.point_at(s.path.length_m());
    EXPECT_LT((run.rows.back().pose.translation() - end).norm(), 0.05) << forms[i];
  }
  EXPECT_LT(area_m2[0], 0.45);
  EXPECT_GT(area_m2[1], 0.6);
  EXPECT_GT(area_m2[2], 0.6);
}

// Line -> arc (R 1 m) -> line at 0.3 m/s from the pose (no frames), 10 mm and 5 deg off at the
// start. A dual steering-wheel vehicle (wheels 1 m apart, steering at 1 rad/s) settles into the
// 2 mm / 2 deg bands within 2 s and stays there through both joints, as a Mecanum vehicle does
// within 1 s, with the finite-step, PID and seed 004 laws. Measured: Mecanum 0.45 s; dual steer
// 0.91 / 1.79 / 1.26 s. It did not (never / 11.0 / 10.4 s, and 8.8 s for the Mecanum) while
// the pose gave no preview of the joints, the latency was predicted with the commands rather than
// with the wheels' turning, and the finite-step plan asked a steered vehicle for a new twist
// in one period.
TEST(VehiclesAndControllers, BothVehiclesSettleAndStayOnALineArcLineFromThePose) {
  for (const char* vehicle : {"mecanum", "dual_steer"}) {
    for (const char* controller : {"finite_step", "pid", "seed004_ff_p"}) {
      const bool steered = std::string(vehicle) == "dual_steer";
      if (!steered && std::string(controller) != "finite_step") continue;
      const Scenario s = shipped("curve_line_arc_r1.yaml", {{"vehicle.kind", vehicle},
                                                            {"controller.kind", controller},
                                                            {"controller.input", "pose"}});
      const RunMetrics m = compute_metrics(run_scenario(s), s);
      ASSERT_TRUE(m.settle_time_s.has_value()) << vehicle << " " << controller;
      EXPECT_LT(*m.settle_time_s, steered ? 2.0 : 1.0) << vehicle << " " << controller;
      EXPECT_EQ(m.limit_violations, 0) << vehicle << " " << controller;
    }
  }
}

// A Mecanum vehicle whose drives lag by 0.2 s (first order), from the pose: the finite-step
// horizon's n_min "auto" plans over 1 + 2 periods and settles sooner than the paper's deadbeat
// (measured 1.49 against 2.12 s).
TEST(VehiclesAndControllers, ALaggingDrivePlansOverMorePeriodsAndSettlesSooner) {
  double settle_s[2] = {};
  const char* n_min[2] = {"auto", "1"};
  for (int i = 0; i < 2; ++i) {
    const Scenario s =
        shipped("mecanum_finite_step_camera.yaml", {{"vehicle.actuator_lag_s", "0.2"},
                                                    {"controller.input", "pose"},
                                                    {"controller.finite_step.n_min", n_min[i]}});
    const RunMetrics m = compute_metrics(run_scenario(s), s);
    ASSERT_TRUE(m.settle_time_s.has_value()) << n_min[i];
    settle_s[i] = *m.settle_time_s;
  }
  EXPECT_LT(settle_s[0], settle_s[1] - 0.3);
}

// A law that commands a sideways speed on a drive form that cannot make one is named before the
// run (front_drive with finite_step ran 102 mm off the line in the default scenario), and only
// then: both wheels steering, or DWA, is a working pair.
TEST(VehiclesAndControllers, ADriveThatCannotMoveSidewaysWithASidewaysLawIsNamed) {
  const auto warnings = [](const char* form, const char* controller) {
    return scenario_warnings(
        shipped("dual_steer_finite_step_camera.yaml",
                {{"vehicle.dual_steer.drive_form", form}, {"controller.kind", controller}}));
  };
  for (const char* form : {"rear_drive", "front_drive"}) {
    for (const char* controller : {"finite_step", "pid", "seed004_ff_p"}) {
      const std::vector<std::string> w = warnings(form, controller);
      ASSERT_EQ(w.size(), 1u) << form << " " << controller;
      EXPECT_NE(w[0].find(form), std::string::npos);
      EXPECT_NE(w[0].find(controller), std::string::npos);
    }
    EXPECT_TRUE(warnings(form, "dwa").empty());
    EXPECT_TRUE(warnings(form, "improved_dwa").empty());
  }
  EXPECT_TRUE(warnings("both_steer", "finite_step").empty());
  EXPECT_TRUE(scenario_warnings(shipped("mecanum_pid_camera.yaml")).empty());
}

// Every shipped vehicle/controller example runs and keeps the vehicle near its path.
TEST(VehiclesAndControllers, EveryExampleCombinationTracks) {
  for (const char* vehicle : {"mecanum", "dual_steer"}) {
    for (const char* controller : {"finite_step", "pid", "seed004_ff_p", "dwa", "improved_dwa"}) {
      const std::string name = std::string(vehicle) + "_" + controller + "_camera.yaml";
      const Scenario s = shipped(name, {{"duration_s", "4.0"}});
      const RunMetrics m = compute_metrics(run_scenario(s), s);
      // 60 mm: the loosest of them (DWA with the seed's 10 deg/s^2 on a camera input) stays
      // within a tape width or two of the line; a controller that loses the line goes far past.
      EXPECT_LT(m.max_abs_e_d_m, 0.06) << name;
      EXPECT_EQ(m.limit_violations, 0) << name;
      EXPECT_EQ(m.frames_lost, 0) << name;
    }
  }
}

}  // namespace
}  // namespace agv::pipeline
