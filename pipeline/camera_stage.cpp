#include "pipeline/camera_stage.h"

#include <Eigen/Core>
#include <cmath>

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

}  // namespace

CameraStage::CameraStage(FrameSource& source, Perceiver& perceiver,
                         BoundedQueue<StampedMeasurement>& queue, Options options, FrameSink sink)
    : source_(source),
      perceiver_(perceiver),
      queue_(queue),
      options_(std::move(options)),
      sink_(std::move(sink)) {}

void CameraStage::drop() {
  source_.skip();
  ++dropped_;
}

bool CameraStage::step() {
  const Clock::time_point t0 = Clock::now();
  std::optional<SourceFrame> frame = source_.next();
  if (!frame) return false;
  FrameRecord record;
  record.index = frame->index;
  record.stamp_s = frame->t_s;
  record.label = frame->label;
  record.truth = frame->truth;
  const Clock::time_point t1 = Clock::now();
  record.source_s = seconds_between(t0, t1);
  if (!frame->problem.empty()) {
    record.bad = true;
    record.problem = frame->problem;
    perceiver_.reset();  // the next frame does not continue this one
    records_.push_back(record);
    if (sink_) sink_(record, *frame, nullptr);
    return true;
  }
  if (!frame->image.empty()) {
    apply_frame_faults(options_.faults, frame->t_s, frame->index, &frame->image);
  }
  perception::LineDetection detection;
  record.measurement = perceiver_.measure(*frame, &detection);
  record.perceive_s = seconds_between(t1, Clock::now());
  if (!record.measurement.line_found) record.no_line_reason = detection.rejected_because;
  if (detection.junction) {
    // The ways out: every branch but those pointing back at the vehicle (the incoming one, and
    // pieces of the tapes behind the junction).
    const Eigen::Vector2d towards = detection.junction->point_m.normalized();
    for (const perception::Branch& branch : detection.junction->branches) {
      const Eigen::Vector2d way(std::cos(branch.heading_rad), std::sin(branch.heading_rad));
      if (way.dot(towards) > -0.5) record.legs_rad.push_back(branch.heading_rad);
    }
  }
  if (record.measurement.line_found) record.chosen_leg_rad = detection.branch_heading_rad;
  queue_.push({record.measurement, record.index, frame->t_s + options_.latency_s},
              options_.push_timeout);
  records_.push_back(record);
  if (sink_) sink_(records_.back(), *frame, frame->image.empty() ? nullptr : &detection);
  return true;
}

}  // namespace agv::pipeline
