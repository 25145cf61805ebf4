#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "control/dwa_controller.h"
#include "control/finite_step_controller.h"
#include "control/path.h"
#include "control/pid_controller.h"
#include "control/seed004_controller.h"
#include "control/vehicle_drive.h"
#include "control/vehicle_limits.h"
#include "perception/camera_file.h"
#include "perception/line_estimator.h"
#include "pipeline/bounded_queue.h"  // QueuePolicy
#include "pipeline/sim/frame_faults.h"
#include "pipeline/sim/scene.h"
#include "pipeline/sim/wheel_odometry.h"
#include "pipeline/threaded_loop.h"  // InjectedHang

namespace agv::pipeline {

// Things on the floor that are not the guide line: tile seams and stray marks.
struct FloorMarks {
  double seam_spacing_m = 0.0;  // tile seams every this many metres, along x and y (0: none)
  double seam_width_m = 0.003;
  double seam_darkness = 0.3;  // fraction of the floor's brightness they take away
  double marks_per_m2 = 0.0;   // stray marks: scuffs, tyre marks, short strokes
  double mark_darkness = 0.4;
};

// The vehicle: how it drives (one struct per kind) and what it can do.
struct VehicleConfig {
  control::VehicleDrive drive = control::MecanumDrive{};
  control::VehicleLimits limits;
  double actuator_lag_s = 0.0;  // Mecanum: first-order lag of the wheel drives (0: none)

  control::VehicleKind kind() const { return control::kind_of(drive); }
};

enum class ControllerKind { kFiniteStep, kPid, kSeed004FfP, kDwa, kImprovedDwa };
// Where the tracking error comes from: the camera (perception of the frames) or the vehicle's
// pose (localisation, the patent's world frame; no frames are rendered).
enum class ControllerInput { kCamera, kPose };

// The controller and its settings: one options struct per law, so that a suite can switch the
// kind over one file holding every law's gains.
struct ControllerConfig {
  ControllerKind kind = ControllerKind::kFiniteStep;
  ControllerInput input = ControllerInput::kCamera;
  double ts_s = 0.1;
  control::FiniteStepController::Options finite_step;
  // finite_step.n_min "auto": 1 for a drive that follows its commands at once, one more than the
  // periods an actuator lag's time constant spans; for dual steering wheels, the periods they
  // take to steer 0.25 rad (3 at 1 rad/s and 0.1 s): a plan that asks for a new twist in one
  // period is followed late and overshoots. Resolved when the controller is made (factory).
  bool finite_step_n_min_auto = true;
  control::PidController::Options pid;
  control::Seed004Controller::Options seed004;  // its wheel fields come from the vehicle
  control::DwaController::Options dwa;          // its improved and wheel fields come from the
                                                //   kind and the vehicle
  double line_lost_hold_s = 0.3;
  // The path speed on a curve is at most this fraction of the yaw-rate limit times the radius
  // (0: never lowered); see control::LineTracker.
  double curve_turn_fraction = 0.8;
  bool latency_compensation = true;
};

struct MetricsConfig {
  double settle_band_e_d_m = 0.002;                     // the paper's 2 mm
  double settle_band_e_theta_rad = 0.0349065850398866;  // the paper's 2 deg
};

enum class LoopMode { kLockstep, kThreaded };
struct LoopConfig {
  LoopMode mode = LoopMode::kLockstep;
  std::size_t queue_capacity = 4;
  QueuePolicy queue_policy = QueuePolicy::kDropOldest;
  double time_scale = 1.0;          // threaded: simulated seconds per wall-clock second
  double camera_fps = 0.0;          // frames per second (0: one frame per control period)
  double watchdog_timeout_s = 0.5;  // threaded: a thread silent this long is reported
  std::vector<InjectedHang> hangs;  // threaded, for tests of the watchdog
};

// The words scenario files use for each choice, in the order of the enum.
inline const std::vector<std::pair<std::string, control::VehicleKind>> kVehicleKindWords = {
    {"mecanum", control::VehicleKind::kMecanum}, {"dual_steer", control::VehicleKind::kDualSteer}};
inline const std::vector<std::pair<std::string, control::DriveForm>> kDriveFormWords = {
    {"both_steer", control::DriveForm::kBothSteer},
    {"rear_drive", control::DriveForm::kRearDriveFront},
    {"front_drive", control::DriveForm::kFrontDriveRear}};
inline const std::vector<std::pair<std::string, ControllerKind>> kControllerKindWords = {
    {"finite_step", ControllerKind::kFiniteStep},
    {"pid", ControllerKind::kPid},
    {"seed004_ff_p", ControllerKind::kSeed004FfP},
    {"dwa", ControllerKind::kDwa},
    {"improved_dwa", ControllerKind::kImprovedDwa}};
inline const std::vector<std::pair<std::string, ControllerInput>> kControllerInputWords = {
    {"camera", ControllerInput::kCamera}, {"pose", ControllerInput::kPose}};
inline const std::vector<std::pair<std::string, LoopMode>> kLoopModeWords = {
    {"lockstep", LoopMode::kLockstep}, {"threaded", LoopMode::kThreaded}};

// The word for a choice (as scenario files write it).
template <typename Enum>
const std::string& word_of(const std::vector<std::pair<std::string, Enum>>& words, Enum value) {
  for (const auto& [word, v] : words)
    if (v == value) return word;
  return words.front().first;  // unreachable for a complete table
}

// Everything one simulated run needs, read from a scenario file (see the default scenario,
// pipeline/config/default_scenario.yaml, for every key with its meaning).
struct Scenario {
  std::string source_name;  // the file, or "built-in default scenario"
  double duration_s = 5.0;
  std::uint64_t seed = 1;
  double path_speed_m_s = 0.3;
  int latency_frames = 1;
  double start_s_m = 0.5;                           // where along the path the vehicle starts
  double initial_e_theta_rad = 0.0872664625997165;  // 5 deg
  double initial_e_d_m = 0.010;
  control::Path path;
  TapeStrip tape;                          // its path is `path`
  std::vector<control::Path> extra_paths;  // more tape of the same kind: branches, crossings
  FloorMarks marks;
  FloorStyle floor;
  ImageEffects effects;
  std::vector<FrameFault> frame_faults;     // spoiled frames (line-loss tests)
  bool tape_color_hint = true;              // perception is told the tape colour
  bool perception_tracking = true;          // track the line between full-frame searches
  int perception_search_every_frames = 10;  // full-frame search at least this often
  bool perception_path_memory = true;       // e_d, e_theta from the remembered tape under the
                                            //   vehicle (false: carried back from the view)
  perception::BranchChoice perception_branch = perception::BranchChoice::kStraight;  // at forks
  OdometryNoise odometry;   // the vehicle's wheel odometry
  std::string camera_name;  // where the camera came from
  perception::CameraFile camera;
  // The mount the camera really has, when it differs from the camera file's (what a wrong or
  // outdated calibration does): frames are rendered with it, perception uses the file's.
  std::optional<perception::MountPose> true_mount;
  std::vector<FloorTag> floor_tags;  // AprilTags on the floor (world frame), for calibration
  VehicleConfig vehicle;
  ControllerConfig controller;
  MetricsConfig metrics;
  LoopConfig loop;
};

}  // namespace agv::pipeline
