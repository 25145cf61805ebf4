#pragma once

#include "common/line_measurement.h"
#include "common/pose2.h"
#include "control/path.h"

namespace agv::pipeline {

// The true tracking errors of a vehicle on a known path, with the foot point followed from one
// pose to the next (so that a path that comes back near itself is not confused). Also what a
// perfect localisation tells the controller (controller.input: pose).
class PathTruth {
 public:
  PathTruth(const control::Path& path, double start_s_m) : path_(path), s_m_(start_s_m) {}

  // The errors of `pose` (DESIGN.md signs); moves the foot point along.
  control::TrackingError errors(const Pose2& pose);

  // What localisation reports for `pose` at t_s: its errors, the curvature at its foot point
  // and the arc length left to the path's end (negative past it).
  LineMeasurement localisation(const Pose2& pose, double t_s);

 private:
  control::Path path_;
  double s_m_;
  control::PathProjection foot_;
};

}  // namespace agv::pipeline
