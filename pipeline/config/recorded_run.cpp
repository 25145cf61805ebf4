#include "pipeline/config/recorded_run.h"

#include <chrono>
#include <cmath>

#include "pipeline/config/factory.h"
#include "pipeline/lockstep_loop.h"
#include "pipeline/threaded_loop.h"

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

ThreadedSchedule real_time_schedule(const FrameSource& source, const Scenario& s,
                                    const RecordedRunOptions& options) {
  ThreadedSchedule schedule;
  schedule.start_s = source.next_time_s().value_or(0.0);  // a live source's clock starts at 0
  schedule.ts_s = s.controller.ts_s;
  schedule.end_s = schedule.start_s + options.duration_s;
  schedule.watchdog_timeout_s = s.loop.watchdog_timeout_s;
  schedule.drop_late_frames = !source.live();
  schedule.real_time_control = true;
  schedule.end_with_source = true;
  schedule.brake_at_end = options.brake_at_end;
  schedule.stop = options.stop;
  return schedule;
}

}  // namespace

RunResult run_on_source(FrameSource& source, const perception::CameraModel& camera,
                        const Scenario& s, const RecordedRunOptions& options,
                        const Progress& progress) {
  const Clock::time_point start = Clock::now();
  ImagePerceiver perceiver(camera, options.perception, s.perception_path_memory);
  BoundedQueue<StampedMeasurement> queue(s.loop.queue_capacity, QueuePolicy::kDropOldest);
  CameraStage::Options camera_options;
  CameraStage camera_stage(source, perceiver, queue, camera_options, options.sink);
  ControlStage control(make_tracker(s, s.controller.ts_s), queue,
                       control_stage_options(s, s.controller.ts_s));
  Loop loop{camera_stage, queue, control, nullptr, options.on_period};
  const double setup_wall_s = std::chrono::duration<double>(Clock::now() - start).count();

  RunResult result;
  if (options.real_time) {
    result = run_threaded(loop, real_time_schedule(source, s, options), progress);
  } else {
    LockstepSchedule schedule{source.next_time_s().value_or(0.0), s.controller.ts_s, -1,
                              options.brake_at_end};
    if (std::isfinite(options.duration_s)) {
      schedule.periods =
          static_cast<long>(std::floor(options.duration_s / schedule.ts_s + 1e-9)) + 1;
    }
    result = run_lockstep(loop, schedule, progress);
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  result.setup_wall_s = setup_wall_s;
  return result;
}

}  // namespace agv::pipeline
