#include "pipeline/config/scenario_run.h"

#include <chrono>
#include <cmath>

#include "pipeline/config/factory.h"
#include "pipeline/lockstep_loop.h"
#include "pipeline/rendered_source.h"
#include "pipeline/threaded_loop.h"

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::unique_ptr<Perceiver> make_perceiver(const Scenario& s) {
  if (s.controller.input == ControllerInput::kPose)
    return std::make_unique<LocalisationPerceiver>(PathTruth(s.path, s.start_s_m));
  return std::make_unique<ImagePerceiver>(perception::camera_model_of(s.camera, s.camera_name),
                                          perception_options(s), s.perception_path_memory);
}

ThreadedSchedule threaded_schedule(const Scenario& s) {
  ThreadedSchedule schedule;
  schedule.ts_s = s.controller.ts_s;
  schedule.end_s = s.duration_s;
  schedule.time_scale = s.loop.time_scale;
  schedule.watchdog_timeout_s = s.loop.watchdog_timeout_s;
  schedule.hangs = s.loop.hangs;
  return schedule;
}

}  // namespace

RunResult run_scenario(const Scenario& s, const Progress& progress, const FrameSink& sink) {
  const Clock::time_point start = Clock::now();
  const bool pose_input = s.controller.input == ControllerInput::kPose;
  const double frame_period_s = camera_period_s(s);
  SimulatedVehicle vehicle(make_plant(s), start_twist(s));
  // With pose input the frames are drawn only for a sink that takes them (a recording of a run
  // steered by its true pose).
  const bool render = !pose_input || static_cast<bool>(sink);
  RenderedSource source(render ? make_renderer(s) : nullptr, vehicle,
                        PathTruth(s.path, s.start_s_m), WheelOdometry(s.odometry, s.seed),
                        frame_period_s, s.duration_s);
  const std::unique_ptr<Perceiver> perceiver = make_perceiver(s);
  BoundedQueue<StampedMeasurement> queue(s.loop.queue_capacity, s.loop.queue_policy);
  CameraStage::Options camera_options;
  camera_options.faults = s.frame_faults;
  camera_options.latency_s = s.latency_frames * frame_period_s;
  if (s.loop.mode == LoopMode::kThreaded) {  // a full queue may hold the camera a period
    camera_options.push_timeout = std::chrono::duration_cast<std::chrono::nanoseconds>(
        std::chrono::duration<double>(s.controller.ts_s / s.loop.time_scale));
  }
  CameraStage camera(source, *perceiver, queue, camera_options, sink);
  ControlStage control(make_tracker(s, s.controller.ts_s), queue,
                       control_stage_options(s, s.controller.ts_s), PathTruth(s.path, s.start_s_m));
  Loop loop{camera, queue, control, &vehicle, {}};
  const double setup_wall_s = seconds_since(start);

  RunResult result;
  if (s.loop.mode == LoopMode::kThreaded) {
    result = run_threaded(loop, threaded_schedule(s), progress);
  } else {
    const int periods = static_cast<int>(std::floor(s.duration_s / s.controller.ts_s + 1e-9)) + 1;
    result = run_lockstep(loop, {0.0, s.controller.ts_s, periods}, progress);
  }
  if (pose_input) result.frames.clear();  // localisation, not pictures: no frames to report
  result.wall_s = seconds_since(start);
  result.setup_wall_s = setup_wall_s;
  return result;
}

}  // namespace agv::pipeline
