#pragma once

#include <opencv2/core.hpp>

#include "common/line_measurement.h"
#include "perception/camera_model.h"

namespace agv::perception {

// The detector most line followers use, kept as the yardstick for speed and accuracy: grey,
// GaussianBlur 5x5 (sigma 1.5), Canny (50, 150), HoughLinesP (1 px, 1 deg, 50 votes, segments of
// at least 50 px, gaps up to 10 px). Its segments are taken to the floor through the same camera
// calibration as our perception; those within 10 deg of the longest one (the tape's two edges)
// give the direction (their length-weighted mean direction) and the centre
// (midway between the outermost of them within 1.5 tape widths: the tape's two edges), hence
// e_theta and e_d. No line when only one edge is seen. No curvature, no junctions.
class HoughBaseline {
 public:
  HoughBaseline(const CameraModel& camera, double tape_width_m)
      : camera_(camera), tape_width_m_(tape_width_m) {}

  LineMeasurement estimate(const cv::Mat& frame_bgr, double stamp_s) const;

 private:
  CameraModel camera_;
  double tape_width_m_;
};

}  // namespace agv::perception
