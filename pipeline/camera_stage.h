#pragma once

#include <chrono>
#include <functional>
#include <vector>

#include "pipeline/bounded_queue.h"
#include "pipeline/frame_source.h"
#include "pipeline/perceiver.h"
#include "pipeline/run_result.h"
#include "pipeline/sim/frame_faults.h"

namespace agv::pipeline {

// Receives every frame the camera stage took, with what became of it and what perception saw in
// it (null for a bad frame or a source of poses): a dataset recorder, an annotated video.
using FrameSink = std::function<void(const FrameRecord& record, const SourceFrame& frame,
                                     const perception::LineDetection* detection)>;

// The camera half of the loop: frame source -> frame faults -> perception -> a stamped
// measurement in the queue to the controller. Written once; the lockstep and threaded loops
// only decide when step() runs.
class CameraStage {
 public:
  struct Options {
    std::vector<FrameFault> faults;  // frames spoiled on purpose (line-loss tests)
    double latency_s = 0.0;          // transport latency: a measurement is usable this long
                                     //   after its frame was taken
    std::chrono::nanoseconds push_timeout{0};  // how long a push may wait for room (kBlock)
  };

  CameraStage(FrameSource& source, Perceiver& perceiver, BoundedQueue<StampedMeasurement>& queue,
              Options options, FrameSink sink = {});

  // Takes the next frame, spoils it as the faults say, measures it and queues the measurement.
  // A bad frame (one the source passes on with its problem) is recorded and sends nothing.
  // False at the end of the source.
  bool step();
  // Passes over the next frame unread (a real-time loop that has fallen behind); counted.
  void drop();

  FrameSource& source() { return source_; }
  const std::vector<FrameRecord>& records() const { return records_; }
  std::uint64_t frames_dropped() const { return dropped_ + source_.frames_dropped(); }
  const Perceiver& perceiver() const { return perceiver_; }

 private:
  FrameSource& source_;
  Perceiver& perceiver_;
  BoundedQueue<StampedMeasurement>& queue_;
  Options options_;
  FrameSink sink_;
  std::vector<FrameRecord> records_;
  std::uint64_t dropped_ = 0;
};

}  // namespace agv::pipeline
