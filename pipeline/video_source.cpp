#include "pipeline/video_source.h"

#include "common/input_error.h"
#include "pipeline/dataset_source.h"

namespace agv::pipeline {

VideoSource::VideoSource(const std::string& path, const perception::CameraIntrinsics& camera,
                         bool pass_bad_frames)
    : path_(path), camera_(camera), pass_bad_frames_(pass_bad_frames) {
  if (!video_.open(path, cv::CAP_ANY))
    throw InputError(path + ": cannot open the video (unknown format or corrupt)");
  const double fps = video_.get(cv::CAP_PROP_FPS);
  if (fps > 0.0 && fps < 10000.0) fps_ = fps;
  frame_count_ = static_cast<long>(video_.get(cv::CAP_PROP_FRAME_COUNT));
  read_ahead();
}

void VideoSource::read_ahead() {
  ahead_.reset();
  SourceFrame frame;
  frame.index = read_;
  frame.label = "video frame " + std::to_string(read_);
  if (!video_.read(frame.image)) {
    if (frame_count_ > 0 && static_cast<long>(read_) < frame_count_) {
      const std::string problem = "truncated: frame " + std::to_string(read_) + " of " +
                                  std::to_string(frame_count_) + " cannot be decoded";
      if (!pass_bad_frames_) throw InputError(path_ + ": " + problem);
      frame.problem = problem + " (" + std::to_string(frame_count_ - read_) + " frames missing)";
      frame.t_s = read_ / fps_;
      frame_count_ = static_cast<long>(read_);  // nothing follows
      ahead_ = frame;
    }
    return;
  }
  // The container's time of the frame; the frame rate's where it gives none.
  const double position_s = video_.get(cv::CAP_PROP_POS_MSEC) / 1e3;
  frame.t_s = (read_ == 0 || position_s > 0.0) ? position_s : read_ / fps_;
  if (read_ == 0) frame.t_s = 0.0;
  ++read_;
  if (const auto problem = usable_frame(&frame.image, camera_)) {
    if (!pass_bad_frames_) throw InputError(path_ + " " + frame.label + ": the frame " + *problem);
    frame.problem = *problem;
    frame.image.release();
  }
  ahead_ = std::move(frame);
}

std::optional<double> VideoSource::next_time_s() const {
  if (!ahead_) return std::nullopt;
  return ahead_->t_s;
}

std::optional<SourceFrame> VideoSource::next() {
  if (!ahead_) return std::nullopt;
  std::optional<SourceFrame> frame = std::move(ahead_);
  read_ahead();
  return frame;
}

void VideoSource::skip() { next(); }

}  // namespace agv::pipeline
