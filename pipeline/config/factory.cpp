#include "pipeline/config/factory.h"

#include <cmath>
#include <numbers>

#include "common/angles.h"
#include "control/dwa_controller.h"
#include "control/finite_step_controller.h"
#include "control/pid_controller.h"
#include "control/seed004_controller.h"

namespace agv::pipeline {
namespace {

// Seams and stray marks drawn as thin dark strips over the region the run can see: the main
// path's bounding box grown by a metre.
void add_floor_marks(const Scenario& s, Scene* scene) {
  const FloorMarks& m = s.marks;
  if (m.seam_spacing_m <= 0.0 && m.marks_per_m2 <= 0.0) return;
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (double t = 0.0; t <= s.path.length_m(); t += 0.05) {
    lo = lo.cwiseMin(s.path.point_at(t));
    hi = hi.cwiseMax(s.path.point_at(t));
  }
  lo -= Eigen::Vector2d(1.0, 1.0);
  hi += Eigen::Vector2d(1.0, 1.0);
  auto strip = [&](const Pose2& start, double length_m, double width_m, double darkness) {
    TapeStrip mark;
    mark.path = control::Path::starting_at(start).add_line(length_m);
    mark.width_m = width_m;
    mark.color_bgr = s.floor.color_bgr * (1.0 - darkness);
    mark.edge_softness_m = 0.3 * width_m;
    mark.texture_contrast = 0.0;
    scene->tapes.push_back(mark);
  };
  if (m.seam_spacing_m > 0.0) {
    for (double x = std::ceil(lo.x() / m.seam_spacing_m) * m.seam_spacing_m; x <= hi.x();
         x += m.seam_spacing_m) {
      strip({x, lo.y(), kPi / 2}, hi.y() - lo.y(), m.seam_width_m, m.seam_darkness);
    }
    for (double y = std::ceil(lo.y() / m.seam_spacing_m) * m.seam_spacing_m; y <= hi.y();
         y += m.seam_spacing_m) {
      strip({lo.x(), y, 0.0}, hi.x() - lo.x(), m.seam_width_m, m.seam_darkness);
    }
  }
  cv::RNG rng(s.seed * 7777 + 5);
  const int count = static_cast<int>(m.marks_per_m2 * (hi - lo).prod());
  for (int i = 0; i < count; ++i) {
    strip({rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), rng.uniform(-kPi, kPi)},
          rng.uniform(0.02, 0.1), rng.uniform(0.001, 0.004),
          m.mark_darkness * rng.uniform(0.5, 1.0));
  }
}

std::unique_ptr<control::PathController> make_dwa(const Scenario& s) {
  control::DwaController::Options options = s.controller.dwa;
  options.improved = s.controller.kind == ControllerKind::kImprovedDwa;
  options.front_wheel_x_m = control::front_track_x_m(s.vehicle.drive);
  options.rear_wheel_x_m = control::rear_track_x_m(s.vehicle.drive);
  options.planned_path = std::make_shared<const control::Path>(s.path);
  if (const auto* dual = std::get_if<control::DualSteerGeometry>(&s.vehicle.drive)) {
    options.max_wheel_speed_m_s = dual->max_wheel_speed_m_s;
    options.max_steer_rad = dual->max_steer_rad;
    options.max_steer_rate_rad_s = dual->max_steer_rate_rad_s;
    options.front_steers = dual->front_steers();
    options.rear_steers = dual->rear_steers();
  } else {  // Mecanum wheels do not steer; their rims turn at most this fast
    const auto& mecanum = std::get<control::MecanumDrive>(s.vehicle.drive);
    options.max_wheel_speed_m_s =
        mecanum.wheel_limits.max_wheel_speed_rad_s * mecanum.geometry.wheel_radius_m;
    options.front_steers = options.rear_steers = false;
  }
  return std::make_unique<control::DwaController>(options);
}

// How the scenario's vehicle responds to its commands.
control::DriveResponse::Options drive_response_options(const Scenario& s) {
  control::DriveResponse::Options options{s.vehicle.actuator_lag_s, std::nullopt};
  if (const auto* dual = std::get_if<control::DualSteerGeometry>(&s.vehicle.drive))
    options.dual_steer = *dual;
  return options;
}

// The finite-step horizon's n_min "auto" (ControllerConfig::finite_step_n_min_auto): one more
// than the periods an actuator lag's time constant spans; for dual steering wheels, the periods
// they take to steer 0.25 rad.
int auto_n_min(const Scenario& s) {
  constexpr double kSlack = 1e-9;  // a whole number of periods is not one more
  if (const auto* dual = std::get_if<control::DualSteerGeometry>(&s.vehicle.drive)) {
    constexpr double kSteer_rad = 0.25;
    const double per_period_rad = dual->max_steer_rate_rad_s * s.controller.ts_s;
    return std::max(1, static_cast<int>(std::ceil(kSteer_rad / per_period_rad - kSlack)));
  }
  return 1 + static_cast<int>(std::ceil(s.vehicle.actuator_lag_s / s.controller.ts_s - kSlack));
}

}  // namespace

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

std::unique_ptr<control::PathController> make_controller(const Scenario& s) {
  switch (s.controller.kind) {
    case ControllerKind::kFiniteStep: {
      control::FiniteStepController::Options options = s.controller.finite_step;
      if (s.controller.finite_step_n_min_auto)
        options.n_min = std::min(auto_n_min(s), options.n_max);
      return std::make_unique<control::FiniteStepController>(options);
    }
    case ControllerKind::kPid:
      return std::make_unique<control::PidController>(s.controller.pid);
    case ControllerKind::kSeed004FfP: {
      control::Seed004Controller::Options options = s.controller.seed004;
      if (const auto* mecanum = std::get_if<control::MecanumDrive>(&s.vehicle.drive)) {
        options.mecanum = mecanum->geometry;
        options.wheel_limits = mecanum->wheel_limits;
      }
      return std::make_unique<control::Seed004Controller>(options);
    }
    case ControllerKind::kDwa:
    case ControllerKind::kImprovedDwa:
      return make_dwa(s);
  }
  return nullptr;  // unreachable: every kind is handled above
}

control::LineTracker make_tracker(const Scenario& s, double ts_s) {
  control::LineTracker::Options options;
  options.ts_s = ts_s;
  options.path_speed_m_s = s.path_speed_m_s;
  options.line_lost_hold_s = s.controller.line_lost_hold_s;
  options.latency_compensation = s.controller.latency_compensation;
  options.curve_turn_fraction = s.controller.curve_turn_fraction;
  options.drive = drive_response_options(s);
  return control::LineTracker(make_controller(s), s.vehicle.limits, options, start_twist(s));
}

ControlStage::Options control_stage_options(const Scenario& s, double ts_s) {
  return {s.vehicle.drive, s.vehicle.limits, ts_s, start_twist(s)};
}

std::vector<std::string> scenario_warnings(const Scenario& s) {
  std::vector<std::string> warnings;
  const auto* dual = std::get_if<control::DualSteerGeometry>(&s.vehicle.drive);
  const bool sideways_law = s.controller.kind == ControllerKind::kFiniteStep ||
                            s.controller.kind == ControllerKind::kPid ||
                            s.controller.kind == ControllerKind::kSeed004FfP;
  if (dual && dual->form != control::DriveForm::kBothSteer && sideways_law) {
    warnings.push_back("vehicle.dual_steer.drive_form " + word_of(kDriveFormWords, dual->form) +
                       " cannot move its reference point sideways, which controller.kind " +
                       word_of(kControllerKindWords, s.controller.kind) +
                       " commands: expect it to leave the line; dwa and improved_dwa steer such "
                       "a vehicle");
  }
  return warnings;
}

Plant make_plant(const Scenario& s) {
  return Plant(start_pose(s), start_twist(s), drive_response_options(s));
}

perception::CameraModel render_camera(const Scenario& s) {
  if (!s.true_mount) return perception::camera_model_of(s.camera, s.camera_name);
  return perception::CameraModel(s.camera.intrinsics, *s.true_mount);
}

Scene render_scene(const Scenario& scenario) {
  Scene scene;
  add_floor_marks(scenario, &scene);  // first: the tape is laid over seams and marks
  scene.tags = scenario.floor_tags;
  scene.tapes.push_back(scenario.tape);
  for (const control::Path& path : scenario.extra_paths) {
    TapeStrip extra = scenario.tape;
    extra.path = path;
    extra.gaps_m.clear();
    scene.tapes.push_back(extra);
  }
  scene.floor = scenario.floor;
  scene.effects = scenario.effects;
  scene.seed = scenario.seed;
  return scene;
}

perception::LineEstimator::Options perception_options(const Scenario& scenario) {
  perception::LineEstimator::Options options;
  options.tape.width_m = scenario.tape.width_m;
  if (scenario.tape_color_hint) options.tape.color_bgr = scenario.tape.color_bgr;
  options.tracking = scenario.perception_tracking;
  options.search_every_frames = scenario.perception_search_every_frames;
  options.branch = scenario.perception_branch;
  return options;
}

std::unique_ptr<FrameRenderer> make_renderer(const Scenario& s) {
  return std::make_unique<FrameRenderer>(render_camera(s), render_scene(s));
}

double camera_period_s(const Scenario& s) {
  return s.loop.camera_fps > 0.0 ? 1.0 / s.loop.camera_fps : s.controller.ts_s;
}

perception::LineEstimator::Options recorded_perception_options(
    const Scenario& s, const perception::CameraFile& camera) {
  perception::LineEstimator::Options options = perception_options(s);
  // The recording's tape is the camera file's (the scenario's tape is the rendered one): its
  // width if the file gives it, else measured.
  options.tape.width_m = camera.tape_width_m.value_or(0.0);
  options.tape.color_bgr = camera.tape_color_bgr;
  return options;
}

}  // namespace agv::pipeline
