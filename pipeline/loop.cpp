#include "pipeline/loop.h"

namespace agv::pipeline {

void collect_results(const Loop& loop, RunResult* result) {
  result->controller_name = loop.control.controller_name();
  result->frames = loop.camera.records();
  result->queue = loop.queue.stats();
  result->measurements_superseded = loop.control.superseded();
  result->frames_dropped = loop.camera.frames_dropped();
  result->perception_counts = loop.camera.perceiver().counts();
  result->odometry_source = loop.camera.perceiver().odometry_source();
  for (const FrameRecord& frame : result->frames) {
    result->total_times.source_s += frame.source_s;
    result->total_times.perceive_s += frame.perceive_s;
  }
  result->total_times.control_s = loop.control.compute_s();
}

}  // namespace agv::pipeline
