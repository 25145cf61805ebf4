#include "pipeline/replay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "common/input_error.h"
#include "control/line_tracker.h"

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

// The frame as 8-bit BGR or grey, or the reason it cannot be used.
std::optional<std::string> usable(cv::Mat* image, const perception::CameraIntrinsics& camera) {
  if (image->empty()) return "cannot be read or decoded";
  if (image->depth() != CV_8U) return "is not 8 bits per channel (e.g. a 16-bit image)";
  if (image->channels() == 4) cv::cvtColor(*image, *image, cv::COLOR_BGRA2BGR);
  if (image->channels() != 1 && image->channels() != 3)
    return "has " + std::to_string(image->channels()) + " channels";
  if (image->cols != camera.width_px || image->rows != camera.height_px) {
    return "is " + std::to_string(image->cols) + "x" + std::to_string(image->rows) +
           ", the camera file says " + std::to_string(camera.width_px) + "x" +
           std::to_string(camera.height_px);
  }
  return std::nullopt;
}

double median_interval_s(const std::vector<DatasetRow>& rows) {
  std::vector<double> intervals;
  for (size_t i = 1; i < rows.size(); ++i) intervals.push_back(rows[i].t_s - rows[i - 1].t_s);
  if (intervals.empty()) return 0.1;
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  return intervals[intervals.size() / 2];
}

}  // namespace

ReplayResult run_replay(const Dataset& dataset, const ReplayOptions& options,
                        const ReplayVisitor& visitor, const Progress& progress) {
  const Clock::time_point start = Clock::now();
  const perception::CameraModel camera =
      perception::camera_model_of(dataset.camera, dataset.camera_name);
  perception::TrackingLineEstimator estimator(camera, options.perception);

  // Frames: from the manifest, or decoded from the video as it plays.
  cv::VideoCapture video;
  std::vector<DatasetRow> rows = dataset.rows;
  double fps = 0.0;
  int video_frames = 0;
  if (!dataset.video.empty()) {
    if (!video.open(dataset.video))
      throw InputError(dataset.video + ": cannot open the video (unknown format or corrupt)");
    fps = video.get(cv::CAP_PROP_FPS);
    if (!(fps > 0.0 && fps < 10000.0)) fps = 30.0;
    video_frames = static_cast<int>(video.get(cv::CAP_PROP_FRAME_COUNT));
  }

  ReplayResult result;
  result.period_s = dataset.video.empty() ? median_interval_s(rows) : 1.0 / fps;
  ControllerConfig controller = options.controller;
  controller.ts_s = result.period_s;
  control::LineTracker::Options tracker_options;
  tracker_options.ts_s = result.period_s;
  tracker_options.path_speed_m_s = options.path_speed_m_s;
  tracker_options.line_lost_hold_s = controller.line_lost_hold_s;
  tracker_options.latency_compensation = controller.latency_compensation;
  control::LineTracker tracker(make_controller(controller, VehicleConfig{}), options.limits,
                               tracker_options, BodyTwist{options.path_speed_m_s, 0.0, 0.0});
  result.controller_name = tracker.controller().name();

  perception::LineDetection detection;
  for (int i = 0;; ++i) {
    ReplayFrame frame;
    cv::Mat image;
    std::string where;
    if (dataset.video.empty()) {
      if (i >= static_cast<int>(rows.size())) break;
      const DatasetRow& row = rows[i];
      frame.index = row.index;
      frame.t_s = row.t_s;
      frame.source = row.file;
      frame.truth = row.truth;
      where = (dataset.root / row.file).string() + " (" + dataset.manifest + " line " +
              std::to_string(row.line) + ")";
      image = cv::imread((dataset.root / row.file).string(), cv::IMREAD_UNCHANGED);
    } else {
      if (!video.read(image)) {
        if (video_frames > 0 && i < video_frames) {
          const std::string problem = dataset.video + ": truncated: frame " + std::to_string(i) +
                                      " of " + std::to_string(video_frames) + " cannot be decoded";
          if (!options.skip_bad_frames) throw InputError(problem);
          ReplayFrame missing;
          missing.index = i;
          missing.t_s = i / fps;
          missing.source = "video frame " + std::to_string(i);
          missing.bad = true;
          missing.problem =
              "truncated video: " + std::to_string(video_frames - i) + " frames missing";
          result.frames.push_back(missing);
        }
        break;
      }
      frame.index = i;
      frame.t_s = i / fps;
      frame.source = "video frame " + std::to_string(i);
      where = dataset.video + " frame " + std::to_string(i);
    }
    if (const auto problem = usable(&image, dataset.camera.intrinsics)) {
      if (!options.skip_bad_frames) throw InputError(where + ": the frame " + *problem);
      frame.bad = true;
      frame.problem = *problem;
      estimator.reset();  // the next frame is not a continuation of the last good one
      // A bad frame carries no measurement: the controller acts as if none arrived.
      const control::TrackerOutput output = tracker.step(std::nullopt, frame.t_s);
      frame.command = output.command;
      frame.flags = output.flags;
      result.frames.push_back(frame);
      continue;
    }
    const Clock::time_point t0 = Clock::now();
    frame.measurement = estimator.measure(image, frame.t_s, &detection);
    frame.perceive_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const control::TrackerOutput output = tracker.step(frame.measurement, frame.t_s);
    frame.command = output.command;
    frame.flags = output.flags;
    result.frames.push_back(frame);
    if (visitor) visitor(result.frames.back(), image, detection);
    if (progress) {
      const double total =
          dataset.video.empty() ? static_cast<double>(rows.size()) : std::max(1, video_frames);
      progress(std::min(1.0, (i + 1) / total));
    }
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  result.perception_counts = estimator.counts();
  return result;
}

}  // namespace agv::pipeline
