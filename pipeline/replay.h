#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/body_twist.h"
#include "common/line_measurement.h"
#include "control/vehicle_limits.h"
#include "perception/tracking_line_estimator.h"
#include "pipeline/closed_loop.h"
#include "pipeline/config/scenario.h"
#include "pipeline/dataset.h"

namespace agv::pipeline {

struct ReplayOptions {
  bool skip_bad_frames = false;  // count bad frames and go on, instead of stopping
  perception::LineEstimator::Options perception;
  ControllerConfig controller;  // ts_s is taken from the frames' timing
  double path_speed_m_s = 0.3;
  control::VehicleLimits limits;
};

// One frame as replay saw it.
struct ReplayFrame {
  int index = 0;
  double t_s = 0.0;
  std::string source;  // file name, or "video frame N"
  bool bad = false;    // could not be used (reason in `problem`)
  std::string problem;
  LineMeasurement measurement;
  std::optional<control::TrackingError> truth;
  BodyTwist command;  // what the controller would have commanded
  std::uint32_t flags = 0;
  double perceive_ms = 0.0;
};

struct ReplayResult {
  std::vector<ReplayFrame> frames;
  double period_s = 0.1;  // control period used (median frame interval)
  std::string controller_name;
  double wall_s = 0.0;
  perception::TrackingLineEstimator::Counts perception_counts;  // tracked vs searched frames
};

// Called for every good frame with what perception saw, e.g. to write an annotated video.
using ReplayVisitor = std::function<void(const ReplayFrame& frame, const cv::Mat& image,
                                         const perception::LineDetection& detection)>;

// Runs perception and the controller (open loop: the commands it would have given) over the
// frames of a dataset or video, in time order. A frame that cannot be read, is of the wrong size
// or of an unusable type throws InputError naming the file and row, or with skip_bad_frames is
// marked bad and counted.
ReplayResult run_replay(const Dataset& dataset, const ReplayOptions& options,
                        const ReplayVisitor& visitor = {}, const Progress& progress = {});

}  // namespace agv::pipeline
