#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/pose2.h"
#include "control/path.h"
#include "perception/camera_file.h"

namespace agv::pipeline {

// One frame of a recorded dataset (a row of manifest.csv), with its ground truth and wheel
// odometry if recorded.
struct DatasetRow {
  int index = 0;
  double t_s = 0.0;
  std::string file;                             // relative to the dataset folder
  std::optional<Pose2> pose;                    // x_m, y_m, yaw_rad
  std::optional<control::TrackingError> truth;  // e_theta_rad, e_d_m
  std::optional<Pose2> odometry;                // odom_x_m, odom_y_m, odom_yaw_rad
  int line = 0;  // line number in manifest.csv, for messages (0: a bare folder)
};

// A recorded dataset (shared/DESIGN.md): frames/ (PNG or JPEG) listed by manifest.csv
// (index,t_s,file then optional x_m,y_m,yaw_rad,e_theta_rad,e_d_m and
// odom_x_m,odom_y_m,odom_yaw_rad) and camera.yaml; or a bare folder of images, in name order,
// timed by a frame rate, without ground truth.
struct Dataset {
  std::filesystem::path root;
  std::string manifest;  // path of manifest.csv ("" for a bare folder)
  std::vector<DatasetRow> rows;
  bool has_truth = false;
  bool has_odometry = false;
  perception::CameraFile camera;
  std::string camera_name;
};

// Opens and checks a dataset folder. `camera_path` overrides the dataset's camera.yaml (a bare
// folder needs one unless it holds camera.yaml). A folder without manifest.csv is a bare folder
// of images (PNG, JPEG, BMP, TIFF; in it or in its frames/), timed at `fps` frames per second,
// which must then be given. Throws InputError naming the file and row on: a path that does not
// exist or is not a folder, no manifest and no images (or no fps), a malformed row (wrong field
// count, non-numeric or non-finite value, unknown column), indices or times not increasing, a
// listed frame file missing (unless allow_missing_frames), no camera.
Dataset open_dataset(const std::string& path, const std::string& camera_path, double fps,
                     bool allow_missing_frames);

// True for names ending in a video extension (.avi, .mp4, .mkv, .mov, .webm).
bool looks_like_video(const std::string& path);

// The image files (PNG, JPEG, BMP, TIFF) directly in a folder, in name order; empty when none
// (or the folder cannot be read).
std::vector<std::filesystem::path> image_files_in(const std::filesystem::path& folder);

// Writes a dataset: frames/NNNNNN.png or .jpg, manifest.csv with the ground-truth and wheel
// odometry columns, and camera.yaml. Everything goes into `folder` (a temporary folder renamed at
// the end by its owner).
class DatasetWriter {
 public:
  DatasetWriter(const std::filesystem::path& folder, const perception::CameraFile& camera,
                const std::string& format, int jpeg_quality);
  void add(int index, double t_s, const cv::Mat& frame, const Pose2& pose,
           const control::TrackingError& truth, const Pose2& odometry);
  void finish();
  int frames() const { return frames_; }

 private:
  std::filesystem::path folder_;
  std::string format_;
  int jpeg_quality_;
  std::string manifest_;
  int frames_ = 0;
};

}  // namespace agv::pipeline
