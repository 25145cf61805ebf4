#pragma once

#include <memory>
#include <string>

#include "common/line_measurement.h"
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
};

// Perception of the frame's image: the line estimator, tracking between full searches, and (with
// a path memory) the errors at the vehicle read from the remembered tape under it, placed with
// the frame's odometry.
class ImagePerceiver : public Perceiver {
 public:
  ImagePerceiver(const perception::CameraModel& camera,
                 const perception::LineEstimator::Options& options, bool path_memory)
      : estimator_(camera, options) {
    if (path_memory) memory_.emplace();
  }
  LineMeasurement measure(const SourceFrame& frame, perception::LineDetection* details) override {
    if (!memory_) return estimator_.measure(frame.image, frame.t_s, details);
    perception::LineDetection local;
    perception::LineDetection& detection = details ? *details : local;
    const LineMeasurement in_view = estimator_.measure(frame.image, frame.t_s, &detection);
    return memory_->update(in_view, detection, frame.odometry);
  }
  // A bad frame between: the line tracking starts again; the remembered tape stays (the
  // odometry still places it).
  void reset() override { estimator_.reset(); }
  perception::TrackingLineEstimator::Counts counts() const override { return estimator_.counts(); }

 private:
  perception::TrackingLineEstimator estimator_;
  std::optional<perception::PathMemory> memory_;
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
