#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "perception/mount_pose.h"

namespace agv::perception {

// Pinhole intrinsics with OpenCV's distortion model, as OpenCV's calibration sample writes them:
// the standard model (k1 k2 p1 p2 [k3 [k4 k5 k6 ...]]) or, with `fisheye`, OpenCV's equidistant
// fisheye model (cv::fisheye: k1 k2 k3 k4).
struct CameraIntrinsics {
  int width_px = 640;
  int height_px = 480;
  cv::Matx33d camera_matrix = cv::Matx33d(384, 0, 319.5, 0, 384, 239.5, 0, 0, 1);
  std::vector<double> distortion;  // empty: none
  bool fisheye = false;
};

// Maps pixels to points of the floor plane z = 0 in the vehicle frame and back, through the
// lens distortion, the pinhole and the mount pose. Pixel coordinates follow OpenCV: the centre
// of pixel (0, 0) is at (0, 0).
class CameraModel {
 public:
  CameraModel(const CameraIntrinsics& intrinsics, const MountPose& mount);

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const MountPose& mount() const { return mount_; }

  // Floor point (vehicle frame, metres) seen at a pixel; nullopt when that pixel's ray does not
  // reach the floor in front of the camera.
  std::optional<Eigen::Vector2d> pixel_to_floor(const cv::Point2d& pixel) const;
  // Batch form; valid[i] says whether floor[i] is set.
  void pixels_to_floor(const std::vector<cv::Point2d>& pixels, std::vector<Eigen::Vector2d>* floor,
                       std::vector<bool>* valid) const;

  // Pixel where a point given in the vehicle frame is seen; nullopt when it is behind the camera.
  std::optional<cv::Point2d> vehicle_to_pixel(const Eigen::Vector3d& point_vehicle_m) const;
  // Pixel of a point given in the camera frame (in front of it), as project_camera_points gives
  // it: OpenCV's lens models written out for one point (their per-call set-up cost more than the
  // arithmetic); the tilted-sensor model (14 coefficients) through OpenCV.
  cv::Point2d camera_point_to_pixel(const Eigen::Vector3d& point_camera_m) const;
  std::optional<cv::Point2d> floor_to_pixel(const Eigen::Vector2d& floor_vehicle_m) const {
    return vehicle_to_pixel({floor_vehicle_m.x(), floor_vehicle_m.y(), 0.0});
  }

  // Undistorted normalised image coordinates (x/z, y/z in the camera frame) of pixels.
  std::vector<cv::Point2d> undistort(const std::vector<cv::Point2d>& pixels) const;

  // Pixels of points given in a frame posed (rvec, tvec) in the camera frame, as
  // cv::projectPoints (cv::fisheye::projectPoints for a fisheye lens) gives them.
  std::vector<cv::Point2d> project_camera_points(const std::vector<cv::Point3f>& points,
                                                 const cv::Mat& rvec, const cv::Mat& tvec) const;

 private:
  CameraIntrinsics intrinsics_;
  MountPose mount_;
  Eigen::Matrix3d r_vc_;
  cv::Mat camera_matrix_;
  cv::Mat distortion_;
};

}  // namespace agv::perception
