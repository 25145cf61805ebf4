#pragma once

#include <optional>

#include <opencv2/core.hpp>

#include "common/pose2.h"
#include "perception/camera_model.h"

namespace agv::perception {

// The vehicle's motion between consecutive frames, read from the frames themselves: the floor's
// texture moves under a downward camera. Each frame is resampled to a bird's-eye view of the
// floor around the middle of the camera's view (lens distortion and perspective undone through
// the calibration) and band-passed to its texture; the shift between consecutive views is found
// by phase correlation (however large), the texture's corners are followed from there by
// pyramidal Lucas-Kanade, and the rigid motion most of them agree on (RANSAC) is the floor's.
// A floor with too little texture to tell (or a first frame) gives nothing.
class FloorOdometry {
 public:
  struct Options {
    double resolution_m = 0.001;  // bird's-eye pixel
    double half_size_m = 0.08;    // the view is 2 x this square
    int min_features = 20;        // texture corners that must agree on a motion
  };

  FloorOdometry(const CameraModel& camera, const Options& options);
  explicit FloorOdometry(const CameraModel& camera) : FloorOdometry(camera, Options{}) {}

  // The vehicle's pose at this frame in its frame at the previous one; nullopt for the first
  // frame, or when the alignment fails or is not trusted.
  std::optional<Pose2> motion(const cv::Mat& frame);
  void reset() { previous_.release(); }

 private:
  cv::Mat birds_eye(const cv::Mat& frame) const;

  Options options_;
  Eigen::Vector2d centre_m_;  // the view's centre, vehicle frame
  cv::Mat map_x_, map_y_;     // bird's-eye pixel -> camera pixel
  cv::Mat previous_;
  cv::Mat window_;  // Hanning window for the phase correlation
};

}  // namespace agv::perception
