#include "perception/mount_calibration.h"

#include <cmath>
#include <map>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "common/input_error.h"

namespace agv::perception {
namespace {

// Camera pose in V from a rotation vector and translation of X_c = R X_v + t.
MountPose mount_of(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d r_cv;
  cv::cv2eigen(cv::Mat(r), r_cv);
  const Eigen::Vector3d t(tvec[0], tvec[1], tvec[2]);
  return MountPose::from_rotation(-r_cv.transpose() * t, r_cv.transpose());
}

Eigen::Matrix<double, 6, 1> mount_vector(const MountPose& m) {
  Eigen::Matrix<double, 6, 1> v;
  v << m.xyz_m, m.rpy_rad;
  return v;
}

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

}  // namespace

std::array<Eigen::Vector3d, 4> tag_corners_in_vehicle(const FloorTagPose& tag) {
  // Detector order: ideal (-1, 1), (1, 1), (1, -1), (-1, -1) with the ideal y pointing down in
  // the printed image, i.e. against the tag's y on the floor.
  const double h = 0.5 * tag.size_m, c = std::cos(tag.yaw_rad), s = std::sin(tag.yaw_rad);
  const double ideal[4][2] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  std::array<Eigen::Vector3d, 4> corners;
  for (int k = 0; k < 4; ++k) {
    const double lx = ideal[k][0] * h, ly = -ideal[k][1] * h;
    corners[k] = {tag.x_m + c * lx - s * ly, tag.y_m + s * lx + c * ly, 0.0};
  }
  return corners;
}

MountCalibration calibrate_mount(const CameraIntrinsics& intrinsics,
                                 const std::vector<cv::Mat>& frames,
                                 const std::vector<std::string>& frame_names,
                                 const FloorTagsFile& tags) {
  AprilTagDetector::Options options;
  options.family = tags.family;
  const AprilTagDetector detector(options);
  std::map<int, FloorTagPose> known;
  for (const FloorTagPose& t : tags.tags) known[t.id] = t;

  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::map<int, int> seen;
  MountCalibration result;

  for (size_t f = 0; f < frames.size(); ++f) {
    bool used = false;
    for (const TagDetection& d : detector.detect(frames[f])) {
      const auto it = known.find(d.id);
      if (it == known.end()) continue;
      const auto corners = tag_corners_in_vehicle(it->second);
      for (int k = 0; k < 4; ++k) {
        object.emplace_back(corners[k].x(), corners[k].y(), corners[k].z());
        image.push_back(d.corners_px[k]);
      }
      ++seen[d.id];
      used = true;
    }
    result.frames_used += used ? 1 : 0;
  }
  if (object.size() < 4) {
    std::string ids;
    for (const FloorTagPose& t : tags.tags) ids += (ids.empty() ? "" : ", ") + std::to_string(t.id);
    throw InputError("no tag of TAGS.yaml (" + tags.family + " ids " + ids + ") was found in " +
                     std::to_string(frames.size()) + " frame(s)" +
                     (frame_names.empty() ? "" : " (" + frame_names.front() + " ...)") +
                     "; at least one whole tag is needed");
  }
  result.tags_seen = static_cast<int>(seen.size());
  result.points = static_cast<int>(object.size());

  const cv::Mat k(intrinsics.camera_matrix);
  const cv::Mat dist(intrinsics.distortion);
  // Start: IPPE on the first tag's corners (a square), of its two solutions the one whose
  // camera is above the floor and which reprojects all points best; then all points, LM.
  std::vector<cv::Point3d> first(object.begin(), object.begin() + 4);
  std::vector<cv::Point2d> first_px(image.begin(), image.begin() + 4);
  std::vector<cv::Mat> rvecs, tvecs;
  cv::solvePnPGeneric(first, first_px, k, dist, rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
  cv::Vec3d best_r, best_t;
  double best_error = 1e300;
  for (size_t i = 0; i < rvecs.size(); ++i) {
    const cv::Vec3d r(rvecs[i]), t(tvecs[i]);
    if (mount_of(r, t).xyz_m.z() <= 0.0) continue;
    std::vector<cv::Point2d> projected;
    cv::projectPoints(object, r, t, k, dist, projected);
    double e = 0.0;
    for (size_t j = 0; j < image.size(); ++j) e += std::pow(cv::norm(projected[j] - image[j]), 2);
    if (e < best_error) {
      best_error = e;
      best_r = r;
      best_t = t;
    }
  }
  if (best_error == 1e300) throw InputError("the tags give no camera pose above the floor");
  cv::solvePnPRefineLM(
      object, image, k, dist, best_r, best_t,
      cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-12));

  std::vector<cv::Point2d> projected;
  cv::Mat jacobian;
  cv::projectPoints(object, best_r, best_t, k, dist, projected, jacobian);
  double sum = 0.0;
  for (size_t j = 0; j < image.size(); ++j) sum += std::pow(cv::norm(projected[j] - image[j]), 2);
  result.rms_px = std::sqrt(sum / image.size());
  result.mount = mount_of(best_r, best_t);

  // Covariance of (rvec, tvec): sigma^2 (J^T J)^-1, sigma^2 from the residuals (2n - 6 degrees
  // of freedom); carried to (xyz, rpy) through the numerical Jacobian of the conversion.
  Eigen::MatrixXd j_pose;
  cv::cv2eigen(jacobian.colRange(0, 6), j_pose);
  const double dof = std::max(1.0, 2.0 * image.size() - 6.0);
  const Eigen::Matrix<double, 6, 6> cov_pose =
      (sum / dof) * (j_pose.transpose() * j_pose).inverse();
  Eigen::Matrix<double, 6, 6> j_mount;
  const Eigen::Matrix<double, 6, 1> at = mount_vector(result.mount);
  for (int c = 0; c < 6; ++c) {
    cv::Vec3d r = best_r, t = best_t;
    const double step = 1e-7;
    (c < 3 ? r[c] : t[c - 3]) += step;
    Eigen::Matrix<double, 6, 1> d = (mount_vector(mount_of(r, t)) - at) / step;
    for (int a = 3; a < 6; ++a) d[a] = wrap(d[a] * step) / step;
    j_mount.col(c) = d;
  }
  const Eigen::Matrix<double, 6, 6> cov_mount = j_mount * cov_pose * j_mount.transpose();
  result.sigma = cov_mount.diagonal().cwiseMax(0.0).cwiseSqrt();

  if (result.tags_seen < 2)
    result.warnings.push_back(
        "only one tag seen: the mount rests on 4 corners; two or more tags spread over the view "
        "constrain it far better");
  if (result.rms_px > 1.0)
    result.warnings.push_back(
        "reprojection RMS above 1 px: check the tag poses in TAGS.yaml, "
        "their size, and the camera intrinsics");
  return result;
}

}  // namespace agv::perception
