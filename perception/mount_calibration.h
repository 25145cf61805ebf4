#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "perception/apriltag_detector.h"
#include "perception/camera_model.h"

namespace agv::perception {

// An AprilTag lying on the floor at a known pose in the vehicle frame V (TAGS.yaml): centre
// (x_m, y_m), its x axis at yaw_rad, size_m as AprilTag measures it.
struct FloorTagPose {
  int id = 0;
  double size_m = 0.1;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
};

// The tag's four corners in V (z = 0), in the order the detector reports them. Seen from above
// (z up), the tag's x axis points right and its y axis up, as it is printed.
std::array<Eigen::Vector3d, 4> tag_corners_in_vehicle(const FloorTagPose& tag);

// The tags of a mount calibration (TAGS.yaml, read by pipeline::load_floor_tags_file).
struct FloorTagsFile {
  std::string family = "tag36h11";
  std::vector<FloorTagPose> tags;
};

// How well one tag's corners agree with the fitted mount.
struct TagResidual {
  int id = 0;
  double rms_px = 0.0;
  bool excluded = false;  // disagreed with the others: the mount was refitted without it
};

struct MountCalibration {
  MountPose mount;
  std::vector<TagResidual> tags;  // by id
  double rms_px = 0.0;            // reprojection RMS of all tag corners
  int frames_used = 0, tags_seen = 0, points = 0;
  // Standard deviations of x, y, z (m) and roll, pitch, yaw (rad) of the mount, from the
  // Jacobian of the reprojection at the solution and the residual RMS.
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<std::string> warnings;
};

// The camera's mount from tags on the floor at known poses: one joint PnP over every corner of
// every known tag in every frame (the vehicle does not move between frames), started from the
// single-tag IPPE solution with the camera above the floor and refined by Levenberg-Marquardt
// over all points (a per-tag solution alone can flip for a camera looking down). A tag whose
// corners disagree with the others (RMS above max(1 px, 4x the median tag's): its pose in
// TAGS.yaml is off, or it lies turned) is named in a warning, with how far off it is and, when
// turning it by 90, 180 or 270 deg fits, by how much it is turned, and the mount is refitted
// without it (while two tags remain). A fisheye camera's corners are undistorted first. Throws
// InputError when fewer than 4 corners (one tag) are seen in all frames, naming what was
// searched. `progress` (optional) is told the fraction of the frames searched for tags after
// each one.
MountCalibration calibrate_mount(const CameraIntrinsics& intrinsics,
                                 const std::vector<cv::Mat>& frames,
                                 const std::vector<std::string>& frame_names,
                                 const FloorTagsFile& tags,
                                 const std::function<void(double)>& progress = nullptr);

}  // namespace agv::perception
