#pragma once

#include <memory>

#include "pipeline/frame_source.h"
#include "pipeline/sim/frame_renderer.h"
#include "pipeline/sim/path_truth.h"
#include "pipeline/sim/simulated_vehicle.h"
#include "pipeline/sim/wheel_odometry.h"

namespace agv::pipeline {

// The frames a camera on a simulated vehicle takes: one every frame_period_s from 0 to end_s,
// drawn by the renderer at the pose the vehicle has at that moment, with the true errors
// against the path. Without a renderer (a run whose controller takes the pose, not images) the
// frames carry the pose alone.
class RenderedSource : public FrameSource {
 public:
  RenderedSource(std::unique_ptr<FrameRenderer> renderer, const SimulatedVehicle& vehicle,
                 PathTruth truth, WheelOdometry odometry, double frame_period_s, double end_s);

  std::optional<SourceFrame> next() override;
  std::optional<double> next_time_s() const override;
  double frame_period_s() const override { return frame_period_s_; }
  long frame_count() const override;
  std::string describe() const override { return "renderer"; }

 private:
  std::unique_ptr<FrameRenderer> renderer_;
  const SimulatedVehicle& vehicle_;
  PathTruth truth_;
  WheelOdometry odometry_;
  double frame_period_s_, end_s_;
  std::uint64_t next_index_ = 0;
  cv::Mat image_;
};

}  // namespace agv::pipeline
