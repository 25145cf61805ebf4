#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/body_twist.h"
#include "common/line_measurement.h"
#include "common/pose2.h"
#include "control/line_tracker.h"
#include "control/vehicle_drive.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/config/scenario.h"
#include "pipeline/watchdog.h"

namespace agv::pipeline {

// A measurement with the ground truth of the frame it was made from.
struct StampedMeasurement {
  LineMeasurement measurement;
  control::TrackingError frame_truth;
  std::uint64_t frame_index = 0;
};

// One control period of a run (one row of trace.csv).
struct TraceRow {
  double t_s = 0.0;
  Pose2 pose;                    // true pose at t_s
  control::TrackingError truth;  // true errors at t_s
  bool has_measurement = false;  // the controller had a measurement to act on
  LineMeasurement measurement;   // the newest measurement it had
  double measurement_age_s = 0.0;
  control::TrackerOutput output;  // command, flags, what the controller acted on
  control::WheelCommand wheels =  // what the command asks of the vehicle's wheels
      control::MecanumWheelSpeeds(control::MecanumWheelSpeeds::Zero());
  // World positions of the wheel centres on the centre line (control::front_track_x_m).
  Eigen::Vector2d front_wheel = Eigen::Vector2d::Zero();
  Eigen::Vector2d rear_wheel = Eigen::Vector2d::Zero();
  std::uint32_t violations = 0;  // control::LimitViolation bits of the command
};

// Perception of one frame against its ground truth.
struct FrameRecord {
  std::uint64_t index = 0;
  double stamp_s = 0.0;
  control::TrackingError truth;
  LineMeasurement measurement;
};

struct StageTimes {
  double render_s = 0.0;
  double perceive_s = 0.0;
  double control_s = 0.0;
};

struct RunResult {
  std::string controller_name;
  std::vector<TraceRow> rows;
  std::vector<FrameRecord> frames;
  QueueStats queue;
  StageTimes total_times;  // summed over the run, seconds (lockstep; threaded: per thread)
  double wall_s = 0.0;
  double setup_wall_s = 0.0;          // of wall_s: building renderer, floor maps and estimator
  double max_tick_lateness_s = 0.0;   // threaded: how late the control thread ran at worst
  std::vector<WatchdogStall> stalls;  // threaded: threads the watchdog found silent
};

// Reports progress as a fraction in [0, 1]; may be empty.
using Progress = std::function<void(double)>;

// Receives every rendered frame with its ground truth (for recording datasets); may be empty.
using FrameSink =
    std::function<void(const FrameRecord& record, const Pose2& pose, const cv::Mat& frame)>;

// The controller the config names, with what it needs to know of the vehicle and, if given,
// the planned path (DWA looks ahead along it when the input is the pose).
std::unique_ptr<control::PathController> make_controller(
    const ControllerConfig& config, const VehicleConfig& vehicle,
    const control::Path* planned_path = nullptr);
// The camera that takes the frames: the camera file's, or its intrinsics with the true mount.
perception::CameraModel render_camera(const Scenario& scenario);
// The scenario's controller inside a LineTracker (limits, line-loss hold), started at its twist.
control::LineTracker make_tracker(const Scenario& scenario);

// Deterministic: one frame per control period; the measurement of the frame taken at period k
// reaches the controller at period k + latency_frames, through the bounded queue.
RunResult run_lockstep(const Scenario& scenario, const Progress& progress = {},
                       const FrameSink& sink = {});

// A camera thread renders and measures frames on its own clock and pushes them into the bounded
// queue; a control thread runs every Ts, takes the newest measurement and logs its age.
// Simulated time runs at loop.time_scale times wall-clock time.
RunResult run_threaded(const Scenario& scenario, const Progress& progress = {});

// run_lockstep or run_threaded, as the scenario's loop.mode says.
RunResult run_scenario(const Scenario& scenario, const Progress& progress = {});

}  // namespace agv::pipeline
