#include "perception/floor_odometry.h"

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "perception/floor_map.h"

namespace agv::perception {

// Bird's-eye pixel (column c, row r) <-> floor point p (vehicle frame): the image's top towards
// the front and its left towards the left, as a downward camera sees it:
//   p = centre + res (size/2 - r, size/2 - c).
FloorOdometry::FloorOdometry(const CameraModel& camera, const Options& options)
    : options_(options) {
  const FloorMap floor(camera);
  centre_m_ = floor.view_centre_m();
  const int size = static_cast<int>(std::round(2.0 * options_.half_size_m / options_.resolution_m));
  map_x_.create(size, size, CV_32F);
  map_y_.create(size, size, CV_32F);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const Eigen::Vector2d p =
          centre_m_ + options_.resolution_m * Eigen::Vector2d(size / 2.0 - r, size / 2.0 - c);
      const std::optional<cv::Point2d> pixel = camera.floor_to_pixel(p);
      map_x_.at<float>(r, c) = pixel ? static_cast<float>(pixel->x) : -1.0f;
      map_y_.at<float>(r, c) = pixel ? static_cast<float>(pixel->y) : -1.0f;
    }
  }
}

cv::Mat FloorOdometry::birds_eye(const cv::Mat& frame) const {
  cv::Mat grey;
  if (frame.channels() == 3) {
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = frame;
  }
  cv::Mat view;
  cv::remap(grey, view, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  view.convertTo(view, CV_32F);
  // Band-pass: sensor noise off the fine texture, and the slow shading (and the tape's broad
  // band, which says nothing about motion along it) off the texture that shows the motion.
  cv::Mat smooth, broad;
  cv::GaussianBlur(view, smooth, cv::Size(3, 3), 0.8);
  cv::GaussianBlur(view, broad, cv::Size(0, 0), 4.0);
  return smooth - broad;
}

std::optional<Pose2> FloorOdometry::motion(const cv::Mat& frame) {
  const cv::Mat view = birds_eye(frame);
  if (previous_.empty()) {
    previous_ = view;
    return std::nullopt;
  }
  // The shift first, by phase correlation (any size, no rotation); then the texture's corners
  // followed from there by pyramidal Lucas-Kanade, and the rigid motion that moves most of them
  // (RANSAC).
  if (window_.empty()) cv::createHanningWindow(window_, view.size(), CV_32F);
  const cv::Point2d shift = cv::phaseCorrelate(previous_, view, window_);
  cv::Mat previous_8u, view_8u;
  previous_.convertTo(previous_8u, CV_8U, 4.0, 128.0);
  view.convertTo(view_8u, CV_8U, 4.0, 128.0);
  previous_ = view;
  std::vector<cv::Point2f> corners, followed;
  cv::goodFeaturesToTrack(previous_8u, corners, 300, 0.01, 4.0);
  if (static_cast<int>(corners.size()) < options_.min_features) return std::nullopt;
  for (const cv::Point2f& c : corners)
    followed.emplace_back(c.x + static_cast<float>(shift.x), c.y + static_cast<float>(shift.y));
  std::vector<unsigned char> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(
      previous_8u, view_8u, corners, followed, status, error, cv::Size(15, 15), 2,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01),
      cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<cv::Point2f> from, to;
  for (size_t i = 0; i < corners.size(); ++i) {
    if (!status[i]) continue;
    from.push_back(corners[i]);
    to.push_back(followed[i]);
  }
  if (static_cast<int>(from.size()) < options_.min_features) return std::nullopt;
  std::vector<unsigned char> inliers;
  const cv::Mat similarity =
      cv::estimateAffinePartial2D(from, to, inliers, cv::RANSAC, 1.0, 2000, 0.995, 10);
  int inlier_count = 0;
  for (unsigned char inlier : inliers) inlier_count += inlier ? 1 : 0;
  if (similarity.empty() || inlier_count < options_.min_features) return std::nullopt;
  // A similarity: take its rotation (a floor seen from a fixed height does not change scale).
  const double angle = std::atan2(similarity.at<double>(1, 0), similarity.at<double>(0, 0));
  cv::Mat warp =
      (cv::Mat_<float>(2, 3) << std::cos(angle), -std::sin(angle), similarity.at<double>(0, 2),
       std::sin(angle), std::cos(angle), similarity.at<double>(1, 2));
  // The previous view's pixel x shows in this view at W x. Through the bird's-eye mapping
  // G (pixel -> floor), a floor point p at the previous frame lies at G W G^-1 p now; for a
  // point fixed on the floor that is V^-1 p, V the vehicle's motion.
  const double res = options_.resolution_m, half = map_x_.rows / 2.0;
  Eigen::Matrix3d g;
  g << 0.0, -res, centre_m_.x() + res * half, -res, 0.0, centre_m_.y() + res * half, 0.0, 0.0, 1.0;
  Eigen::Matrix3d w = Eigen::Matrix3d::Identity();
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) w(r, c) = warp.at<float>(r, c);
  const Eigen::Matrix3d inverse_motion = g * w * g.inverse();
  const Pose2 seen{inverse_motion(0, 2), inverse_motion(1, 2),
                   std::atan2(inverse_motion(1, 0), inverse_motion(0, 0))};
  return seen.inverse();
}

}  // namespace agv::perception
