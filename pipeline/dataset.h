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

// One frame of a recorded dataset (a row of manifest.csv), with its ground truth if recorded.
struct DatasetRow {
  int index = 0;
  double t_s = 0.0;
  std::string file;                             // relative to the dataset folder; empty for video
  std::optional<Pose2> pose;                    // x_m, y_m, yaw_rad
  std::optional<control::TrackingError> truth;  // e_theta_rad, e_d_m
  int line = 0;                                 // line number in manifest.csv, for messages
};

// A recorded dataset (shared/DESIGN.md): frames/ (PNG or JPEG) listed by manifest.csv
// (index,t_s,file then optional x_m,y_m,yaw_rad,e_theta_rad,e_d_m) and camera.yaml; or a
// single video file, whose frames are timed by its frame rate.
struct Dataset {
  std::filesystem::path root;
  std::string manifest;  // path of manifest.csv ("" for a video)
  std::vector<DatasetRow> rows;
  bool has_truth = false;
  std::string video;  // path of the video file, if frames come from one
  perception::CameraFile camera;
  std::string camera_name;
};

// Opens and checks a dataset folder or a video file. `camera_path` overrides the dataset's
// camera.yaml (a video needs one). Throws InputError naming the file and row on: a path that
// does not exist or is neither a folder nor a video, no manifest, a malformed row (wrong field
// count, non-numeric or non-finite value, unknown column), indices or times not increasing, a
// listed frame file missing (unless allow_missing_frames), no camera.
Dataset open_dataset(const std::string& path, const std::string& camera_path, double video_fps,
                     bool allow_missing_frames);

// True for names ending in a video extension (.avi, .mp4, .mkv, .mov).
bool looks_like_video(const std::string& path);

// Writes a dataset: frames/NNNNNN.png or .jpg, manifest.csv with the ground-truth columns, and
// camera.yaml. Everything goes into `folder` (a temporary folder renamed at the end by its owner).
class DatasetWriter {
 public:
  DatasetWriter(const std::filesystem::path& folder, const perception::CameraFile& camera,
                const std::string& format, int jpeg_quality);
  void add(int index, double t_s, const cv::Mat& frame, const Pose2& pose,
           const control::TrackingError& truth);
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
