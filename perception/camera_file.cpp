#include "perception/camera_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <set>
#include <sstream>

#include "common/input_error.h"

namespace agv::perception {
namespace {

// Keys this project reads, and keys OpenCV's calibration samples write that it ignores.
const std::set<std::string> kOwnKeys = {"image_width",
                                        "image_height",
                                        "camera_matrix",
                                        "distortion_coefficients",
                                        "mount_xyz_m",
                                        "mount_rpy_rad",
                                        "avg_reprojection_error",
                                        "calibration_time",
                                        "nr_of_frames",
                                        "mount_reprojection_error_px",
                                        "mount_views",
                                        "mount_calibration_time",
                                        "mount_calibration_method",
                                        "calibration_method",
                                        "tape_width_m",
                                        "tape_color_bgr"};
const std::set<std::string> kOpenCvSampleKeys = {"board_width",
                                                 "board_height",
                                                 "square_size",
                                                 "aspectRatio",
                                                 "fix_aspect_ratio",
                                                 "flags",
                                                 "per_view_reprojection_errors",
                                                 "extrinsic_parameters",
                                                 "image_points",
                                                 "grid_points",
                                                 "nframes",
                                                 "fisheye_model",
                                                 "board_grid_points",
                                                 "marker_size",
                                                 "dictionary"};

[[noreturn]] void fail(const std::string& source, const std::string& field,
                       const std::string& what) {
  throw InputError(source + ": field '" + field + "': " + what);
}

bool finite(const cv::Mat& m) { return cv::checkRange(m, true, nullptr, -1e300, 1e300); }

int read_int(const cv::FileNode& root, const std::string& key, const std::string& source) {
  const cv::FileNode node = root[key];
  if (node.empty()) fail(source, key, "missing");
  if (!node.isInt()) {
    if (node.isReal() && std::floor(node.real()) == node.real())
      return static_cast<int>(node.real());
    fail(source, key, "expected an integer");
  }
  return static_cast<int>(node);
}

cv::Mat read_matrix(const cv::FileNode& root, const std::string& key, const std::string& source) {
  const cv::FileNode node = root[key];
  if (node.empty()) fail(source, key, "missing");
  cv::Mat m;
  if (node.isSeq()) {
    std::vector<double> values;
    for (const cv::FileNode& item : node) {
      if (!item.isReal() && !item.isInt()) fail(source, key, "expected a sequence of numbers");
      values.push_back(item.real());
    }
    m = cv::Mat(values, true).reshape(1, 1);
  } else if (node.isMap()) {
    // The declared shape first: OpenCV allocates rows x cols before it reads the data, and a
    // camera file has no matrix larger than 3 x 3 or 1 x 14 (distortion).
    const cv::FileNode rows = node["rows"], cols = node["cols"];
    const auto in_range = [](const cv::FileNode& n) {
      return n.isInt() && static_cast<int>(n) >= 1 && static_cast<int>(n) <= 16;
    };
    if (!in_range(rows) || !in_range(cols) ||
        static_cast<int>(rows) * static_cast<int>(cols) > 16) {
      fail(source, key, "expected an opencv-matrix with rows and cols from 1 to 16");
    }
    try {
      node >> m;
    } catch (const cv::Exception&) {
      fail(source, key, "expected an opencv-matrix (rows, cols, dt, data)");
    }
    if (m.empty()) fail(source, key, "expected an opencv-matrix (rows, cols, dt, data)");
    m.convertTo(m, CV_64F);
  } else {
    fail(source, key, "expected a matrix or a sequence of numbers");
  }
  if (!finite(m)) fail(source, key, "contains a value that is not a finite number");
  return m;
}

Eigen::Vector3d read_vector3(const cv::FileNode& root, const std::string& key,
                             const std::string& source) {
  const cv::Mat m = read_matrix(root, key, source);
  if (m.total() != 3) fail(source, key, "expected 3 numbers, got " + std::to_string(m.total()));
  const cv::Mat flat = m.reshape(1, 1);
  return {flat.at<double>(0), flat.at<double>(1), flat.at<double>(2)};
}

std::string read_string(const cv::FileNode& root, const std::string& key) {
  const cv::FileNode node = root[key];
  return node.isString() ? static_cast<std::string>(node) : std::string();
}

double read_optional_real(const cv::FileNode& root, const std::string& key,
                          const std::string& source, double fallback) {
  const cv::FileNode node = root[key];
  if (node.empty()) return fallback;
  if (!node.isReal() && !node.isInt()) fail(source, key, "expected a number");
  const double value = node.real();
  if (!std::isfinite(value)) fail(source, key, "not a finite number");
  return value;
}

struct CalibrationKeys {
  const char* error;
  const char* views;
  const char* date;
  const char* method;
};

CalibrationInfo read_calibration_info(const cv::FileNode& root, const std::string& source,
                                      const CalibrationKeys& keys) {
  CalibrationInfo info;
  info.avg_reprojection_error_px = read_optional_real(root, keys.error, source, -1.0);
  info.views = static_cast<int>(read_optional_real(root, keys.views, source, 0.0));
  info.date = read_string(root, keys.date);
  info.method = read_string(root, keys.method);
  return info;
}

}  // namespace

std::string distortion_fold_problem(const CameraIntrinsics& intrinsics) {
  // The distorted radius must keep growing out to each image corner; where it turns back the
  // model folds the image onto itself and pixels there have no unique ray.
  if (intrinsics.distortion.empty()) return "";
  const cv::Matx33d& k = intrinsics.camera_matrix;
  const double fx = k(0, 0), fy = k(1, 1), cx = k(0, 2), cy = k(1, 2);
  const double w = intrinsics.width_px - 1.0, h = intrinsics.height_px - 1.0;
  const CameraModel camera(intrinsics, MountPose{});
  const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
  for (const cv::Point2d corner :
       {cv::Point2d(0, 0), cv::Point2d(w, 0), cv::Point2d(0, h), cv::Point2d(w, h)}) {
    const cv::Point2d direction((corner.x - cx) / fx, (corner.y - cy) / fy);
    const double corner_radius_px = std::hypot(corner.x - cx, corner.y - cy);
    // Rays out to 4x the pinhole radius of the corner; a fisheye sees rays beyond 90 deg too,
    // which no pinhole ray reaches: out to 85 deg for it.
    std::vector<cv::Point3f> ray;
    constexpr int kSamples = 400;
    const double max_scale =
        intrinsics.fisheye ? std::tan(85.0 * M_PI / 180.0) / std::max(1e-9, cv::norm(direction))
                           : 4.0;
    for (int i = 1; i <= kSamples; ++i) {
      const double scale = max_scale * i / kSamples;
      ray.emplace_back(static_cast<float>(direction.x * scale),
                       static_cast<float>(direction.y * scale), 1.0f);
    }
    const std::vector<cv::Point2d> projected = camera.project_camera_points(ray, zero, zero);
    double previous_radius_px = 0.0;
    bool reached_corner = false;
    for (const cv::Point2d& p : projected) {
      const double radius_px = std::hypot(p.x - cx, p.y - cy);
      if (!(radius_px > previous_radius_px)) break;  // the mapping turned back: it folds
      if (radius_px >= corner_radius_px) {
        reached_corner = true;
        break;
      }
      previous_radius_px = radius_px;
    }
    if (!reached_corner) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "the distortion folds the image (the projection turns back %.0f px from the "
                    "centre, before the image corner at %.0f px)",
                    previous_radius_px, corner_radius_px);
      return text;
    }
  }
  return "";
}

namespace {

void check_distortion_does_not_fold(const CameraIntrinsics& intrinsics, const std::string& source) {
  const std::string problem = distortion_fold_problem(intrinsics);
  if (!problem.empty())
    fail(source, "distortion_coefficients",
         problem + "; these coefficients cannot describe this camera");
}

}  // namespace

void validate_intrinsics(const CameraIntrinsics& intrinsics, const std::string& source) {
  if (intrinsics.width_px <= 0 || intrinsics.width_px > 20000) {
    fail(source, "image_width", "must be between 1 and 20000 pixels");
  }
  if (intrinsics.height_px <= 0 || intrinsics.height_px > 20000) {
    fail(source, "image_height", "must be between 1 and 20000 pixels");
  }
  const cv::Matx33d& k = intrinsics.camera_matrix;
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(k.val[i])) fail(source, "camera_matrix", "contains a non-finite value");
  }
  if (!(k(0, 0) > 0.0) || !(k(1, 1) > 0.0)) {
    fail(source, "camera_matrix",
         "focal lengths fx and fy must be positive (matrix does not invert)");
  }
  if (k(1, 0) != 0.0 || k(2, 0) != 0.0 || k(2, 1) != 0.0 || k(2, 2) != 1.0) {
    fail(source, "camera_matrix", "expected [[fx, s, cx], [0, fy, cy], [0, 0, 1]]");
  }
  if (k(0, 2) < -intrinsics.width_px || k(0, 2) > 2.0 * intrinsics.width_px ||
      k(1, 2) < -intrinsics.height_px || k(1, 2) > 2.0 * intrinsics.height_px) {
    fail(source, "camera_matrix", "principal point lies far outside the image");
  }
  const size_t n = intrinsics.distortion.size();
  if (intrinsics.fisheye && n != 0 && n != 4)
    fail(source, "distortion_coefficients",
         "OpenCV's fisheye model has 4 coefficients (k1 k2 k3 k4), got " + std::to_string(n));
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    fail(source, "distortion_coefficients",
         "expected 4, 5, 8, 12 or 14 coefficients (OpenCV's model), got " + std::to_string(n));
  }
  for (double d : intrinsics.distortion) {
    if (!std::isfinite(d)) fail(source, "distortion_coefficients", "contains a non-finite value");
  }
  check_distortion_does_not_fold(intrinsics, source);
}

void validate_mount(const MountPose& mount, const std::string& source) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(mount.xyz_m[i])) fail(source, "mount_xyz_m", "contains a non-finite value");
    if (!std::isfinite(mount.rpy_rad[i])) {
      fail(source, "mount_rpy_rad", "contains a non-finite value");
    }
  }
  if (!(mount.xyz_m.z() > 0.0)) {
    fail(source, "mount_xyz_m", "the camera must be above the floor (z > 0)");
  }
  if (!(mount.rotation().col(2).z() < -0.1)) {
    fail(source, "mount_rpy_rad",
         "the optical axis does not point down at the floor (" + mount.describe() + ")");
  }
}

CameraFile parse_camera_text(const std::string& yaml_text, const std::string& source) {
  cv::FileStorage storage;
  try {
    storage.open(yaml_text,
                 cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    throw InputError(source + ": not a readable OpenCV YAML file (" + e.err + ")");
  }
  if (!storage.isOpened()) throw InputError(source + ": not a readable OpenCV YAML file");
  const cv::FileNode root = storage.root();
  if (!root.isMap()) throw InputError(source + ": expected a YAML mapping at the top level");
  for (const std::string& key : root.keys()) {
    if (!kOwnKeys.count(key) && !kOpenCvSampleKeys.count(key)) {
      fail(source, key,
           "unknown key (camera files hold image_width, image_height, "
           "camera_matrix, distortion_coefficients, mount_xyz_m, mount_rpy_rad)");
    }
  }
  bool fisheye = false;
  if (!root["fisheye_model"].empty()) {
    if (!root["fisheye_model"].isInt() || (static_cast<int>(root["fisheye_model"]) != 0 &&
                                           static_cast<int>(root["fisheye_model"]) != 1))
      fail(source, "fisheye_model", "expected 0 (standard model) or 1 (OpenCV's fisheye model)");
    fisheye = static_cast<int>(root["fisheye_model"]) == 1;
  }

  CameraFile camera;
  CameraIntrinsics& intrinsics = camera.intrinsics;
  intrinsics.width_px = read_int(root, "image_width", source);
  intrinsics.height_px = read_int(root, "image_height", source);
  const cv::Mat k = read_matrix(root, "camera_matrix", source);
  if (k.total() != 9) fail(source, "camera_matrix", "expected a 3x3 matrix");
  intrinsics.camera_matrix = cv::Matx33d(k.reshape(1, 3));
  const cv::Mat d = read_matrix(root, "distortion_coefficients", source);
  intrinsics.distortion.assign(d.begin<double>(), d.end<double>());
  intrinsics.fisheye = fisheye;
  validate_intrinsics(intrinsics, source);

  const bool has_xyz = !root["mount_xyz_m"].empty();
  const bool has_rpy = !root["mount_rpy_rad"].empty();
  if (has_xyz != has_rpy) {
    fail(source, has_xyz ? "mount_rpy_rad" : "mount_xyz_m",
         "missing (a mount needs both mount_xyz_m and mount_rpy_rad)");
  }
  if (has_xyz) {
    MountPose mount;
    mount.xyz_m = read_vector3(root, "mount_xyz_m", source);
    mount.rpy_rad = read_vector3(root, "mount_rpy_rad", source);
    validate_mount(mount, source);
    camera.mount = mount;
  }
  if (!root["tape_width_m"].empty()) {
    const double width = read_optional_real(root, "tape_width_m", source, 0.0);
    if (!(width > 0.001 && width < 0.5))
      fail(source, "tape_width_m", "expected a width between 0.001 and 0.5 m");
    camera.tape_width_m = width;
  }
  if (!root["tape_color_bgr"].empty()) {
    const Eigen::Vector3d bgr = read_vector3(root, "tape_color_bgr", source);
    if (bgr.minCoeff() < 0.0 || bgr.maxCoeff() > 255.0)
      fail(source, "tape_color_bgr", "expected values 0-255");
    camera.tape_color_bgr = cv::Vec3d(bgr.x(), bgr.y(), bgr.z());
  }
  camera.intrinsics_calibration = read_calibration_info(
      root, source,
      {"avg_reprojection_error", "nr_of_frames", "calibration_time", "calibration_method"});
  camera.mount_calibration =
      read_calibration_info(root, source,
                            {"mount_reprojection_error_px", "mount_views", "mount_calibration_time",
                             "mount_calibration_method"});
  return camera;
}

CameraFile load_camera_file(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw InputError(path + ": camera file not found (or not a regular file)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the camera file");
  std::stringstream text;
  text << in.rdbuf();
  if (text.str().find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(path + ": the camera file is empty");
  }
  return parse_camera_text(text.str(), path);
}

std::string camera_file_text(const CameraFile& camera) {
  cv::FileStorage storage(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  const CalibrationInfo& ic = camera.intrinsics_calibration;
  if (!ic.date.empty()) storage << "calibration_time" << ic.date;
  if (!ic.method.empty()) storage << "calibration_method" << ic.method;
  if (ic.views > 0) storage << "nr_of_frames" << ic.views;
  storage << "image_width" << camera.intrinsics.width_px;
  storage << "image_height" << camera.intrinsics.height_px;
  storage << "camera_matrix" << cv::Mat(camera.intrinsics.camera_matrix);
  std::vector<double> distortion = camera.intrinsics.distortion;
  if (distortion.empty()) distortion.assign(camera.intrinsics.fisheye ? 4 : 5, 0.0);
  storage << "distortion_coefficients" << cv::Mat(distortion, true);
  if (camera.intrinsics.fisheye) storage << "fisheye_model" << 1;
  if (ic.avg_reprojection_error_px >= 0.0) {
    storage << "avg_reprojection_error" << ic.avg_reprojection_error_px;
  }
  if (camera.mount) {
    const MountPose& m = *camera.mount;
    storage << "mount_xyz_m" << cv::Mat(1, 3, CV_64F, const_cast<double*>(m.xyz_m.data())).clone();
    storage << "mount_rpy_rad"
            << cv::Mat(1, 3, CV_64F, const_cast<double*>(m.rpy_rad.data())).clone();
    const CalibrationInfo& mc = camera.mount_calibration;
    if (mc.avg_reprojection_error_px >= 0.0) {
      storage << "mount_reprojection_error_px" << mc.avg_reprojection_error_px;
    }
    if (mc.views > 0) storage << "mount_views" << mc.views;
    if (!mc.date.empty()) storage << "mount_calibration_time" << mc.date;
    if (!mc.method.empty()) storage << "mount_calibration_method" << mc.method;
  }
  if (camera.tape_width_m) storage << "tape_width_m" << *camera.tape_width_m;
  if (camera.tape_color_bgr) {
    const cv::Vec3d& bgr = *camera.tape_color_bgr;
    storage << "tape_color_bgr" << std::vector<double>{bgr[0], bgr[1], bgr[2]};
  }
  return storage.releaseAndGetString();
}

void save_camera_file(const std::string& path, const CameraFile& camera) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write the camera file");
    out << camera_file_text(camera);
    if (!out) throw InputError(path + ": writing the camera file failed");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error)
    throw InputError(path + ": cannot move the new camera file into place: " + error.message());
}

CameraModel camera_model_of(const CameraFile& camera, const std::string& source) {
  if (!camera.mount) {
    throw InputError(source +
                     ": field 'mount_xyz_m': missing; this file holds intrinsics only "
                     "(run 'agv calibrate mount' to add the camera's mount pose)");
  }
  return CameraModel(camera.intrinsics, *camera.mount);
}

}  // namespace agv::perception
