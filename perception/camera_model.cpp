#include "perception/camera_model.h"

#include <cmath>

#include <opencv2/calib3d.hpp>

namespace agv::perception {
namespace {

// Rays closer to horizontal than this never meet the floor within a useful range.
constexpr double kMinDownwardRayComponent = 1e-6;

}  // namespace

CameraModel::CameraModel(const CameraIntrinsics& intrinsics, const MountPose& mount)
    : intrinsics_(intrinsics),
      mount_(mount),
      r_vc_(mount.rotation()),
      camera_matrix_(cv::Mat(intrinsics.camera_matrix)),
      distortion_(intrinsics.distortion.empty()
                      ? cv::Mat()
                      : cv::Mat(intrinsics.distortion, true).reshape(1, 1)) {}

std::vector<cv::Point2d> CameraModel::undistort(const std::vector<cv::Point2d>& pixels) const {
  std::vector<cv::Point2d> normalised;
  if (pixels.empty()) return normalised;
  // OpenCV's default is 5 fixed-point iterations: not enough for metric accuracy at the corners.
  const cv::TermCriteria exact(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12);
  if (intrinsics_.fisheye) {
    cv::fisheye::undistortPoints(pixels, normalised, camera_matrix_, distortion_, cv::noArray(),
                                 cv::noArray(), exact);
    return normalised;
  }
  cv::undistortPoints(pixels, normalised, camera_matrix_, distortion_, cv::noArray(), cv::noArray(),
                      exact);
  return normalised;
}

void CameraModel::pixels_to_floor(const std::vector<cv::Point2d>& pixels,
                                  std::vector<Eigen::Vector2d>* floor,
                                  std::vector<bool>* valid) const {
  const std::vector<cv::Point2d> normalised = undistort(pixels);
  floor->assign(pixels.size(), Eigen::Vector2d::Zero());
  valid->assign(pixels.size(), false);
  const Eigen::Vector3d& t = mount_.xyz_m;
  for (size_t i = 0; i < normalised.size(); ++i) {
    const Eigen::Vector3d ray = r_vc_ * Eigen::Vector3d(normalised[i].x, normalised[i].y, 1.0);
    if (ray.z() > -kMinDownwardRayComponent) continue;
    const double scale = -t.z() / ray.z();
    if (scale <= 0.0) continue;
    (*floor)[i] = (t + scale * ray).head<2>();
    (*valid)[i] = true;
  }
}

std::optional<Eigen::Vector2d> CameraModel::pixel_to_floor(const cv::Point2d& pixel) const {
  std::vector<Eigen::Vector2d> floor;
  std::vector<bool> valid;
  pixels_to_floor({pixel}, &floor, &valid);
  if (!valid[0]) return std::nullopt;
  return floor[0];
}

std::optional<cv::Point2d> CameraModel::vehicle_to_pixel(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d p_camera = r_vc_.transpose() * (p - mount_.xyz_m);
  if (p_camera.z() <= 1e-9) return std::nullopt;
  return camera_point_to_pixel(p_camera);
}

cv::Point2d CameraModel::camera_point_to_pixel(const Eigen::Vector3d& p_camera) const {
  const std::vector<double>& k = intrinsics_.distortion;
  if (k.size() > 12) {  // the tilted sensor's terms: through OpenCV
    const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
    return project_camera_points(
               {cv::Point3f(0, 0, 0)}, zero,
               (cv::Mat_<double>(3, 1) << p_camera.x(), p_camera.y(), p_camera.z()))
        .front();
  }
  const cv::Matx33d& a = intrinsics_.camera_matrix;
  const double x = p_camera.x() / p_camera.z(), y = p_camera.y() / p_camera.z();
  auto coefficient = [&](size_t i) { return i < k.size() ? k[i] : 0.0; };
  double xd = x, yd = y;
  if (intrinsics_.fisheye) {
    // cv::fisheye::projectPoints: theta_d = theta (1 + k1 theta^2 + ... + k4 theta^8).
    const double r = std::hypot(x, y);
    if (r > 1e-8) {
      const double theta = std::atan(r), t2 = theta * theta;
      const double theta_d =
          theta *
          (1.0 + t2 * (coefficient(0) +
                       t2 * (coefficient(1) + t2 * (coefficient(2) + t2 * coefficient(3)))));
      xd = x * theta_d / r;
      yd = y * theta_d / r;
    }
  } else if (!k.empty()) {
    // cv::projectPoints: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]].
    const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
    const double radial = (1.0 + coefficient(0) * r2 + coefficient(1) * r4 + coefficient(4) * r6) /
                          (1.0 + coefficient(5) * r2 + coefficient(6) * r4 + coefficient(7) * r6);
    const double p1 = coefficient(2), p2 = coefficient(3);
    xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) + coefficient(8) * r2 +
         coefficient(9) * r4;
    yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y + coefficient(10) * r2 +
         coefficient(11) * r4;
  }
  // OpenCV's projections take fx, fy, cx, cy from the matrix (no skew).
  return {a(0, 0) * xd + a(0, 2), a(1, 1) * yd + a(1, 2)};
}

std::vector<cv::Point2d> CameraModel::project_camera_points(const std::vector<cv::Point3f>& points,
                                                            const cv::Mat& rvec,
                                                            const cv::Mat& tvec) const {
  std::vector<cv::Point3d> object(points.begin(), points.end());
  std::vector<cv::Point2d> image;
  if (intrinsics_.fisheye) {
    cv::fisheye::projectPoints(object, image, rvec, tvec, camera_matrix_,
                               distortion_.empty() ? cv::Mat::zeros(1, 4, CV_64F) : distortion_);
  } else {
    cv::projectPoints(object, rvec, tvec, camera_matrix_, distortion_, image);
  }
  return image;
}

}  // namespace agv::perception
