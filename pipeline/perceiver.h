#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/angles.h"
#include "common/line_measurement.h"
#include "perception/floor_odometry.h"
#include "perception/path_memory.h"
#include "perception/tracking_line_estimator.h"
#include "pipeline/frame_source.h"
#include "pipeline/sim/path_truth.h"

namespace agv::pipeline {

// What turns a frame into a measurement of the line: perception of its image, or (in a
// simulation whose controller takes the pose) localisation from its true pose.
class Perceiver {
 public:
  virtual ~Perceiver() = default;
  // The measurement of a usable frame; `details` (may be null) receives what perception saw.
  virtual LineMeasurement measure(const SourceFrame& frame, perception::LineDetection* details) = 0;
  // The next frame does not follow the last one (a bad frame came between).
  virtual void reset() {}
  virtual perception::TrackingLineEstimator::Counts counts() const { return {}; }
  // What moved the remembered tape with the vehicle: "wheel odometry", "none" (no path memory,
  // or frames without odometry: every line carried back from the view), ...
  virtual std::string odometry_source() const { return "none"; }
};

// Perception of the frame's image: the line estimator, tracking between full searches, and (with
// a path memory) the errors at the vehicle read from the remembered tape under it, placed with
// the frame's wheel odometry or, for frames without, with the motion read from the frames
// themselves (FloorOdometry; where the floor shows too little texture, the last motion again).
class ImagePerceiver : public Perceiver {
 public:
  ImagePerceiver(const perception::CameraModel& camera,
                 const perception::LineEstimator::Options& options, bool path_memory)
      : estimator_(camera, options) {
    if (!path_memory) return;
    memory_.emplace();
    floor_odometry_.emplace(camera);
  }
  LineMeasurement measure(const SourceFrame& frame, perception::LineDetection* details) override {
    if (!memory_) return estimator_.measure(frame.image, frame.t_s, details);
    perception::LineDetection local;
    perception::LineDetection& detection = details ? *details : local;
    perception::OdometryKind kind;
    const std::optional<Pose2> odometry = odometry_of(frame, &kind);
    if (odometry && last_odometry_)
      estimator_.vehicle_turned(wrap_angle_rad(odometry->yaw_rad - last_odometry_->yaw_rad));
    last_odometry_ = odometry;
    const LineMeasurement in_view = estimator_.measure(frame.image, frame.t_s, &detection);
    const LineMeasurement m = memory_->update(in_view, detection, odometry, kind);
    if (!m.line_found && !memory_->refused_because().empty())
      detection.rejected_because = memory_->refused_because();
    return m;
  }
  // A bad frame between: the line tracking starts again; the remembered tape stays (the
  // odometry still places it), but motion read from the frames must start again.
  void reset() override {
    estimator_.reset();
    if (floor_odometry_) floor_odometry_->reset();
  }
  perception::TrackingLineEstimator::Counts counts() const override { return estimator_.counts(); }
  std::string odometry_source() const override;
  // The centre-line points the path memory holds, in the vehicle frame of the last frame (none
  // without a path memory).
  std::vector<Eigen::Vector2d> remembered_tape() const {
    return memory_ ? memory_->points_in_vehicle_frame() : std::vector<Eigen::Vector2d>{};
  }

 private:
  // The frame's odometry pose: the wheels', else integrated from the motion read from the
  // frames, else from the last motion read (a guess); `kind` says which.
  std::optional<Pose2> odometry_of(const SourceFrame& frame, perception::OdometryKind* kind);

  perception::TrackingLineEstimator estimator_;
  std::optional<perception::PathMemory> memory_;
  std::optional<perception::FloorOdometry> floor_odometry_;
  Pose2 frame_odometry_;              // integrated from the frames' motion
  std::optional<Pose2> last_motion_;  // for frames whose motion cannot be read
  std::optional<Pose2> last_odometry_;  // the frame before's, to turn what is held with
  long wheel_frames_ = 0, floor_frames_ = 0, repeated_frames_ = 0;
};

// Localisation: the errors of the frame's true pose against the path (controller.input: pose).
class LocalisationPerceiver : public Perceiver {
 public:
  explicit LocalisationPerceiver(PathTruth truth) : truth_(std::move(truth)) {}
  LineMeasurement measure(const SourceFrame& frame, perception::LineDetection*) override {
    return truth_.localisation(*frame.pose, frame.t_s);
  }

 private:
  PathTruth truth_;
};

}  // namespace agv::pipeline
