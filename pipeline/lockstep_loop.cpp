#include "pipeline/lockstep_loop.h"

#include <algorithm>

namespace agv::pipeline {
namespace {

// Frame and period times are sums of periods: a nanosecond of slack keeps rounding from moving
// a frame to the other side of a period.
constexpr double kFrameTimeSlack_s = 1e-9;

// Measures every frame taken up to limit_s.
void take_frames_until(CameraStage& camera, double limit_s) {
  for (std::optional<double> t_s = camera.source().next_time_s(); t_s && *t_s <= limit_s;
       t_s = camera.source().next_time_s()) {
    camera.step();
  }
}

bool stands_still(const TraceRow& row) {
  const BodyTwist& c = row.output.command;
  return c.vx_m_s == 0.0 && c.vy_m_s == 0.0 && c.wz_rad_s == 0.0;
}

}  // namespace

RunResult run_lockstep(Loop& loop, const LockstepSchedule& schedule, const Progress& progress) {
  RunResult result;
  const bool until_source_ends = schedule.periods < 0;
  const long frames = loop.camera.source().frame_count();
  long k = 0;
  for (; until_source_ends || k < schedule.periods; ++k) {
    const double t_s = schedule.start_s + k * schedule.ts_s;
    if (until_source_ends && !loop.camera.source().next_time_s()) break;
    take_frames_until(loop.camera, t_s - kFrameTimeSlack_s);  // taken while the last command held
    std::optional<Pose2> pose;
    if (loop.vehicle) {
      if (k > 0) loop.vehicle->advance(t_s, schedule.ts_s);
      pose = loop.vehicle->state_at(t_s).pose;
    }
    take_frames_until(loop.camera, t_s + kFrameTimeSlack_s);
    result.rows.push_back(loop.control.step(t_s, pose));
    const TraceRow& row = result.rows.back();
    if (loop.vehicle) loop.vehicle->command(row.output.command);
    if (loop.on_period) loop.on_period(row);
    if (!progress || k % 10 != 0) continue;
    if (!until_source_ends) {
      progress(static_cast<double>(k + 1) / schedule.periods);
    } else if (frames > 0) {
      progress(std::min(1.0, static_cast<double>(loop.camera.records().size()) / frames));
    }
  }
  for (; schedule.brake_at_end && !result.rows.empty() && !stands_still(result.rows.back()); ++k) {
    result.rows.push_back(loop.control.brake(schedule.start_s + k * schedule.ts_s));
    if (loop.on_period) loop.on_period(result.rows.back());
  }
  if (progress) progress(1.0);
  result.stop_reason = until_source_ends ? "end of source" : "duration";
  collect_results(loop, &result);
  return result;
}

}  // namespace agv::pipeline
