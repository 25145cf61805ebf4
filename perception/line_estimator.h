#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/line_measurement.h"
#include "perception/camera_model.h"
#include "perception/edge_scan.h"
#include "perception/floor_map.h"

namespace agv::perception {

// What is known in advance about the tape.
struct TapeHints {
  double width_m = 0.025;              // expected width; 0: unknown (no width check)
  std::optional<cv::Vec3d> color_bgr;  // tape colour; nullopt: found from the image
};

// Everything the estimator saw in one frame, for annotation, plots and tests.
struct LineDetection {
  std::vector<EdgePair> edges;                   // pixel edges per scan line
  std::vector<Eigen::Vector2d> centre_points_m;  // vehicle frame, one per edge pair
  std::vector<double> widths_m;                  // chord per edge pair
  std::vector<bool> inliers;
  Eigen::Vector2d line_point_m = Eigen::Vector2d::Zero();  // fitted centre line, vehicle frame
  Eigen::Vector2d line_direction = Eigen::Vector2d::UnitX();
  double residual_rms_m = 0.0;
  double span_m = 0.0;
  double measured_width_m = 0.0;
  std::string rejected_because;  // empty when a line was found
};

// Finds the guide line in a frame and reports it as (e_theta, e_d) of the vehicle reference
// point (shared/DESIGN.md), through the camera's floor mapping:
//  1. a linear colour axis (tape colour hint or automatic) turns the frame into contrast;
//  2. on a 1/4-size copy, a bar detector tuned to the tape width, a threshold and connected
//     regions say where the tape may be;
//  3. along each full-resolution row (or column) across the tape, the two edges are found to
//     sub-pixel precision at the half-way crossings of the local contrast;
//  4. both edges are mapped to the floor; their midpoint lies on the tape's centre line
//     whatever the perspective (it is the midpoint of points on two parallel lines);
//  5. a robust line fit through the centre points, checked against the tape width, the
//     visible length and the residuals, gives the line or line_found = false.
class LineEstimator {
 public:
  struct Options {
    TapeHints tape;
    int downsample = 4;  // a power of two
    int min_region_area_small_px = 12;
    int min_points = 12;
    double min_visible_length_m = 0.03;
    double width_tolerance = 0.35;        // accepted |measured - expected| / expected
    double width_spread_tolerance = 0.3;  // accepted 10-90 % range of the widths / median width
    double min_confidence = 0.1;          // weaker evidence: no line
    double inlier_threshold_m = 0.0015;
    double min_inlier_fraction = 0.5;
    int ransac_iterations = 64;
    EdgeScanOptions scan;
  };

  LineEstimator(const CameraModel& camera, const Options& options);

  // Measurement of one frame taken at stamp_s (8-bit BGR or grey, the camera's size; any other
  // frame gives line_found = false with the reason in `details`).
  LineMeasurement estimate(const cv::Mat& frame, double stamp_s,
                           LineDetection* details = nullptr) const;

  const FloorMap& floor_map() const { return floor_map_; }
  const CameraModel& camera() const { return camera_; }
  const Options& options() const { return options_; }

 private:
  CameraModel camera_;
  Options options_;
  FloorMap floor_map_;
  std::vector<double> bar_widths_small_px_;  // bar detector widths (see find_tape_regions)
};

}  // namespace agv::perception
