#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include <opencv2/videoio.hpp>

#include "perception/camera_file.h"
#include "pipeline/frame_source.h"

namespace agv::pipeline {

// A camera that delivers frames as they happen, through cv::VideoCapture: a V4L2 device
// ("/dev/video0" or an index "0"), a GStreamer pipeline ending in appsink ("videotestsrc !
// videoconvert ! appsink"), or a network stream URL ("rtsp://...", "http://..."). A grabber
// thread reads frames as fast as the camera gives them and keeps only the newest, stamped on
// arrival; a frame replaced before anyone took it is dropped and counted, so that perception
// always works on the newest frame and never on a backlog.
class LiveSource : public FrameSource {
 public:
  // Opens the camera (throws InputError naming `spec` when it cannot). Frames of another size
  // than the camera file's stop the source with an InputError from next().
  LiveSource(const std::string& spec, const perception::CameraIntrinsics& camera);
  ~LiveSource() override;

  void start(Clock::time_point origin) override;
  std::optional<SourceFrame> next() override;  // waits for a frame newer than the last one
  std::optional<double> next_time_s() const override { return std::nullopt; }
  void interrupt() override;
  bool live() const override { return true; }
  std::uint64_t frames_dropped() const override;
  double frame_period_s() const override { return frame_period_s_; }
  std::string describe() const override { return spec_; }

  // What kind of source a spec names (for messages and tests).
  static std::string kind_of(const std::string& spec);

 private:
  // Shared with the grabber thread, which may outlive the source when a driver blocks.
  struct Shared {
    std::mutex mutex;
    std::condition_variable changed;
    std::optional<SourceFrame> newest;
    std::string error;  // the grabber's InputError message, passed on by next()
    bool ended = false, stopping = false, grabber_done = false;
    std::uint64_t grabbed = 0, dropped = 0;
  };
  static void grab(std::shared_ptr<Shared> shared, std::shared_ptr<cv::VideoCapture> capture,
                   perception::CameraIntrinsics camera, std::string spec, Clock::time_point origin);

  std::string spec_;
  perception::CameraIntrinsics camera_;
  double frame_period_s_ = 0.0;
  std::shared_ptr<cv::VideoCapture> capture_;
  std::shared_ptr<Shared> shared_;
  std::thread grabber_;
};

}  // namespace agv::pipeline
