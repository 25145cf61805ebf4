#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/line_measurement.h"
#include "common/pose2.h"
#include "control/line_tracker.h"
#include "control/path.h"
#include "control/vehicle_drive.h"
#include "perception/tracking_line_estimator.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/watchdog.h"

namespace agv::pipeline {

// A measurement on its way to the controller: usable from available_s on (the frame's time
// plus the configured transport latency).
struct StampedMeasurement {
  LineMeasurement measurement;
  std::uint64_t frame_index = 0;
  double available_s = 0.0;
};

// One control period (one row of trace.csv).
struct TraceRow {
  double t_s = 0.0;
  bool has_measurement = false;      // the controller had a measurement to act on
  bool measurement_arrived = false;  // a new one arrived this period
  LineMeasurement measurement;       // the newest measurement it had
  double measurement_age_s = 0.0;
  control::TrackerOutput output;  // command, flags, what the controller acted on
  control::WheelCommand wheels =  // what the command asks of the vehicle's wheels
      control::MecanumWheelSpeeds(control::MecanumWheelSpeeds::Zero());
  std::uint32_t violations = 0;  // control::LimitViolation bits of the command
  // Simulation only: the true pose and errors at t_s, and the world positions of the wheel
  // centres on the centre line (control::front_track_x_m), whose tracks make the coverage area.
  bool has_truth = false;
  Pose2 pose;
  control::TrackingError truth;
  Eigen::Vector2d front_wheel = Eigen::Vector2d::Zero();
  Eigen::Vector2d rear_wheel = Eigen::Vector2d::Zero();
};

// One frame as the camera stage saw it.
struct FrameRecord {
  std::uint64_t index = 0;
  double stamp_s = 0.0;
  std::string label;                            // where it came from ("frames/000012.png")
  std::optional<control::TrackingError> truth;  // the frame's true errors, if the source knows
  LineMeasurement measurement;
  std::string no_line_reason;  // why no line was found (when perception's details were kept)
  // Where tapes meet in view: the direction (vehicle frame) of every way leaving the junction
  // away from the vehicle, and of the way chosen (perception's branch choice), if any.
  std::vector<double> legs_rad;
  std::optional<double> chosen_leg_rad;
  bool bad = false;  // could not be used (reason in `problem`): no measurement was sent
  std::string problem;
  double source_s = 0.0;    // time to get the frame: render, read or decode
  double perceive_s = 0.0;  // time to measure it
};

struct StageTimes {
  double source_s = 0.0;  // rendering (simulation) or reading and decoding frames
  double perceive_s = 0.0;
  double control_s = 0.0;
};

struct RunResult {
  std::string controller_name;
  std::vector<TraceRow> rows;
  std::vector<FrameRecord> frames;
  QueueStats queue;  // the queue from the camera stage to the control stage
  // Measurements taken from the queue but passed over: a newer one was usable in the same period.
  std::uint64_t measurements_superseded = 0;
  std::uint64_t frames_dropped = 0;  // frames the camera stage could not keep up with
  perception::TrackingLineEstimator::Counts perception_counts;  // tracked vs searched frames
  std::string odometry_source;  // what placed the remembered tape (Perceiver::odometry_source)
  StageTimes total_times;       // summed over the run, seconds
  double wall_s = 0.0;
  double setup_wall_s = 0.0;          // of wall_s: building renderer, floor maps and estimator
  double max_tick_lateness_s = 0.0;   // threaded: how late the control thread ran at worst
  std::vector<WatchdogStall> stalls;  // threaded: threads the watchdog found silent
  std::string stop_reason;            // why the run ended: "duration", "end of source", ...
};

// Reports progress as a fraction in [0, 1]; may be empty.
using Progress = std::function<void(double)>;

}  // namespace agv::pipeline
