#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "control/path.h"

namespace agv::pipeline {

// One frame as a source hands it to the loop: the picture, when it was taken and, where the
// source knows them, the true pose and errors and the vehicle's wheel odometry (DESIGN.md,
// "Frame sources").
struct SourceFrame {
  std::uint64_t index = 0;
  double t_s = 0.0;     // capture time on the source's clock, seconds
  cv::Mat image;        // 8-bit BGR or grey, the camera's size; empty for a source of poses
  std::string label;    // for messages and annotations: "frames/000012.png", "video frame 12"
  std::string problem;  // why the frame cannot be used (unreadable, wrong size); empty: usable
  std::optional<Pose2> pose;  // the vehicle's true pose (simulation, a dataset's ground truth)
  BodyTwist twist;            // simulation: the vehicle's twist at t_s
  std::optional<control::TrackingError> truth;
  std::optional<Pose2> odometry;  // wheel odometry (any origin: only changes mean anything)
};

// Where frames come from: the renderer, a dataset, a bare image folder, a video file or a live
// camera. Frames come in time order. Not thread-safe except interrupt().
class FrameSource {
 public:
  using Clock = std::chrono::steady_clock;
  virtual ~FrameSource() = default;

  // Starts the source's clock at `origin` (a live source stamps frames with the seconds since);
  // called once, before the first next().
  virtual void start(Clock::time_point origin) { (void)origin; }
  // The next frame, or nullopt at the end (or after interrupt()). Bad input throws InputError,
  // unless the source was told to pass bad frames on: then the frame has `problem` set.
  virtual std::optional<SourceFrame> next() = 0;
  // Passes over the next frame without decoding it (a real-time loop that has fallen behind).
  virtual void skip() { next(); }
  // When the next frame was (or will be) taken, if known before it is read: recorded frames
  // and the renderer know, a live camera does not (nullopt), nor does a source at its end.
  virtual std::optional<double> next_time_s() const = 0;
  // Wakes a next() waiting for a live frame and ends the source. Thread-safe.
  virtual void interrupt() {}
  // True for a camera that delivers frames as they happen (they cannot be waited for or
  // replayed at another speed).
  virtual bool live() const { return false; }
  // Frames the source had to discard because nobody took them in time (live sources).
  virtual std::uint64_t frames_dropped() const { return 0; }
  // The time between frames, when the source knows it (0 otherwise).
  virtual double frame_period_s() const = 0;
  // How many frames there are, when known in advance (-1 otherwise).
  virtual long frame_count() const { return -1; }
  virtual std::string describe() const = 0;
};

}  // namespace agv::pipeline
