#include "pipeline/rendered_source.h"

#include <cmath>

namespace agv::pipeline {

RenderedSource::RenderedSource(std::unique_ptr<FrameRenderer> renderer,
                               const SimulatedVehicle& vehicle, PathTruth truth,
                               WheelOdometry odometry, double frame_period_s, double end_s)
    : renderer_(std::move(renderer)),
      vehicle_(vehicle),
      truth_(std::move(truth)),
      odometry_(std::move(odometry)),
      frame_period_s_(frame_period_s),
      end_s_(end_s) {}

std::optional<double> RenderedSource::next_time_s() const {
  const double t_s = next_index_ * frame_period_s_;
  if (t_s > end_s_ + 1e-9) return std::nullopt;
  return t_s;
}

long RenderedSource::frame_count() const {
  return static_cast<long>(std::floor(end_s_ / frame_period_s_ + 1e-9)) + 1;
}

std::optional<SourceFrame> RenderedSource::next() {
  const std::optional<double> t_s = next_time_s();
  if (!t_s) return std::nullopt;
  SourceFrame frame;
  frame.index = next_index_++;
  frame.t_s = *t_s;
  frame.label = "frame " + std::to_string(frame.index);
  const SimulatedVehicle::State state = vehicle_.state_at(*t_s);
  frame.pose = state.pose;
  frame.twist = state.twist;
  frame.truth = truth_.errors(state.pose);
  frame.odometry = odometry_.update(state.pose);
  if (renderer_) {
    // Drawn into one buffer kept between frames: the camera stage is done with a frame before
    // it asks for the next.
    renderer_->render_into(state.pose, state.twist, frame.index, &image_);
    frame.image = image_;
  }
  return frame;
}

}  // namespace agv::pipeline
