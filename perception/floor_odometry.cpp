#include "perception/floor_odometry.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "perception/floor_map.h"

namespace agv::perception {
namespace {

Eigen::Matrix3d homogeneous(const Pose2& pose) {
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  Eigen::Matrix3d m;
  m << c, -s, pose.x_m, s, c, pose.y_m, 0.0, 0.0, 1.0;
  return m;
}

}  // namespace

// Bird's-eye pixel (column c, row r) <-> floor point p (vehicle frame): the image's top towards
// the front and its left towards the left, as a downward camera sees it:
//   p = centre + res (size/2 - r, size/2 - c).
FloorOdometry::FloorOdometry(const CameraModel& camera, const Options& options)
    : options_(options) {
  centre_m_ = FloorMap::shared(camera)->view_centre_m();
  const int size = static_cast<int>(std::round(2.0 * options_.half_size_m / options_.resolution_m));
  const double res = options_.resolution_m, half = size / 2.0;
  to_floor_ << 0.0, -res, centre_m_.x() + res * half, -res, 0.0, centre_m_.y() + res * half, 0.0,
      0.0, 1.0;
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
  const cv::Mat now = birds_eye(frame);
  const cv::Mat before = previous_;
  previous_ = now;
  if (before.empty()) return std::nullopt;
  Views views{before, now, {}, {}, {}};
  before.convertTo(views.previous_8u, CV_8U, 4.0, 128.0);
  now.convertTo(views.now_8u, CV_8U, 4.0, 128.0);
  cv::goodFeaturesToTrack(views.previous_8u, views.corners, 300, 0.01, 4.0);
  if (static_cast<int>(views.corners.size()) < options_.min_features) return std::nullopt;
  // Where the texture's corners should be now: moved by the last motion (a vehicle's speed
  // changes little between frames); when that fails (the first motion, a sudden change), moved
  // by the shift phase correlation finds (any size, no rotation).
  std::optional<Pose2> motion;
  if (last_motion_)
    motion = follow(views, to_floor_.inverse() * homogeneous(last_motion_->inverse()) * to_floor_);
  if (!motion) {
    if (window_.empty()) cv::createHanningWindow(window_, now.size(), CV_32F);
    const cv::Point2d shift = cv::phaseCorrelate(views.previous, views.now, window_);
    Eigen::Matrix3d moved = Eigen::Matrix3d::Identity();
    moved(0, 2) = shift.x;
    moved(1, 2) = shift.y;
    motion = follow(views, moved);
  }
  // A motion far from the last one is not the vehicle's (a vehicle cannot change its speed
  // that much between frames): most likely the corners that agree are on something fixed in
  // the image (the vehicle's shadow edge, a glare spot).
  if (motion && last_motion_) {
    const Pose2 change = last_motion_->inverse().compose(*motion);
    if (change.translation().norm() > options_.max_change_m ||
        std::abs(change.yaw_rad) > options_.max_change_rad)
      motion.reset();
  }
  if (motion) last_motion_ = motion;
  return motion;
}

std::optional<Pose2> FloorOdometry::follow(const Views& views,
                                           const Eigen::Matrix3d& initial) const {
  // The texture's corners followed from their initial guess by pyramidal Lucas-Kanade, and the
  // rigid motion that moves most of them (RANSAC).
  const cv::Mat& previous_8u = views.previous_8u;
  const std::vector<cv::Point2f>& corners = views.corners;
  std::vector<cv::Point2f> followed;
  for (const cv::Point2f& c : corners) {
    const Eigen::Vector3d q = initial * Eigen::Vector3d(c.x, c.y, 1.0);
    followed.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
  std::vector<unsigned char> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(
      previous_8u, views.now_8u, corners, followed, status, error, cv::Size(15, 15), 2,
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
  // The corners that agree must show the motion in both directions: on a floor without texture
  // they lie on the tape's edges, which say nothing of the motion along them (the aperture
  // problem). Their summed gradient structure tensor must not be one-dimensional.
  cv::Mat gx, gy;
  cv::Sobel(previous_8u, gx, CV_32F, 1, 0);
  cv::Sobel(previous_8u, gy, CV_32F, 0, 1);
  Eigen::Matrix2d structure = Eigen::Matrix2d::Zero();
  const cv::Rect image(0, 0, gx.cols, gx.rows);
  for (size_t i = 0; i < from.size(); ++i) {
    if (!inliers[i]) continue;
    const cv::Rect window = cv::Rect(cvRound(from[i].x) - 3, cvRound(from[i].y) - 3, 7, 7) & image;
    for (int r = window.y; r < window.y + window.height; ++r) {
      for (int c = window.x; c < window.x + window.width; ++c) {
        const double x = gx.at<float>(r, c), y = gy.at<float>(r, c);
        structure += Eigen::Matrix2d{{x * x, x * y}, {x * y, y * y}};
      }
    }
  }
  const Eigen::Vector2d spread =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(structure).eigenvalues();
  if (!(spread[0] > options_.min_isotropy * spread[1])) return std::nullopt;
  // A similarity: take its rotation (a floor seen from a fixed height does not change scale).
  const double angle = std::atan2(similarity.at<double>(1, 0), similarity.at<double>(0, 0));
  cv::Mat warp =
      (cv::Mat_<float>(2, 3) << std::cos(angle), -std::sin(angle), similarity.at<double>(0, 2),
       std::sin(angle), std::cos(angle), similarity.at<double>(1, 2));
  // The texture must look the same once aligned: the previous view moved by the warp against
  // this one (normalised correlation over where both are seen). Sensor noise and a tape's edges
  // on a bare floor do not, however many corners agreed.
  cv::Mat aligned;
  cv::warpAffine(views.previous, aligned, warp, views.now.size(), cv::INTER_LINEAR,
                 cv::BORDER_CONSTANT, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  const cv::Mat seen_both = aligned == aligned;
  cv::Scalar mean_a, sd_a, mean_b, sd_b;
  cv::meanStdDev(aligned, mean_a, sd_a, seen_both);
  cv::meanStdDev(views.now, mean_b, sd_b, seen_both);
  cv::Mat product;
  cv::multiply(aligned - mean_a[0], views.now - mean_b[0], product);
  const double correlation = cv::mean(product, seen_both)[0] / std::max(1e-9, sd_a[0] * sd_b[0]);
  if (!(correlation >= options_.min_correlation)) return std::nullopt;
  // The previous view's pixel x shows in this view at W x. Through the bird's-eye mapping
  // G (pixel -> floor), a floor point p at the previous frame lies at G W G^-1 p now; for a
  // point fixed on the floor that is V^-1 p, V the vehicle's motion.
  Eigen::Matrix3d w = Eigen::Matrix3d::Identity();
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) w(r, c) = warp.at<float>(r, c);
  const Eigen::Matrix3d inverse_motion = to_floor_ * w * to_floor_.inverse();
  const Pose2 seen{inverse_motion(0, 2), inverse_motion(1, 2),
                   std::atan2(inverse_motion(1, 0), inverse_motion(0, 0))};
  return seen.inverse();
}

}  // namespace agv::perception
