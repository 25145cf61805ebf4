#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

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
    double resolution_m = 0.001;   // bird's-eye pixel
    double half_size_m = 0.08;     // the view is 2 x this square
    int min_features = 20;         // texture corners that must agree on a motion
    double min_correlation = 0.5;  // of the views once aligned (texture: 0.85-0.99, noise: < 0)
    double max_change_m = 0.01;    // a motion this far from the last one is refused
    double max_change_rad = 0.05;  //   (or turning this much more or less)
    double min_isotropy = 0.1;     // their gradients: smaller / larger eigenvalue at least this
  };

  FloorOdometry(const CameraModel& camera, const Options& options);
  explicit FloorOdometry(const CameraModel& camera) : FloorOdometry(camera, Options{}) {}

  // The vehicle's pose at this frame in its frame at the previous one; nullopt for the first
  // frame, or when the alignment fails or is not trusted.
  std::optional<Pose2> motion(const cv::Mat& frame);
  void reset() {
    previous_.release();
    last_motion_.reset();
  }

 private:
  cv::Mat birds_eye(const cv::Mat& frame) const;
  // Two consecutive bird's-eye views, as 8-bit images too, and the previous one's corners.
  struct Views {
    const cv::Mat& previous;
    const cv::Mat& now;
    cv::Mat previous_8u, now_8u;
    std::vector<cv::Point2f> corners;
  };
  // The motion between the views, the corners of the previous one first looked for at
  // `initial` (bird's-eye pixel -> pixel); nullopt when it cannot be read or is not trusted.
  std::optional<Pose2> follow(const Views& views, const Eigen::Matrix3d& initial) const;

  Options options_;
  Eigen::Vector2d centre_m_;          // the view's centre, vehicle frame
  Eigen::Matrix3d to_floor_;          // bird's-eye pixel (c, r, 1) -> floor point (vehicle frame)
  cv::Mat map_x_, map_y_;             // bird's-eye pixel -> camera pixel
  std::optional<Pose2> last_motion_;  // the last motion read (the prediction for the next)
  cv::Mat previous_;
  cv::Mat window_;  // Hanning window for the phase correlation
};

}  // namespace agv::perception
