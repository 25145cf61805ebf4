#pragma once

#include <opencv2/core.hpp>
#include <optional>

#include "common/line_measurement.h"
#include "perception/line_estimator.h"

namespace agv::perception {

// Measures the frames of one camera in time order. A frame is tracked (LineEstimator::track:
// scanned only where the line of the frame before predicts the tape) when the frame before had
// exactly one line and no junction; otherwise, when tracking fails (the line jumped, a tape
// crosses the band, a check fails), and at least every search_every_frames-th frame (to see
// lines that come into view), the whole frame is searched (LineEstimator::estimate). Tracking
// never reports a line the full search would reject: it applies the same checks. What was
// followed is kept to through junctions and across the view (FollowHistory, choose_line).
class TrackingLineEstimator {
 public:
  TrackingLineEstimator(const CameraModel& camera, const LineEstimator::Options& options);

  LineMeasurement measure(const cv::Mat& frame, double stamp_s, LineDetection* details = nullptr);
  // Forget the frame before (after a gap in the sequence).
  void reset();
  // The vehicle turned by yaw_rad (anticlockwise, odometry) since the frame before; call before
  // measuring the frame (FollowHistory::vehicle_turned).
  void vehicle_turned(double yaw_rad) { history_.vehicle_turned(yaw_rad); }

  struct Counts {
    int tracked = 0;       // frames measured by tracking
    int searched = 0;      // frames that needed the full search
    int track_failed = 0;  // of those, frames where tracking was tried first
  };
  const Counts& counts() const { return counts_; }
  const LineEstimator& estimator() const { return estimator_; }

 private:
  LineEstimator estimator_;
  std::optional<LineDetection> previous_;  // the last frame's detection, when it found a line
  FollowHistory history_;                  // what was followed, kept to through junctions
  int frames_since_search_ = 0;
  Counts counts_;
};

}  // namespace agv::perception
