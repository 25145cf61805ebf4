#pragma once

#include <memory>
#include <string>

#include "common/line_measurement.h"
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

// Perception of the frame's image: the line estimator, tracking between full searches.
class ImagePerceiver : public Perceiver {
 public:
  ImagePerceiver(const perception::CameraModel& camera,
                 const perception::LineEstimator::Options& options)
      : estimator_(camera, options) {}
  LineMeasurement measure(const SourceFrame& frame, perception::LineDetection* details) override {
    return estimator_.measure(frame.image, frame.t_s, details);
  }
  void reset() override { estimator_.reset(); }
  perception::TrackingLineEstimator::Counts counts() const override { return estimator_.counts(); }

 private:
  perception::TrackingLineEstimator estimator_;
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
