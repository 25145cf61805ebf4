#pragma once

#include <optional>
#include <string>

#include "perception/camera_model.h"

namespace agv::perception {

// How a camera file's numbers were obtained (written by the calibration tools, shown to users).
struct CalibrationInfo {
  double avg_reprojection_error_px = -1.0;  // < 0: unknown
  int views = 0;
  std::string date;
  std::string method;
};

// A camera calibration file: OpenCV FileStorage YAML in the layout of OpenCV's calibration
// sample (image_width, image_height, camera_matrix, distortion_coefficients) plus the mount pose
// T_VC (mount_xyz_m, mount_rpy_rad) and how it was obtained. A file from OpenCV's sample has no
// mount; it loads as intrinsics only.
struct CameraFile {
  CameraIntrinsics intrinsics;
  std::optional<MountPose> mount;
  CalibrationInfo intrinsics_calibration;
  CalibrationInfo mount_calibration;
  // What this camera is used to look at, as hints for perception (optional keys
  // tape_width_m and tape_color_bgr).
  std::optional<double> tape_width_m;
  std::optional<cv::Vec3d> tape_color_bgr;
};

// Reads and checks a camera file. Throws InputError naming the file and the field on anything
// missing, malformed, non-finite, out of range, or on a calibration that cannot be used
// (a camera matrix that does not invert, distortion that folds the image, a mount that does not
// look at the floor).
CameraFile load_camera_file(const std::string& path);
// The same from YAML text; `source_name` is the name used in messages.
CameraFile parse_camera_text(const std::string& yaml_text, const std::string& source_name);

// Writes the file (to a temporary name, renamed at the end). Throws InputError when it cannot.
void save_camera_file(const std::string& path, const CameraFile& camera);
std::string camera_file_text(const CameraFile& camera);

// Checks of the numbers alone; throw InputError with `source_name` in the message.
void validate_intrinsics(const CameraIntrinsics& intrinsics, const std::string& source_name);
void validate_mount(const MountPose& mount, const std::string& source_name);

// Why the distortion folds the image (the projection turns back before an image corner), or ""
// when it does not.
std::string distortion_fold_problem(const CameraIntrinsics& intrinsics);

// The camera model of a file, which must have a mount.
CameraModel camera_model_of(const CameraFile& camera, const std::string& source_name);

}  // namespace agv::perception
