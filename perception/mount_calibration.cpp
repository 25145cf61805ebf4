#include "perception/mount_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// A camera pose: X_c = R(r) X_v + t.
struct PoseFit {
  cv::Vec3d r, t;
};

// Reprojection RMS (px) of the points under a pose.
double rms_of(const std::vector<cv::Point3d>& object, const std::vector<cv::Point2d>& image,
              const PoseFit& pose, const cv::Mat& k, const cv::Mat& dist) {
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, pose.r, pose.t, k, dist, projected);
  double sum = 0.0;
  for (size_t j = 0; j < image.size(); ++j) sum += std::pow(cv::norm(projected[j] - image[j]), 2);
  return std::sqrt(sum / std::max<size_t>(1, image.size()));
}

// The camera pose (X_c = R X_v + t) that best reprojects the points: IPPE on the first tag's
// corners (a square), of its two solutions the one whose camera is above the floor and which
// reprojects all points best; then all points, LM.
PoseFit fit_pose(const std::vector<cv::Point3d>& object, const std::vector<cv::Point2d>& image,
                 const cv::Mat& k, const cv::Mat& dist) {
  std::vector<cv::Point3d> first(object.begin(), object.begin() + 4);
  std::vector<cv::Point2d> first_px(image.begin(), image.begin() + 4);
  std::vector<cv::Mat> rvecs, tvecs;
  cv::solvePnPGeneric(first, first_px, k, dist, rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
  PoseFit best;
  double best_error = 1e300;
  for (size_t i = 0; i < rvecs.size(); ++i) {
    const PoseFit candidate{cv::Vec3d(rvecs[i]), cv::Vec3d(tvecs[i])};
    if (mount_of(candidate.r, candidate.t).xyz_m.z() <= 0.0) continue;
    const double e = rms_of(object, image, candidate, k, dist);
    if (e < best_error) {
      best_error = e;
      best = candidate;
    }
  }
  if (best_error == 1e300) throw InputError("the tags give no camera pose above the floor");
  cv::solvePnPRefineLM(
      object, image, k, dist, best.r, best.t,
      cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-12));
  return best;
}

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
                                 const FloorTagsFile& tags,
                                 const std::function<void(double)>& progress) {
  AprilTagDetector::Options options;
  options.family = tags.family;
  const AprilTagDetector detector(options);
  std::map<int, FloorTagPose> known;
  for (const FloorTagPose& t : tags.tags) known[t.id] = t;

  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::vector<int> point_tag;  // which tag each point is a corner of
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
        point_tag.push_back(d.id);
      }
      ++seen[d.id];
      used = true;
    }
    result.frames_used += used ? 1 : 0;
    if (progress) progress(static_cast<double>(f + 1) / frames.size());
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

  const cv::Mat k(intrinsics.camera_matrix);
  cv::Mat dist(intrinsics.distortion);
  if (intrinsics.fisheye) {
    // The corners as a pinhole camera with the same matrix would see them.
    const CameraModel camera(intrinsics, MountPose{});
    const std::vector<cv::Point2d> normalised = camera.undistort(image);
    for (size_t j = 0; j < image.size(); ++j)
      image[j] = {k.at<double>(0, 0) * normalised[j].x + k.at<double>(0, 2),
                  k.at<double>(1, 1) * normalised[j].y + k.at<double>(1, 2)};
    dist = cv::Mat();
  }
  PoseFit pose = fit_pose(object, image, k, dist);

  // Each tag against the mount the others give (one fit without it): a tag far off drags a
  // joint fit towards it and hides among the residuals. The worst tag that disagrees is left
  // out, while three tags remain to compare.
  auto points_of = [&](int id, bool of_tag) {
    std::vector<cv::Point3d> o;
    std::vector<cv::Point2d> i;
    for (size_t j = 0; j < object.size(); ++j) {
      if ((point_tag[j] == id) == of_tag) {
        o.push_back(object[j]);
        i.push_back(image[j]);
      }
    }
    return std::make_pair(o, i);
  };
  std::map<int, bool> excluded;
  for (;;) {
    std::vector<int> ids;
    for (const auto& [id, count] : seen)
      if (!excluded[id]) ids.push_back(id);
    if (ids.size() < 3) break;
    int worst = -1;
    double worst_px = 0.0;
    PoseFit worst_pose;
    for (int id : ids) {
      const auto [others_o, others_i] = points_of(id, false);
      const PoseFit without = fit_pose(others_o, others_i, k, dist);
      const auto [o, i] = points_of(id, true);
      const double off_px = rms_of(o, i, without, k, dist);
      const double others_px = rms_of(others_o, others_i, without, k, dist);
      if (off_px > std::max(1.0, 4.0 * others_px) && off_px > worst_px) {
        worst = id;
        worst_px = off_px;
        worst_pose = without;
      }
    }
    if (worst < 0) break;
    pose = worst_pose;
    excluded[worst] = true;
    auto [o, i] = points_of(worst, true);
    // How far off on the floor: the residual in pixels at the tag's distance from the camera.
    const MountPose m = mount_of(pose.r, pose.t);
    const double depth_m = (Eigen::Vector3d(o[0].x, o[0].y, 0.0) - m.xyz_m).norm();
    char text[300];
    std::snprintf(text, sizeof(text),
                  "tag %d disagrees with the others: its corners are %.1f px off (about %.0f mm on "
                  "the floor); its pose in TAGS.yaml is likely wrong",
                  worst, worst_px, 1e3 * worst_px * depth_m / k.at<double>(0, 0));
    std::string warning = text;
    // A tag lying turned: its corners fit when the order is turned by a quarter turn or more.
    for (int quarter = 1; quarter < 4; ++quarter) {
      std::vector<cv::Point3d> turned(o.size());
      for (size_t j = 0; j < o.size(); ++j) turned[j] = o[(j / 4) * 4 + (j % 4 + quarter) % 4];
      if (rms_of(turned, i, pose, k, dist) < 0.25 * worst_px) {
        warning += " (it lies turned by " + std::to_string(90 * quarter) +
                   " deg from its yaw_rad in TAGS.yaml)";
        break;
      }
    }
    result.warnings.push_back(warning + "; the mount is refitted without it");
    std::vector<cv::Point3d> kept_object;
    std::vector<cv::Point2d> kept_image;
    std::vector<int> kept_tag;
    for (size_t j = 0; j < object.size(); ++j) {
      if (excluded[point_tag[j]]) continue;
      kept_object.push_back(object[j]);
      kept_image.push_back(image[j]);
      kept_tag.push_back(point_tag[j]);
    }
    object = kept_object;
    image = kept_image;
    point_tag = kept_tag;  // `pose` is already the fit without it
  }
  for (const auto& [id, count] : seen) {
    TagResidual residual;
    residual.id = id;
    residual.excluded = excluded[id];
    if (!residual.excluded) {
      const auto [o, i] = points_of(id, true);
      residual.rms_px = rms_of(o, i, pose, k, dist);
    }
    result.tags.push_back(residual);
  }
  result.points = static_cast<int>(object.size());

  std::vector<cv::Point2d> projected;
  cv::Mat jacobian;
  cv::projectPoints(object, pose.r, pose.t, k, dist, projected, jacobian);
  double sum = 0.0;
  for (size_t j = 0; j < image.size(); ++j) sum += std::pow(cv::norm(projected[j] - image[j]), 2);
  result.rms_px = std::sqrt(sum / image.size());
  result.mount = mount_of(pose.r, pose.t);

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
    cv::Vec3d r = pose.r, t = pose.t;
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
