#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "common/line_measurement.h"
#include "perception/camera_model.h"
#include "perception/line_estimator.h"

namespace agv::pipeline {

// A copy of the frame (as BGR) with what perception found drawn on it: the tape edges it used
// (small dots), every fitted line projected back through the camera (thin), the followed line
// (thick), the junction and its branches (arrows), and e_d, e_theta, curvature, confidence as
// text; "NO LINE" and the reason when none was found. `caption` goes in the top-left corner.
cv::Mat annotate_frame(const cv::Mat& frame, const perception::CameraModel& camera,
                       const perception::LineDetection& detection,
                       const LineMeasurement& measurement, const std::string& caption);

}  // namespace agv::pipeline
