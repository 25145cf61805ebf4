#include "pipeline/config/scenario_loader.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "common/input_error.h"
#include "pipeline/config/builtin_files.h"

namespace agv::pipeline {
namespace {

ScenarioText builtin() {
  return {pipeline::builtin_files().at("default_scenario.yaml"), "built-in default scenario", "",
          pipeline::builtin_files()};
}

ScenarioText text(const std::string& yaml) {
  return {yaml, "test.yaml", "", pipeline::builtin_files()};
}

std::string error_of(const ScenarioText& source,
                     const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  try {
    load_scenario(source, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The shipped default scenario is seed 000's Table 1.
TEST(ScenarioLoader, DefaultScenarioIsTable1) {
  const Scenario s = load_scenario(builtin(), {});
  EXPECT_DOUBLE_EQ(s.path_speed_m_s, 0.3);
  EXPECT_NEAR(s.initial_e_theta_rad, 5.0 * M_PI / 180.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.initial_e_d_m, 0.010);
  EXPECT_DOUBLE_EQ(s.controller.ts_s, 0.1);
  EXPECT_DOUBLE_EQ(s.controller.finite_step.v_x_max_m_s, 0.5);
  EXPECT_DOUBLE_EQ(s.controller.finite_step.a_max_m_s2, 0.05);
  EXPECT_DOUBLE_EQ(s.vehicle.limits.a_max_m_s2, 0.5);
  EXPECT_DOUBLE_EQ(s.duration_s, 5.0);
  EXPECT_EQ(s.latency_frames, 1);
  EXPECT_GT(s.effects.noise_sigma, 0.0);
  EXPECT_EQ(s.camera_name, "built-in default_camera.yaml");
}

TEST(ScenarioLoader, SetOverridesAnyKey) {
  const Scenario s = load_scenario(builtin(), {{"path_speed_m_s", "0.5"},
                                               {"controller.finite_step.horizon", "fixed"},
                                               {"tape.color_bgr", "[0, 200, 255]"},
                                               {"path.segments.0.length_m", "7.5"}});
  EXPECT_DOUBLE_EQ(s.path_speed_m_s, 0.5);
  EXPECT_EQ(s.controller.finite_step.mode, control::HorizonMode::kFixed);
  EXPECT_DOUBLE_EQ(s.tape.color_bgr[2], 255.0);
  EXPECT_DOUBLE_EQ(s.path.length_m(), 7.5);
}

TEST(ScenarioLoader, AnEmptyFileMeansEveryDefault) {
  const Scenario s = load_scenario(text(""), {});
  EXPECT_DOUBLE_EQ(s.path_speed_m_s, 0.3);
  EXPECT_GT(s.path.length_m(), 5.0);
}

TEST(ScenarioLoader, BadInputNamesTheFileAndTheKey) {
  struct Case {
    std::string yaml;
    std::vector<std::pair<std::string, std::string>> overrides;
    std::vector<std::string> expected;  // substrings of the message
  };
  const Case cases[] = {
      {"controller:\n  ts: 0.1\n",
       {},
       {"test.yaml", "controller.ts", "did you mean 'controller.ts_s'"}},
      {"pathspeed_m_s: 0.3\n", {}, {"test.yaml", "pathspeed_m_s", "unknown key"}},
      {"duration_s: five\n", {}, {"test.yaml", "duration_s", "expected a number"}},
      {"duration_s: .nan\n", {}, {"test.yaml", "duration_s", "finite"}},
      {"duration_s: -1\n", {}, {"test.yaml", "duration_s"}},
      {"latency_frames: 1.5\n", {}, {"test.yaml", "latency_frames", "whole number"}},
      {"controller:\n  kind: mpc\n", {}, {"controller.kind", "not one of"}},
      {"tape:\n  color_bgr: [1, 2]\n", {}, {"tape.color_bgr", "3 numbers"}},
      {"camera: no_such_camera.yaml\n", {}, {"camera", "no_such_camera.yaml"}},
      {"a: [1, 2\n", {}, {"test.yaml", "not valid YAML"}},
      {"", {{"controller.ts_s", "-0.1"}}, {"--set controller.ts_s=-0.1", "controller.ts_s"}},
      {"", {{"controler.ts_s", "0.1"}}, {"--set controler.ts_s=0.1", "unknown key"}},
      {"", {{"path_speed_m_s", "2.0"}}, {"path_speed_m_s", "v_forward_max"}},
      {"controller:\n  finite_step: {n_min: 12, n_max: 10}\n",
       {},
       {"controller.finite_step.n_min"}},
      {"controller:\n  finite_step: {n_min: soon}\n",
       {},
       {"controller.finite_step.n_min", "whole number or auto", "soon"}},
      {"frame_faults:\n  - {kind: covered, from_s: 2.0, to_s: 1.0}\n", {}, {"frame_faults.0"}},
      {"frame_faults:\n  - {kind: smoke, from_s: 1.0, to_s: 2.0}\n", {}, {"frame_faults.0.kind"}},
      {"",
       {{"frame_faults.0.kind", "covered"}},
       {"--set frame_faults.0.kind=covered", "frame_faults"}},
      {"loop:\n  hangs:\n    - {thread: gpu, at_s: 1.0, for_s: 1.0}\n",
       {},
       {"loop.hangs.0.thread"}},
      {"camera_true_mount: {xyz_m: [0.3, 0.0], rpy_rad: [3.14, 0, 0]}\n",
       {},
       {"camera_true_mount.xyz_m"}},
      // Bad paths: a zero-length line, a radius of 0, a Hermite turn over 90 deg, a segment
      // whose stated start is not where the path ends, a Hermite piece to its own start.
      // Impossible vehicles: wheels too slow for the path speed, a steer range past 90 deg.
      {"vehicle:\n  kind: dual_steer\n  dual_steer: {max_wheel_speed_m_s: 0.2}\n",
       {},
       {"vehicle.dual_steer.max_wheel_speed_m_s", "path_speed_m_s"}},
      {"vehicle:\n  mecanum: {max_wheel_speed_rad_s: 3.0}\n",
       {},
       {"vehicle.mecanum.max_wheel_speed_rad_s"}},
      {"vehicle:\n  kind: dual_steer\n  dual_steer: {max_steer_rad: 2.0}\n",
       {},
       {"vehicle.dual_steer.max_steer_rad"}},
      {"vehicle:\n  kind: dual_steer\n  actuator_lag_s: 0.05\n",
       {},
       {"vehicle.actuator_lag_s", "steer rate"}},
      // Settings of another vehicle kind than the one named, and a --set that switches the kind
      // of a file that describes a Mecanum drive.
      {"vehicle:\n  dual_steer: {wheelbase_m: 1.2}\n",
       {},
       {"test.yaml", "vehicle.dual_steer", "applies to vehicle.kind dual_steer", "is mecanum"}},
      {"vehicle:\n  mecanum: {wheel_radius_m: 0.06}\n",
       {{"vehicle.kind", "dual_steer"}},
       {"vehicle.mecanum", "is dual_steer"}},
      {"path:\n  segments:\n    - {kind: line, length_m: 0.0}\n", {}, {"path.segments.0.length_m"}},
      {"path:\n  segments:\n    - {kind: arc, radius_m: 0, angle_rad: 1.0}\n",
       {},
       {"path.segments.0.radius_m"}},
      {"path:\n  segments:\n    - {kind: hermite_arc, radius_m: 0.5, angle_rad: 2.0}\n",
       {},
       {"path.segments.0.angle_rad"}},
      {"path:\n  segments:\n    - {kind: line, length_m: 1.0}\n    - {kind: line, "
       "length_m: 1.0, start: {x_m: 1.0, y_m: 0.02, heading_rad: 0.0}}\n",
       {},
       {"path.segments.1.start", "continuous", "20.0 mm"}},
      {"path:\n  segments:\n    - {kind: hermite, end: {x_m: 0.0, y_m: 0.0, heading_rad: 1.0}}\n",
       {},
       {"path.segments.0.end", "zero-length"}},

  };
  for (const Case& c : cases) {
    const std::string message = error_of(text(c.yaml), c.overrides);
    ASSERT_FALSE(message.empty()) << c.yaml;
    for (const std::string& part : c.expected) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "expected '" << part << "' in: " << message;
    }
  }
  EXPECT_THROW(split_override("no_equals_sign"), InputError);
}

// Files written before the vehicle and controller settings were grouped by kind: each old key
// is refused with the key it moved to, whichever way it was given.
TEST(ScenarioLoader, AnOldFlatKeySaysWhereItMoved) {
  const std::pair<std::string, std::string> moves[] = {
      {"vehicle:\n  wheel_radius_m: 0.05\n", "vehicle.mecanum.wheel_radius_m"},
      {"vehicle:\n  drive_form: rear_drive\n", "vehicle.dual_steer.drive_form"},
      {"controller:\n  horizon: fixed\n", "controller.finite_step.horizon"},
      {"controller:\n  n_max: 8\n", "controller.finite_step.n_max"},
      {"controller:\n  a_max_m_s2: 0.05\n", "controller.finite_step.a_max_m_s2"},
  };
  for (const auto& [yaml, moved_to] : moves) {
    const std::string message = error_of(text(yaml), {});
    EXPECT_NE(message.find("test.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find("moved to '" + moved_to + "'"), std::string::npos) << message;
  }
  const std::string message = error_of(text(""), {{"controller.horizon", "fixed"}});
  EXPECT_NE(message.find("--set controller.horizon=fixed"), std::string::npos) << message;
  EXPECT_NE(message.find("controller.finite_step.horizon"), std::string::npos) << message;
}

// Each choice is parsed once into its enum, and a vehicle holds only its own kind's settings.
TEST(ScenarioLoader, ChoicesAreTypedAndTheVehicleHoldsItsOwnKind) {
  const Scenario mecanum = load_scenario(text("vehicle:\n  mecanum: {wheel_radius_m: 0.06}\n"), {});
  ASSERT_EQ(mecanum.vehicle.kind(), control::VehicleKind::kMecanum);
  EXPECT_DOUBLE_EQ(std::get<control::MecanumDrive>(mecanum.vehicle.drive).geometry.wheel_radius_m,
                   0.06);
  const Scenario dual = load_scenario(builtin(), {{"vehicle.kind", "dual_steer"},
                                                  {"vehicle.dual_steer.drive_form", "front_drive"},
                                                  {"controller.kind", "improved_dwa"},
                                                  {"controller.input", "pose"},
                                                  {"loop.mode", "threaded"}});
  ASSERT_EQ(dual.vehicle.kind(), control::VehicleKind::kDualSteer);
  EXPECT_EQ(std::get<control::DualSteerGeometry>(dual.vehicle.drive).form,
            control::DriveForm::kFrontDriveRear);
  EXPECT_EQ(dual.controller.kind, ControllerKind::kImprovedDwa);
  EXPECT_EQ(dual.controller.input, ControllerInput::kPose);
  EXPECT_EQ(dual.loop.mode, LoopMode::kThreaded);
}

TEST(ScenarioLoader, CameraPathIsRelativeToTheScenarioFile) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("agv_scenario_test_" + std::to_string(::getpid()));
  fs::create_directories(dir / "cameras");
  std::string camera = pipeline::builtin_files().at("default_camera.yaml");
  camera.replace(camera.find("mount_xyz_m: [ 0.30, 0.0, 0.15 ]"), 32,
                 "mount_xyz_m: [ 0.40, 0.0, 0.20 ]");
  std::ofstream(dir / "cameras" / "high.yaml") << camera;
  std::ofstream(dir / "run.yaml") << "camera: cameras/high.yaml\n";
  ScenarioText source = read_scenario_file((dir / "run.yaml").string());
  source.builtin_files = pipeline::builtin_files();
  const Scenario s = load_scenario(source, {});
  ASSERT_TRUE(s.camera.mount);
  EXPECT_DOUBLE_EQ(s.camera.mount->xyz_m.z(), 0.20);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace agv::pipeline
