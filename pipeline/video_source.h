#pragma once

#include <opencv2/videoio.hpp>

#include "perception/camera_file.h"
#include "pipeline/frame_source.h"

namespace agv::pipeline {

// The frames of a video file, timed by the container (its frame rate where it gives no time).
// Reads one frame ahead, so that the time of the next frame and the end are known in advance.
class VideoSource : public FrameSource {
 public:
  // Throws InputError when the file cannot be opened as a video. pass_bad_frames: a wrong-sized
  // frame, or frames missing from a truncated file, come back with their problem set instead.
  VideoSource(const std::string& path, const perception::CameraIntrinsics& camera,
              bool pass_bad_frames);

  std::optional<SourceFrame> next() override;
  void skip() override;
  std::optional<double> next_time_s() const override;
  double frame_period_s() const override { return 1.0 / fps_; }
  long frame_count() const override { return frame_count_ > 0 ? frame_count_ : -1; }
  std::string describe() const override { return path_; }

 private:
  void read_ahead();

  std::string path_;
  perception::CameraIntrinsics camera_;
  bool pass_bad_frames_;
  cv::VideoCapture video_;
  double fps_ = 30.0;
  long frame_count_ = 0;  // as the container says (not trusted: a file may be truncated)
  std::optional<SourceFrame> ahead_;
  std::uint64_t read_ = 0;
};

}  // namespace agv::pipeline
