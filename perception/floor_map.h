#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>

#include "perception/camera_model.h"

namespace agv::perception {

// The floor point (vehicle frame) that every pixel centre of a camera sees, computed once per
// camera so that per-frame work needs no undistortion. NaN where a pixel sees no floor.
class FloorMap {
 public:
  explicit FloorMap(const CameraModel& camera);

  // The map of a camera, made once per process for every camera with the same intrinsics and
  // mount (making one undistorts every pixel: 0.1-0.3 s at VGA) and shared, read-only, by the
  // renderer and the estimators of every run. Thread-safe; the last 8 cameras are kept.
  static std::shared_ptr<const FloorMap> shared(const CameraModel& camera);

  const cv::Mat& x_m() const { return x_m_; }  // CV_32F, image size
  const cv::Mat& y_m() const { return y_m_; }
  // Side of the floor patch a pixel covers (square root of the Jacobian's determinant), metres.
  const cv::Mat& footprint_m() const { return footprint_m_; }

  // Floor point at a sub-pixel position, by bilinear interpolation of the map; nullopt outside
  // the image or where the floor is not seen. The map is smooth, so interpolation error is
  // far below a micrometre for usual lenses.
  std::optional<Eigen::Vector2d> at(double u_px, double v_px) const;
  // Asks the processor to bring the map entries at() reads there nearer, ahead of the call.
  void prefetch(double u_px, double v_px) const;

  // A circle (vehicle frame) containing every floor point in view.
  Eigen::Vector2d view_centre_m() const { return view_centre_m_; }
  double view_radius_m() const { return view_radius_m_; }
  // Median footprint: the typical floor size of one pixel.
  double typical_footprint_m() const { return typical_footprint_m_; }

 private:
  // The map cell (u0, v0) whose corners at() interpolates between, or nullopt outside the image.
  std::optional<std::pair<int, int>> cell_of(double u_px, double v_px) const;

  cv::Mat x_m_, y_m_, footprint_m_;
  cv::Mat xy_m_;  // CV_32FC2: x_m_ and y_m_ interleaved, for at()
  Eigen::Vector2d view_centre_m_ = Eigen::Vector2d::Zero();
  double view_radius_m_ = 0.0;
  double typical_footprint_m_ = 0.0;
};

}  // namespace agv::perception
