#pragma once

#include <atomic>
#include <functional>
#include <limits>

#include "perception/camera_model.h"
#include "perception/line_estimator.h"
#include "pipeline/camera_stage.h"
#include "pipeline/config/scenario.h"
#include "pipeline/frame_source.h"
#include "pipeline/run_result.h"

namespace agv::pipeline {

struct RecordedRunOptions {
  // Real time (agv track): the stages on their own threads on the wall clock, recorded frames
  // played at their own rate (late ones dropped), the controller every controller.ts_s at the
  // time it really runs. Otherwise (agv replay, track --as-fast-as-possible): lockstep on the
  // frames' clock, as fast as the computer goes.
  bool real_time = false;
  // When the source ends, `stop` is set (real time) or the duration is over, brake to a stop
  // within the limits: the last command is a stop (agv track).
  bool brake_at_end = false;
  double duration_s = std::numeric_limits<double>::infinity();  // of the source's time
  const std::atomic<bool>* stop = nullptr;                      // real time: Ctrl-C
  perception::LineEstimator::Options perception;
  FrameSink sink;                                  // every frame, with perception's details
  std::function<void(const TraceRow&)> on_period;  // every command as it is made
};

// Perception and the scenario's controller (and vehicle limits) on the frames of a recording or
// a live camera, through the same stages as a simulation, open loop: the commands go to
// on_period (a command stream, a vehicle), no plant moves.
RunResult run_on_source(FrameSource& source, const perception::CameraModel& camera,
                        const Scenario& scenario, const RecordedRunOptions& options,
                        const Progress& progress = {});

}  // namespace agv::pipeline
