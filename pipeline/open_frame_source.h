#pragma once

#include <memory>
#include <string>

#include "perception/camera_file.h"
#include "pipeline/frame_source.h"

namespace agv::pipeline {

struct OpenedSource {
  std::unique_ptr<FrameSource> source;
  perception::CameraFile camera;  // the calibration its frames are measured with
  std::string camera_name;
  std::string kind;  // "dataset", "image folder", "video file", "V4L2 device", ...
  bool has_truth = false;
};

// Opens what `spec` names (shared/DESIGN.md, "Frame sources"): a dataset folder (manifest.csv,
// frames/, camera.yaml), a bare folder of images (timed at `fps`), a video file (.avi, .mp4,
// .mkv, .mov, .webm), or a live source: a V4L2 device ("/dev/video0", "0"), a GStreamer pipeline
// (a string with '!'), a network stream URL ("rtsp://..."). `camera_path` is the calibration;
// all but a dataset holding camera.yaml need one. pass_bad_frames: unreadable or wrong-sized
// recorded frames come back marked bad instead of stopping with InputError.
OpenedSource open_frame_source(const std::string& spec, const std::string& camera_path, double fps,
                               bool pass_bad_frames);

}  // namespace agv::pipeline
