#pragma once

#include <deque>
#include <optional>

#include "control/line_tracker.h"
#include "control/vehicle_drive.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/run_result.h"
#include "pipeline/sim/path_truth.h"

namespace agv::pipeline {

// The control half of the loop: the newest measurement usable by now -> the controller (inside
// the LineTracker's limits and line-loss handling) -> the command -> a trace row. Written once;
// the lockstep and threaded loops only decide when step() runs. The command goes to a plant or
// to a real vehicle, as the loop decides.
class ControlStage {
 public:
  struct Options {
    control::VehicleDrive drive;    // for the wheel commands and wheel tracks of the trace
    control::VehicleLimits limits;  // the limits each command is checked against
    double ts_s = 0.1;
    BodyTwist start_command;  // the command before the first period
  };

  // `truth`: in simulation, the path the rows' true errors are measured against.
  ControlStage(control::LineTracker tracker, BoundedQueue<StampedMeasurement>& queue,
               Options options, std::optional<PathTruth> truth = std::nullopt);

  // One control period at t_s: takes what arrived in the queue, keeps what is not yet usable
  // (transport latency), acts on the newest usable measurement. `true_pose`: the vehicle's pose
  // at t_s, in simulation.
  TraceRow step(double t_s, const std::optional<Pose2>& true_pose = std::nullopt);
  // One period of a vehicle told to stop (the run is ending): brakes within the limits.
  TraceRow brake(double t_s, const std::optional<Pose2>& true_pose = std::nullopt);

  std::string controller_name() const { return tracker_.controller().name(); }
  // Usable measurements passed over because a newer one was usable in the same period.
  std::uint64_t superseded() const { return superseded_; }
  double compute_s() const { return compute_s_; }  // time spent in the controller

 private:
  std::optional<StampedMeasurement> newest_usable(double t_s);
  TraceRow row_of(double t_s, const control::TrackerOutput& output,
                  const std::optional<Pose2>& true_pose);

  control::LineTracker tracker_;
  BoundedQueue<StampedMeasurement>& queue_;
  Options options_;
  std::optional<PathTruth> truth_;
  std::deque<StampedMeasurement> in_transit_;  // taken from the queue, not yet usable
  std::optional<StampedMeasurement> newest_;   // the newest measurement acted on so far
  BodyTwist previous_command_;
  std::uint64_t superseded_ = 0;
  double compute_s_ = 0.0;
};

}  // namespace agv::pipeline
