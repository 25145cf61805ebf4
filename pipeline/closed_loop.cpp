#include "pipeline/closed_loop.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include "control/finite_step_controller.h"
#include "control/pid_controller.h"
#include "perception/tracking_line_estimator.h"
#include "pipeline/config/scenario_loader.h"
#include "pipeline/sim/frame_renderer.h"
#include "pipeline/sim/plant.h"

namespace agv::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Vehicle pose at the start: at arc length start_s_m, offset and turned by the initial errors.
Pose2 start_pose(const Scenario& s) {
  const Eigen::Vector2d foot = s.path.point_at(s.start_s_m);
  const double heading = s.path.heading_at(s.start_s_m);
  const Eigen::Vector2d left(-std::sin(heading), std::cos(heading));
  const Eigen::Vector2d p = foot + s.initial_e_d_m * left;
  return {p.x(), p.y(), wrap_angle_rad(heading + s.initial_e_theta_rad)};
}

BodyTwist start_twist(const Scenario& s) {
  return {s.path_speed_m_s, 0.0, s.path.curvature_at(s.start_s_m) * s.path_speed_m_s};
}

// Ground truth of a pose, keeping the foot point near the previous one.
class TruthTracker {
 public:
  TruthTracker(const control::Path& path, double start_s_m) : path_(path), s_m_(start_s_m) {}
  control::TrackingError operator()(const Pose2& pose) {
    foot_ = path_.project(pose.translation(), s_m_, 0.5);
    s_m_ = foot_.s_m;
    return path_.tracking_error(pose, foot_);
  }
  // What localisation tells the controller (controller.input: pose) about the pose last passed
  // to operator() and its errors `e`: those errors, the curvature at its foot point and the arc
  // length left to the path's end.
  LineMeasurement pose_measurement(const Pose2& pose, const control::TrackingError& e,
                                   double t_s) const {
    LineMeasurement m;
    m.stamp_s = t_s;
    m.line_found = true;
    m.e_theta_rad = e.e_theta_rad;
    m.e_d_m = e.e_d_m;
    m.curvature_1_m = foot_.curvature_1_m;
    m.confidence = 1.0;
    m.lines_seen = 1;
    const Eigen::Vector2d tangent(std::cos(foot_.heading_rad), std::sin(foot_.heading_rad));
    const double past_end_m =
        foot_.after_end ? (pose.translation() - foot_.point).dot(tangent) : 0.0;
    m.path_remaining_m = path_.length_m() - foot_.s_m - past_end_m;
    return m;
  }

 private:
  const control::Path& path_;
  double s_m_;
  control::PathProjection foot_;
};

Plant make_plant(const Scenario& s) {
  Plant::Options options{s.vehicle.actuator_lag_s, std::nullopt};
  if (const auto* dual = std::get_if<control::DualSteerGeometry>(&s.vehicle.drive))
    options.dual_steer = *dual;
  return Plant(start_pose(s), start_twist(s), options);
}

TraceRow make_row(const Scenario& s, double t_s, const Pose2& pose,
                  const control::TrackingError& truth,
                  const std::optional<StampedMeasurement>& newest,
                  const control::TrackerOutput& output, const BodyTwist& previous_command) {
  TraceRow row;
  row.t_s = t_s;
  row.pose = pose;
  row.truth = truth;
  if (newest) {
    row.has_measurement = true;
    row.measurement = newest->measurement;
    row.measurement_age_s = t_s - newest->measurement.stamp_s;
  }
  row.output = output;
  row.wheels = control::wheel_command(s.vehicle.drive, output.command);
  row.front_wheel = pose.transform({control::front_track_x_m(s.vehicle.drive), 0.0});
  row.rear_wheel = pose.transform({control::rear_track_x_m(s.vehicle.drive), 0.0});
  row.violations =
      control::check_limits(output.command, previous_command, s.vehicle.limits, s.controller.ts_s);
  return row;
}

}  // namespace

control::LineTracker make_tracker(const Scenario& s) {
  control::LineTracker::Options options;
  options.ts_s = s.controller.ts_s;
  options.path_speed_m_s = s.path_speed_m_s;
  options.line_lost_hold_s = s.controller.line_lost_hold_s;
  options.latency_compensation = s.controller.latency_compensation;
  return control::LineTracker(make_controller(s.controller, s.vehicle, &s.path), s.vehicle.limits,
                              options, start_twist(s));
}

perception::CameraModel render_camera(const Scenario& s) {
  if (!s.true_mount) return perception::camera_model_of(s.camera, s.camera_name);
  return perception::CameraModel(s.camera.intrinsics, *s.true_mount);
}

std::unique_ptr<control::PathController> make_controller(const ControllerConfig& config,
                                                         const VehicleConfig& vehicle,
                                                         const control::Path* planned_path) {
  switch (config.kind) {
    case ControllerKind::kFiniteStep:
      return std::make_unique<control::FiniteStepController>(config.finite_step);
    case ControllerKind::kPid:
      return std::make_unique<control::PidController>(config.pid);
    case ControllerKind::kSeed004FfP: {
      control::Seed004Controller::Options options = config.seed004;
      if (const auto* mecanum = std::get_if<control::MecanumDrive>(&vehicle.drive)) {
        options.mecanum = mecanum->geometry;
        options.wheel_limits = mecanum->wheel_limits;
      }
      return std::make_unique<control::Seed004Controller>(options);
    }
    case ControllerKind::kDwa:
    case ControllerKind::kImprovedDwa:
      break;
  }
  control::DwaController::Options options = config.dwa;
  options.improved = config.kind == ControllerKind::kImprovedDwa;
  options.front_wheel_x_m = control::front_track_x_m(vehicle.drive);
  options.rear_wheel_x_m = control::rear_track_x_m(vehicle.drive);
  if (planned_path) options.planned_path = std::make_shared<const control::Path>(*planned_path);
  if (const auto* dual = std::get_if<control::DualSteerGeometry>(&vehicle.drive)) {
    options.max_wheel_speed_m_s = dual->max_wheel_speed_m_s;
    options.max_steer_rad = dual->max_steer_rad;
    options.front_steers = dual->front_steers();
    options.rear_steers = dual->rear_steers();
  } else {  // Mecanum wheels do not steer; their rims turn at most this fast
    const auto& mecanum = std::get<control::MecanumDrive>(vehicle.drive);
    options.max_wheel_speed_m_s =
        mecanum.wheel_limits.max_wheel_speed_rad_s * mecanum.geometry.wheel_radius_m;
    options.front_steers = options.rear_steers = false;
  }
  return std::make_unique<control::DwaController>(options);
  return std::make_unique<control::FiniteStepController>(config.finite_step);
}

RunResult run_lockstep(const Scenario& s, const Progress& progress, const FrameSink& sink) {
  const Clock::time_point wall_start = Clock::now();
  const perception::CameraModel camera = perception::camera_model_of(s.camera, s.camera_name);
  const FrameRenderer renderer(render_camera(s), render_scene(s));
  perception::TrackingLineEstimator estimator(camera, perception_options(s));
  control::LineTracker tracker = make_tracker(s);
  Plant plant = make_plant(s);
  TruthTracker truth_of(s.path, s.start_s_m);
  BoundedQueue<StampedMeasurement> queue(s.loop.queue_capacity, QueuePolicy::kDropOldest);
  const bool pose_input = s.controller.input == ControllerInput::kPose;
  const double setup_wall_s = seconds_since(wall_start);
  std::deque<StampedMeasurement> in_flight;  // taken, not yet delivered (latency)

  RunResult result;
  result.controller_name = tracker.controller().name();
  const double ts = s.controller.ts_s;
  const int periods = static_cast<int>(std::floor(s.duration_s / ts + 1e-9)) + 1;
  BodyTwist previous_command = start_twist(s);
  std::optional<StampedMeasurement> newest;
  cv::Mat frame;
  for (int k = 0; k < periods; ++k) {
    const double t = k * ts;
    const Pose2 pose = plant.pose();
    const control::TrackingError truth = truth_of(pose);

    Clock::time_point t0 = Clock::now();
    StampedMeasurement stamped{{}, truth, static_cast<std::uint64_t>(k)};
    if (pose_input) {
      stamped.measurement = truth_of.pose_measurement(pose, truth, t);
    } else {
      renderer.render_into(pose, plant.twist(), static_cast<std::uint64_t>(k), &frame);
      apply_frame_faults(s.frame_faults, t, static_cast<std::uint64_t>(k), &frame);
      Clock::time_point t1 = Clock::now();
      stamped.measurement = estimator.measure(frame, t);
      Clock::time_point t2 = Clock::now();
      result.total_times.render_s += std::chrono::duration<double>(t1 - t0).count();
      result.total_times.perceive_s += std::chrono::duration<double>(t2 - t1).count();
      result.frames.push_back({stamped.frame_index, t, truth, stamped.measurement});
      if (sink) sink(result.frames.back(), pose, frame);
    }

    in_flight.push_back(stamped);
    while (!in_flight.empty() &&
           in_flight.front().measurement.stamp_s + s.latency_frames * ts <= t + 1e-9) {
      queue.push(in_flight.front());
      in_flight.pop_front();
    }
    const std::optional<StampedMeasurement> arrived = queue.pop_newest();
    if (arrived) newest = arrived;

    t0 = Clock::now();
    const control::TrackerOutput output = tracker.step(
        arrived ? std::optional<LineMeasurement>(arrived->measurement) : std::nullopt, t);
    result.total_times.control_s += seconds_since(t0);
    result.rows.push_back(make_row(s, t, pose, truth, newest, output, previous_command));
    previous_command = output.command;
    plant.step(output.command, ts);
    if (progress && (k % 10 == 0 || k + 1 == periods))
      progress(static_cast<double>(k + 1) / periods);
  }
  result.queue = queue.stats();
  result.wall_s = seconds_since(wall_start);
  result.setup_wall_s = setup_wall_s;
  return result;
}

RunResult run_threaded(const Scenario& s, const Progress& progress) {
  // Built before the clock starts: their set-up (floor map, texture) is not part of the run.
  const Clock::time_point setup_start = Clock::now();
  const perception::CameraModel camera = perception::camera_model_of(s.camera, s.camera_name);
  const FrameRenderer renderer(render_camera(s), render_scene(s));
  perception::TrackingLineEstimator estimator(camera, perception_options(s));  // camera thread
  const double setup_wall_s = seconds_since(setup_start);
  const Clock::time_point wall_start = Clock::now();
  const double ts = s.controller.ts_s;
  const double frame_period_s = s.loop.camera_fps > 0.0 ? 1.0 / s.loop.camera_fps : ts;
  const int periods = static_cast<int>(std::floor(s.duration_s / ts + 1e-9)) + 1;
  auto wall_time_of = [&](double sim_s) {
    return wall_start + std::chrono::duration_cast<Clock::duration>(
                            std::chrono::duration<double>(sim_s / s.loop.time_scale));
  };

  // State shared by the two threads: the pose at the last control tick and the twist since.
  std::mutex state_mutex;
  Plant plant = make_plant(s);
  double tick_s = 0.0;
  BodyTwist active_command = start_twist(s);
  const bool pose_input = s.controller.input == ControllerInput::kPose;

  BoundedQueue<StampedMeasurement> queue(s.loop.queue_capacity, s.loop.queue_policy);
  std::atomic<bool> stop{false};
  RunResult result;
  std::mutex frames_mutex;
  enum Watched { kCameraThread = 0, kControlThread = 1 };
  // Each thread waits up to its own period between beats: the timeout is at least two of them.
  Watchdog watchdog({"camera", "control"},
                    std::max(s.loop.watchdog_timeout_s, 2.0 * std::max(frame_period_s, ts)),
                    wall_start, s.loop.time_scale);
  // Injected hangs (tests): each thread hangs once at each of its hang times.
  auto hang_if_due = [&](LoopThread thread, double t, std::vector<bool>* done) {
    for (size_t h = 0; h < s.loop.hangs.size(); ++h) {
      const LoopConfig::Hang& hang = s.loop.hangs[h];
      if (hang.thread != thread || (*done)[h] || t < hang.at_s) continue;
      (*done)[h] = true;
      std::this_thread::sleep_for(std::chrono::duration<double>(hang.for_s / s.loop.time_scale));
    }
  };

  std::thread camera_thread([&] {
    TruthTracker truth_of(s.path, s.start_s_m);
    std::deque<StampedMeasurement> in_flight;
    std::vector<bool> hung(s.loop.hangs.size(), false);
    cv::Mat frame;
    for (std::uint64_t i = 0; !stop.load(); ++i) {
      const double t = i * frame_period_s;
      if (t > s.duration_s + s.latency_frames * ts) break;
      std::this_thread::sleep_until(wall_time_of(t));
      hang_if_due(LoopThread::kCamera, t, &hung);
      watchdog.beat(kCameraThread);
      Pose2 pose;
      BodyTwist twist;
      {
        std::lock_guard<std::mutex> lock(state_mutex);
        // The wheels' twist (dual steer) or the command, held since the last tick.
        twist =
            s.vehicle.kind() == control::VehicleKind::kDualSteer ? plant.twist() : active_command;
        pose = integrate_twist(plant.pose(), twist, std::max(0.0, t - tick_s));
      }
      const control::TrackingError truth = truth_of(pose);
      Clock::time_point t0 = Clock::now();
      StampedMeasurement stamped{{}, truth, i};
      if (pose_input) {
        stamped.measurement = truth_of.pose_measurement(pose, truth, t);
      } else {
        renderer.render_into(pose, twist, i, &frame);
        apply_frame_faults(s.frame_faults, t, i, &frame);
        Clock::time_point t1 = Clock::now();
        stamped.measurement = estimator.measure(frame, t);
        Clock::time_point t2 = Clock::now();
        std::lock_guard<std::mutex> lock(frames_mutex);
        result.total_times.render_s += std::chrono::duration<double>(t1 - t0).count();
        result.total_times.perceive_s += std::chrono::duration<double>(t2 - t1).count();
        result.frames.push_back({i, t, truth, stamped.measurement});
      }
      // Extra transport latency, if configured, before the measurement enters the queue.
      in_flight.push_back(stamped);
      const double now_s = seconds_since(wall_start) * s.loop.time_scale;
      while (!in_flight.empty() &&
             in_flight.front().measurement.stamp_s + s.latency_frames * ts <= now_s + 1e-9) {
        queue.push(in_flight.front(),
                   std::chrono::milliseconds(static_cast<int>(1000 * ts / s.loop.time_scale)));
        in_flight.pop_front();
      }
    }
    watchdog.finished(kCameraThread);
  });

  control::LineTracker tracker = make_tracker(s);
  result.controller_name = tracker.controller().name();
  TruthTracker truth_of(s.path, s.start_s_m);
  BodyTwist previous_command = start_twist(s);
  std::optional<StampedMeasurement> newest;
  std::vector<bool> hung(s.loop.hangs.size(), false);
  for (int k = 0; k < periods; ++k) {
    const double t = k * ts;
    std::this_thread::sleep_until(wall_time_of(t));
    hang_if_due(LoopThread::kControl, t, &hung);
    watchdog.beat(kControlThread);
    result.max_tick_lateness_s =
        std::max(result.max_tick_lateness_s, seconds_since(wall_start) - t / s.loop.time_scale);
    Pose2 pose;
    {
      std::lock_guard<std::mutex> lock(state_mutex);
      if (k > 0) plant.step(active_command, ts);
      tick_s = t;
      pose = plant.pose();
    }
    const control::TrackingError truth = truth_of(pose);
    const std::optional<StampedMeasurement> arrived = queue.pop_newest();
    if (arrived) newest = arrived;
    const Clock::time_point t0 = Clock::now();
    const control::TrackerOutput output = tracker.step(
        arrived ? std::optional<LineMeasurement>(arrived->measurement) : std::nullopt, t);
    result.total_times.control_s += seconds_since(t0);
    {
      std::lock_guard<std::mutex> lock(state_mutex);
      active_command = output.command;
    }
    result.rows.push_back(make_row(s, t, pose, truth, newest, output, previous_command));
    previous_command = output.command;
    if (progress && (k % 10 == 0 || k + 1 == periods))
      progress(static_cast<double>(k + 1) / periods);
  }
  watchdog.finished(kControlThread);
  stop.store(true);
  queue.close();
  camera_thread.join();
  watchdog.stop();
  result.stalls = watchdog.stalls();
  result.queue = queue.stats();
  result.wall_s = seconds_since(wall_start) + setup_wall_s;
  result.setup_wall_s = setup_wall_s;
  return result;
}

RunResult run_scenario(const Scenario& scenario, const Progress& progress) {
  return scenario.loop.mode == LoopMode::kThreaded ? run_threaded(scenario, progress)
                                                   : run_lockstep(scenario, progress);
}

}  // namespace agv::pipeline
