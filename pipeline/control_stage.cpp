#include "pipeline/control_stage.h"

#include <chrono>

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

// Measurement times are sums of periods: a nanosecond of slack keeps rounding from delaying one
// by a whole period.
constexpr double kMeasurementTimeSlack_s = 1e-9;

}  // namespace

ControlStage::ControlStage(control::LineTracker tracker, BoundedQueue<StampedMeasurement>& queue,
                           Options options, std::optional<PathTruth> truth)
    : tracker_(std::move(tracker)),
      queue_(queue),
      options_(std::move(options)),
      truth_(std::move(truth)),
      previous_command_(options_.start_command) {}

std::optional<StampedMeasurement> ControlStage::newest_usable(double t_s) {
  for (std::optional<StampedMeasurement> item = queue_.pop(std::chrono::nanoseconds(0)); item;
       item = queue_.pop(std::chrono::nanoseconds(0))) {
    in_transit_.push_back(std::move(*item));
  }
  std::optional<StampedMeasurement> usable;
  while (!in_transit_.empty() && in_transit_.front().available_s <= t_s + kMeasurementTimeSlack_s) {
    if (usable) ++superseded_;
    usable = std::move(in_transit_.front());
    in_transit_.pop_front();
  }
  return usable;
}

TraceRow ControlStage::step(double t_s, const std::optional<Pose2>& true_pose) {
  const std::optional<StampedMeasurement> arrived = newest_usable(t_s);
  if (arrived) newest_ = arrived;
  const Clock::time_point start = Clock::now();
  const control::TrackerOutput output = tracker_.step(
      arrived ? std::optional<LineMeasurement>(arrived->measurement) : std::nullopt, t_s);
  compute_s_ += std::chrono::duration<double>(Clock::now() - start).count();
  TraceRow row = row_of(t_s, output, true_pose);
  row.measurement_arrived = arrived.has_value();
  return row;
}

TraceRow ControlStage::brake(double t_s, const std::optional<Pose2>& true_pose) {
  const std::optional<StampedMeasurement> arrived = newest_usable(t_s);
  if (arrived) newest_ = arrived;
  TraceRow row = row_of(t_s, tracker_.brake(t_s), true_pose);
  row.measurement_arrived = arrived.has_value();
  return row;
}

TraceRow ControlStage::row_of(double t_s, const control::TrackerOutput& output,
                              const std::optional<Pose2>& true_pose) {
  TraceRow row;
  row.t_s = t_s;
  if (newest_) {
    row.has_measurement = true;
    row.measurement = newest_->measurement;
    row.measurement_age_s = t_s - newest_->measurement.stamp_s;
  }
  row.output = output;
  row.wheels = control::wheel_command(options_.drive, output.command);
  row.violations =
      control::check_limits(output.command, previous_command_, options_.limits, options_.ts_s);
  previous_command_ = output.command;
  if (true_pose) {
    row.has_truth = true;
    row.pose = *true_pose;
    if (truth_) row.truth = truth_->errors(*true_pose);
    row.front_wheel = true_pose->transform({control::front_track_x_m(options_.drive), 0.0});
    row.rear_wheel = true_pose->transform({control::rear_track_x_m(options_.drive), 0.0});
  }
  return row;
}

}  // namespace agv::pipeline
