#include "perception/tracking_line_estimator.h"

#include <utility>

namespace agv::perception {

TrackingLineEstimator::TrackingLineEstimator(const CameraModel& camera,
                                             const LineEstimator::Options& options)
    : estimator_(camera, options) {}

void TrackingLineEstimator::reset() {
  previous_.reset();
  history_ = FollowHistory{};
  frames_since_search_ = 0;
}

LineMeasurement TrackingLineEstimator::measure(const cv::Mat& frame, double stamp_s,
                                               LineDetection* details) {
  const LineEstimator::Options& options = estimator_.options();
  LineDetection detection;
  LineMeasurement m;
  // Not through a junction: while a branch is held, the whole frame is searched (the branch
  // may show as a line of its own only frames after the tape it leaves).
  const bool trackable = options.tracking && previous_ && previous_->lines.size() == 1 &&
                         !previous_->one_edge && !previous_->junction &&
                         !history_.branch_heading_rad &&
                         frames_since_search_ + 1 < std::max(1, options.search_every_frames);
  bool done = false;
  if (trackable) {
    m = estimator_.track(frame, stamp_s, *previous_, &detection, &history_);
    done = m.line_found;
    if (done) {
      ++counts_.tracked;
      ++frames_since_search_;
    } else {
      ++counts_.track_failed;
    }
  }
  if (!done) {
    m = estimator_.estimate(frame, stamp_s, &detection, &history_);
    ++counts_.searched;
    frames_since_search_ = 0;
  }
  history_.update(detection.branch_heading_rad,
                  m.line_found ? std::optional<CurveModel>(detection.followed_model) : std::nullopt,
                  m.line_found ? std::optional<double>(m.tape_width_m) : std::nullopt,
                  m.line_found ? std::optional<ContrastAxis>(detection.axis) : std::nullopt);
  if (details) *details = detection;
  if (m.line_found) {
    previous_ = std::move(detection);
  } else {
    previous_.reset();
  }
  return m;
}

}  // namespace agv::perception
