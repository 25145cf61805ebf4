#include "pipeline/config/scenario_loader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/angles.h"
#include "common/input_error.h"
#include "pipeline/config/yaml_reader.h"

namespace agv::pipeline {
namespace {

constexpr double kJointTolerance_m = 1e-3;                 // a stated segment start may be 1 mm
constexpr double kJointTolerance_rad = kPi / 180.0 / 2.0;  // and half a degree off the path's end

cv::Vec3d colour(const std::vector<double>& bgr) { return {bgr[0], bgr[1], bgr[2]}; }
std::vector<double> values(const cv::Vec3d& bgr) { return {bgr[0], bgr[1], bgr[2]}; }

// A path under `prefix` ("path", "extra_tapes.0"): start pose and segments.
control::Path read_path(YamlReader& in, const std::string& prefix) {
  const Pose2 start{in.number(prefix + ".start.x_m", 0.0, -1e4, 1e4),
                    in.number(prefix + ".start.y_m", 0.0, -1e4, 1e4),
                    in.number(prefix + ".start.heading_rad", 0.0, -2 * kPi, 2 * kPi)};
  control::Path path = control::Path::starting_at(start);
  const size_t count = in.sequence_size(prefix + ".segments");
  if (count == 0) return path.add_line(20.0);
  for (size_t i = 0; i < count; ++i) {
    const std::string key = prefix + ".segments." + std::to_string(i) + ".";
    // A segment may say where it starts: it must be where the path ends so far.
    if (in.has(key + "start")) {
      const Pose2 stated{in.number(key + "start.x_m", 0.0, -1e4, 1e4),
                         in.number(key + "start.y_m", 0.0, -1e4, 1e4),
                         in.number(key + "start.heading_rad", 0.0, -2 * kPi, 2 * kPi)};
      const Pose2 end = path.end_pose();
      const double gap_m = (stated.translation() - end.translation()).norm();
      const double kink_rad = std::abs(wrap_angle_rad(stated.yaw_rad - end.yaw_rad));
      if (gap_m > kJointTolerance_m || kink_rad > kJointTolerance_rad) {
        char text[256];
        std::snprintf(text, sizeof(text),
                      "the joints must be continuous: the path so far ends at (%.4f, %.4f) m "
                      "heading %.2f deg, %.1f mm and %.2f deg away",
                      end.x_m, end.y_m, rad_to_deg(end.yaw_rad), 1e3 * gap_m, rad_to_deg(kink_rad));
        throw InputError(in.origin(key + "start") + ": key '" + key + "start': " + text);
      }
    }
    const std::string kind =
        in.choice(key + "kind", "line", {"line", "arc", "hermite_arc", "hermite"});
    if (kind == "line") {
      path.add_line(in.positive(key + "length_m", 1.0, 1e4));
    } else if (kind == "hermite") {
      const Pose2 end{in.number(key + "end.x_m", 0.0, -1e4, 1e4),
                      in.number(key + "end.y_m", 0.0, -1e4, 1e4),
                      in.number(key + "end.heading_rad", 0.0, -2 * kPi, 2 * kPi)};
      if ((end.translation() - path.end_pose().translation()).norm() < 1e-4)
        throw InputError(in.origin(key + "end") + ": key '" + key +
                         "end': must lie away from the segment's start (zero-length segment)");
      path.add_hermite_to(end);
    } else {
      const double radius_m = in.positive(key + "radius_m", 0.5, 1e4);
      const double limit_rad = kind == "arc" ? 2 * kPi : kPi / 2 + 1e-6;  // seed 004 S1: <= 90 deg
      const double angle_rad = in.number(key + "angle_rad", kPi / 2, -limit_rad, limit_rad);
      if (angle_rad == 0.0)
        throw InputError(in.origin(key + "angle_rad") + ": key '" + key +
                         "angle_rad': must not be 0");
      if (kind == "arc") {
        path.add_arc(radius_m, angle_rad);
      } else {
        path.add_hermite_arc(radius_m, angle_rad, in.integer(key + "pieces", 2, 1, 64));
      }
    }
  }
  return path;
}

// The camera file named by the scenario: a path relative to the scenario file (or, when given
// with --set, to the working directory); for the built-in scenario, or a relative name that
// does not exist beside the scenario, one of the built-in files.
perception::CameraFile read_camera(YamlReader& in, const ScenarioText& source, std::string* name) {
  const std::string value = in.text("camera", "default_camera.yaml");
  const bool from_option = in.origin("camera") != source.name;
  std::filesystem::path path(value);
  if (path.is_relative() && !from_option && !source.base_dir.empty()) {
    path = std::filesystem::path(source.base_dir) / path;
  }
  std::error_code error;
  const auto builtin = source.builtin_files.find(value);
  const bool use_builtin = builtin != source.builtin_files.end() && !from_option &&
                           (source.base_dir.empty() || !std::filesystem::exists(path, error));
  if (use_builtin) {
    *name = "built-in " + value;
    return perception::parse_camera_text(builtin->second, *name);
  }
  *name = path.string();
  try {
    return perception::load_camera_file(path.string());
  } catch (const InputError& e) {
    throw InputError(in.origin("camera") + ": key 'camera': " + e.what());
  }
}

// Keys that moved when the vehicle and controller settings were grouped by kind: a file that
// still uses one is told where it went.
void refuse_moved_keys(const YamlReader& in) {
  static const std::vector<std::pair<std::string, std::string>> moved = {
      {"vehicle.wheel_radius_m", "vehicle.mecanum.wheel_radius_m"},
      {"vehicle.half_wheelbase_m", "vehicle.mecanum.half_wheelbase_m"},
      {"vehicle.half_track_m", "vehicle.mecanum.half_track_m"},
      {"vehicle.max_wheel_speed_rad_s", "vehicle.mecanum.max_wheel_speed_rad_s"},
      {"vehicle.max_wheel_accel_rad_s2", "vehicle.mecanum.max_wheel_accel_rad_s2"},
      {"vehicle.drive_form", "vehicle.dual_steer.drive_form"},
      {"vehicle.wheelbase_m", "vehicle.dual_steer.wheelbase_m"},
      {"vehicle.max_steer_rad", "vehicle.dual_steer.max_steer_rad"},
      {"vehicle.max_steer_rate_rad_s", "vehicle.dual_steer.max_steer_rate_rad_s"},
      {"vehicle.max_wheel_speed_m_s", "vehicle.dual_steer.max_wheel_speed_m_s"},
      {"controller.horizon", "controller.finite_step.horizon"},
      {"controller.n_fixed", "controller.finite_step.n_fixed"},
      {"controller.n_min", "controller.finite_step.n_min"},
      {"controller.n_max", "controller.finite_step.n_max"},
      {"controller.a_max_m_s2", "controller.finite_step.a_max_m_s2"},
      {"controller.v_x_max_m_s", "controller.finite_step.v_x_max_m_s"},
  };
  for (const auto& [old_key, new_key] : moved) {
    if (in.has(old_key)) {
      throw InputError(in.origin(old_key) + ": key '" + old_key + "': has moved to '" + new_key +
                       "' (vehicle and controller settings are grouped by kind)");
    }
  }
}

// Duration, seed, speed, latency, the path and where on it the vehicle starts.
void read_run(YamlReader& in, Scenario* s) {
  s->duration_s = in.positive("duration_s", s->duration_s, 3600.0);
  s->seed = static_cast<std::uint64_t>(in.integer("seed", 1, 0, 2147483647));
  s->path_speed_m_s = in.number("path_speed_m_s", s->path_speed_m_s, 0.0, 5.0);
  s->latency_frames = in.integer("latency_frames", s->latency_frames, 0, 50);
  s->initial_e_theta_rad =
      in.number("initial_error.e_theta_rad", s->initial_e_theta_rad, -kPi / 2, kPi / 2);
  s->initial_e_d_m = in.number("initial_error.e_d_m", s->initial_e_d_m, -0.5, 0.5);
  s->path = read_path(in, "path");
  for (size_t i = 0; i < in.sequence_size("extra_tapes"); ++i) {
    s->extra_paths.push_back(read_path(in, "extra_tapes." + std::to_string(i)));
  }
  s->start_s_m = in.number("start_s_m", s->start_s_m, 0.0, s->path.length_m());
}

void read_tape(YamlReader& in, Scenario* s) {
  TapeStrip& tape = s->tape;
  tape.width_m = in.number("tape.width_m", tape.width_m, 0.002, 0.3);
  tape.color_bgr = colour(in.numbers("tape.color_bgr", values(tape.color_bgr), 3, 0.0, 255.0));
  tape.edge_softness_m = in.number("tape.edge_softness_m", tape.edge_softness_m, 0.0, 0.01);
  tape.texture_contrast = in.number("tape.texture_contrast", tape.texture_contrast, 0.0, 1.0);
  tape.wear = in.number("tape.wear", tape.wear, 0.0, 0.95);
  for (size_t i = 0; i < in.sequence_size("tape.gaps_m"); ++i) {
    const std::string key = "tape.gaps_m." + std::to_string(i);
    const std::vector<double> gap = in.numbers(key, {}, 2, 0.0, s->path.length_m());
    if (gap[0] >= gap[1]) {
      throw InputError(in.origin(key) + ": key '" + key + "': expected [from, to] with from < to");
    }
    tape.gaps_m.emplace_back(gap[0], gap[1]);
  }
  tape.path = s->path;
}

void read_floor(YamlReader& in, Scenario* s) {
  FloorMarks& marks = s->marks;
  marks.seam_spacing_m = in.number("floor.seam_spacing_m", marks.seam_spacing_m, 0.0, 100.0);
  if (marks.seam_spacing_m > 0.0 && marks.seam_spacing_m < 0.05) {
    throw InputError(in.origin("floor.seam_spacing_m") +
                     ": key 'floor.seam_spacing_m': 0 (no seams) or at least 0.05 m");
  }
  marks.seam_width_m = in.number("floor.seam_width_m", marks.seam_width_m, 0.0005, 0.05);
  marks.seam_darkness = in.number("floor.seam_darkness", marks.seam_darkness, 0.0, 1.0);
  marks.marks_per_m2 = in.number("floor.marks_per_m2", marks.marks_per_m2, 0.0, 200.0);
  marks.mark_darkness = in.number("floor.mark_darkness", marks.mark_darkness, 0.0, 1.0);
  FloorStyle& floor = s->floor;
  floor.color_bgr = colour(in.numbers("floor.color_bgr", values(floor.color_bgr), 3, 0.0, 255.0));
  floor.texture_contrast = in.number("floor.texture_contrast", floor.texture_contrast, 0.0, 1.0);
  floor.texture_feature_m =
      in.number("floor.texture_feature_m", floor.texture_feature_m, 0.0005, 0.05);
}

void read_image_effects(YamlReader& in, ImageEffects* fx) {
  fx->noise_sigma = in.number("image.noise_sigma", fx->noise_sigma, 0.0, 100.0);
  fx->exposure_s = in.number("image.exposure_s", fx->exposure_s, 0.0, 0.1);
  fx->vignetting = in.number("image.vignetting", fx->vignetting, 0.0, 0.95);
  fx->illumination_gradient =
      in.number("image.illumination_gradient", fx->illumination_gradient, 0.0, 1.5);
  fx->illumination_direction_rad = in.number("image.illumination_direction_rad",
                                             fx->illumination_direction_rad, -2 * kPi, 2 * kPi);
  fx->brightness = in.number("image.brightness", fx->brightness, 0.05, 4.0);
  fx->shadow_darkness = in.number("image.shadow.darkness", fx->shadow_darkness, 0.0, 0.95);
  fx->shadow_direction_rad =
      in.number("image.shadow.direction_rad", fx->shadow_direction_rad, -2 * kPi, 2 * kPi);
  fx->shadow_offset = in.number("image.shadow.offset", fx->shadow_offset, -1.5, 1.5);
  fx->shadow_softness = in.number("image.shadow.softness", fx->shadow_softness, 0.001, 1.0);
  fx->specular_strength = in.number("image.specular.strength", fx->specular_strength, 0.0, 255.0);
  fx->specular_x = in.number("image.specular.x", fx->specular_x, -0.5, 1.5);
  fx->specular_y = in.number("image.specular.y", fx->specular_y, -0.5, 1.5);
  fx->specular_radius = in.number("image.specular.radius", fx->specular_radius, 0.005, 2.0);
}

void read_frame_faults(YamlReader& in, Scenario* s) {
  for (size_t i = 0; i < in.sequence_size("frame_faults"); ++i) {
    const std::string key = "frame_faults." + std::to_string(i);
    FrameFault fault;
    fault.kind = in.choice(
        key + ".kind", FrameFault::Kind::kCovered,
        std::vector<std::pair<std::string, FrameFault::Kind>>{
            {"covered", FrameFault::Kind::kCovered}, {"flash", FrameFault::Kind::kFlash}});
    fault.from_s = in.number(key + ".from_s", 0.0, 0.0, 1e6);
    fault.to_s = in.number(key + ".to_s", 0.0, 0.0, 1e6);
    if (fault.to_s <= fault.from_s)
      throw InputError(in.origin(key) + ": key '" + key + "': expected from_s < to_s");
    s->frame_faults.push_back(fault);
  }
}

void read_perception(YamlReader& in, Scenario* s) {
  s->tape_color_hint = in.boolean("perception.use_tape_color_hint", s->tape_color_hint);
  s->perception_tracking = in.boolean("perception.tracking", s->perception_tracking);
  s->perception_search_every_frames =
      in.integer("perception.search_every_frames", s->perception_search_every_frames, 1, 100000);
  s->perception_path_memory = in.boolean("perception.path_memory", s->perception_path_memory);
  s->perception_branch = in.choice("perception.branch", s->perception_branch,
                                   std::vector<std::pair<std::string, perception::BranchChoice>>{
                                       {"left", perception::BranchChoice::kLeft},
                                       {"straight", perception::BranchChoice::kStraight},
                                       {"right", perception::BranchChoice::kRight}});
}

void read_odometry(YamlReader& in, OdometryNoise* o) {
  o->scale_error = in.number("odometry.scale_error", o->scale_error, -0.5, 0.5);
  o->yaw_drift_rad_per_m =
      in.number("odometry.yaw_drift_rad_per_m", o->yaw_drift_rad_per_m, -1.0, 1.0);
  o->position_noise_m_per_sqrt_m =
      in.number("odometry.position_noise_m_per_sqrt_m", o->position_noise_m_per_sqrt_m, 0.0, 0.1);
  o->yaw_noise_rad_per_sqrt_m =
      in.number("odometry.yaw_noise_rad_per_sqrt_m", o->yaw_noise_rad_per_sqrt_m, 0.0, 0.5);
}

// The camera file (which must hold a mount), the mount the camera really has if it differs,
// and the AprilTags on the floor.
void read_camera_and_tags(YamlReader& in, const ScenarioText& source, Scenario* s) {
  s->camera = read_camera(in, source, &s->camera_name);
  if (!s->camera.mount) {
    throw InputError(s->camera_name +
                     ": field 'mount_xyz_m': missing; a simulation needs the camera's mount "
                     "pose (run 'agv calibrate mount', or add mount_xyz_m and mount_rpy_rad)");
  }
  if (in.has("camera_true_mount")) {
    perception::MountPose mount;
    const std::vector<double> xyz = in.numbers("camera_true_mount.xyz_m", {}, 3, -10.0, 10.0);
    const std::vector<double> rpy = in.numbers("camera_true_mount.rpy_rad", {}, 3, -7.0, 7.0);
    mount.xyz_m = {xyz[0], xyz[1], xyz[2]};
    mount.rpy_rad = {rpy[0], rpy[1], rpy[2]};
    perception::validate_mount(mount, in.origin("camera_true_mount") + " (camera_true_mount)");
    s->true_mount = mount;
  }
  for (size_t i = 0; i < in.sequence_size("floor_tags"); ++i) {
    const std::string key = "floor_tags." + std::to_string(i);
    FloorTag tag;
    tag.family = in.text(key + ".family", tag.family);
    tag.id = in.integer(key + ".id", 0, 0, 100000);
    tag.size_m = in.number(key + ".size_m", tag.size_m, 0.005, 2.0);
    tag.pose = {in.number(key + ".x_m", 0.0, -1e4, 1e4), in.number(key + ".y_m", 0.0, -1e4, 1e4),
                in.number(key + ".yaw_rad", 0.0, -10.0, 10.0)};
    s->floor_tags.push_back(tag);
  }
}

control::MecanumDrive read_mecanum(YamlReader& in) {
  control::MecanumDrive d;
  const std::string k = "vehicle.mecanum.";
  d.geometry.wheel_radius_m = in.positive(k + "wheel_radius_m", d.geometry.wheel_radius_m, 1.0);
  d.geometry.half_wheelbase_m =
      in.positive(k + "half_wheelbase_m", d.geometry.half_wheelbase_m, 5.0);
  d.geometry.half_track_m = in.positive(k + "half_track_m", d.geometry.half_track_m, 5.0);
  d.wheel_limits.max_wheel_speed_rad_s =
      in.positive(k + "max_wheel_speed_rad_s", d.wheel_limits.max_wheel_speed_rad_s, 10000.0);
  d.wheel_limits.max_wheel_accel_rad_s2 =
      in.positive(k + "max_wheel_accel_rad_s2", d.wheel_limits.max_wheel_accel_rad_s2, 1e5);
  return d;
}

control::DualSteerGeometry read_dual_steer(YamlReader& in) {
  control::DualSteerGeometry d;
  const std::string k = "vehicle.dual_steer.";
  d.form = in.choice(k + "drive_form", d.form, kDriveFormWords);
  d.wheelbase_m = in.positive(k + "wheelbase_m", d.wheelbase_m, 20.0);
  d.max_steer_rad = in.positive(k + "max_steer_rad", d.max_steer_rad, kPi / 2 + 1e-9);
  d.max_steer_rate_rad_s = in.positive(k + "max_steer_rate_rad_s", d.max_steer_rate_rad_s, 100.0);
  d.max_wheel_speed_m_s = in.positive(k + "max_wheel_speed_m_s", d.max_wheel_speed_m_s, 20.0);
  return d;
}

// The wheels must be able to carry the vehicle along the path at path speed.
void check_wheels_carry_path_speed(const YamlReader& in, const Scenario& s) {
  double need = s.path_speed_m_s, limit = 0.0;
  std::string key;
  if (const auto* mecanum = std::get_if<control::MecanumDrive>(&s.vehicle.drive)) {
    need = s.path_speed_m_s / mecanum->geometry.wheel_radius_m;
    limit = mecanum->wheel_limits.max_wheel_speed_rad_s;
    key = "vehicle.mecanum.max_wheel_speed_rad_s";
  } else {
    limit = std::get<control::DualSteerGeometry>(s.vehicle.drive).max_wheel_speed_m_s;
    key = "vehicle.dual_steer.max_wheel_speed_m_s";
  }
  if (need > limit) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  ": key '%s': %.3g is below the %.3g that path_speed_m_s %.3g m/s needs",
                  key.c_str(), limit, need, s.path_speed_m_s);
    throw InputError(in.origin(key) + text);
  }
}

// The vehicle's limits and its drive: the section of its kind; a section of another kind is
// refused (it would be silently ignored).
void read_vehicle(YamlReader& in, Scenario* s) {
  VehicleConfig& v = s->vehicle;
  const control::VehicleKind kind =
      in.choice("vehicle.kind", control::VehicleKind::kMecanum, kVehicleKindWords);
  for (const auto& [word, other] : kVehicleKindWords) {
    if (other == kind || !in.has("vehicle." + word)) continue;
    throw InputError(in.origin("vehicle." + word) + ": key 'vehicle." + word +
                     "': applies to vehicle.kind " + word + ", but this vehicle is " +
                     word_of(kVehicleKindWords, kind));
  }
  if (kind == control::VehicleKind::kMecanum) {
    v.drive = read_mecanum(in);
  } else {
    v.drive = read_dual_steer(in);
  }
  v.limits.v_forward_max_m_s =
      in.positive("vehicle.v_forward_max_m_s", v.limits.v_forward_max_m_s, 10.0);
  v.limits.v_lateral_max_m_s =
      in.positive("vehicle.v_lateral_max_m_s", v.limits.v_lateral_max_m_s, 10.0);
  v.limits.a_max_m_s2 = in.positive("vehicle.a_max_m_s2", v.limits.a_max_m_s2, 50.0);
  v.limits.w_max_rad_s = in.positive("vehicle.w_max_rad_s", v.limits.w_max_rad_s, 20.0);
  v.limits.alpha_max_rad_s2 =
      in.positive("vehicle.alpha_max_rad_s2", v.limits.alpha_max_rad_s2, 200.0);
  v.actuator_lag_s = in.number("vehicle.actuator_lag_s", v.actuator_lag_s, 0.0, 2.0);
  if (v.actuator_lag_s > 0.0 && kind == control::VehicleKind::kDualSteer) {
    throw InputError(in.origin("vehicle.actuator_lag_s") +
                     ": key 'vehicle.actuator_lag_s': applies to Mecanum vehicles; a dual "
                     "steering-wheel vehicle's response is its steer rate "
                     "(vehicle.dual_steer.max_steer_rate_rad_s)");
  }
  if (s->path_speed_m_s > v.limits.v_forward_max_m_s) {
    throw InputError(in.origin("path_speed_m_s") + ": key 'path_speed_m_s': " +
                     std::to_string(s->path_speed_m_s) + " m/s is above vehicle.v_forward_max_m_s");
  }
  check_wheels_carry_path_speed(in, *s);
}

void read_finite_step(YamlReader& in, control::FiniteStepController::Options* f, bool* n_min_auto) {
  const std::string k = "controller.finite_step.";
  f->a_max_m_s2 = in.positive(k + "a_max_m_s2", f->a_max_m_s2, 50.0);
  f->v_x_max_m_s = in.positive(k + "v_x_max_m_s", f->v_x_max_m_s, 10.0);
  f->mode = in.choice(k + "horizon", f->mode,
                      std::vector<std::pair<std::string, control::HorizonMode>>{
                          {"shrinking", control::HorizonMode::kShrinking},
                          {"fixed", control::HorizonMode::kFixed}});
  f->n_fixed = in.integer(k + "n_fixed", f->n_fixed, 1, 1000);
  if (in.has(k + "n_min")) {
    const std::string text = in.text(k + "n_min", "");
    *n_min_auto = text == "auto";
    if (!*n_min_auto) {
      if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(in.origin(k + "n_min") + ": key '" + k +
                         "n_min': expected a whole number or auto, got '" + text + "'");
      f->n_min = in.integer(k + "n_min", f->n_min, 1, 1000);
    }
  }
  f->n_max = in.integer(k + "n_max", f->n_max, 1, 1000);
  if (!*n_min_auto && f->n_min > f->n_max) {
    throw InputError(in.origin(k + "n_min") + ": key '" + k +
                     "n_min': must not exceed controller.finite_step.n_max");
  }
}

void read_pid(YamlReader& in, control::PidController::Options* p) {
  const std::string k = "controller.pid.";
  p->kp_d_1_s = in.number(k + "kp_d_1_s", p->kp_d_1_s, 0.0, 100.0);
  p->ki_d_1_s2 = in.number(k + "ki_d_1_s2", p->ki_d_1_s2, 0.0, 100.0);
  p->kd_d = in.number(k + "kd_d", p->kd_d, 0.0, 100.0);
  p->kp_theta_1_s = in.number(k + "kp_theta_1_s", p->kp_theta_1_s, 0.0, 100.0);
  p->ki_theta_1_s2 = in.number(k + "ki_theta_1_s2", p->ki_theta_1_s2, 0.0, 100.0);
  p->kd_theta = in.number(k + "kd_theta", p->kd_theta, 0.0, 100.0);
}

void read_seed004(YamlReader& in, control::Seed004Controller::Options* f) {
  const std::string k = "controller.seed004.";
  f->k_along_1_s = in.number(k + "k_along_1_s", f->k_along_1_s, 0.0, 100.0);
  f->k_lateral_1_s = in.number(k + "k_lateral_1_s", f->k_lateral_1_s, 0.0, 100.0);
  f->k_heading_1_s = in.number(k + "k_heading_1_s", f->k_heading_1_s, 0.0, 100.0);
  f->end_decel_m_s2 = in.positive(k + "end_decel_m_s2", f->end_decel_m_s2, 50.0);
  f->end_hold_m = in.number(k + "end_hold_m", f->end_hold_m, 0.0, 10.0);
}

void read_dwa(YamlReader& in, control::DwaController::Options* d) {
  const std::string k = "controller.dwa.";
  d->v_samples = in.integer(k + "v_samples", d->v_samples, 1, 1000);
  d->w_samples = in.integer(k + "w_samples", d->w_samples, 1, 1000);
  d->horizon_s = in.positive(k + "horizon_s", d->horizon_s, 60.0);
  d->lookahead_m = in.positive(k + "lookahead_m", d->lookahead_m, 100.0);
  d->weight_heading = in.number(k + "weight_heading", d->weight_heading, 0.0, 1e3);
  d->weight_clearance = in.number(k + "weight_clearance", d->weight_clearance, 0.0, 1e3);
  d->weight_speed = in.number(k + "weight_speed", d->weight_speed, 0.0, 1e3);
  d->weight_area = in.number(k + "weight_area", d->weight_area, 0.0, 1e3);
}

void read_controller(YamlReader& in, ControllerConfig* c) {
  c->kind = in.choice("controller.kind", c->kind, kControllerKindWords);
  c->input = in.choice("controller.input", c->input, kControllerInputWords);
  c->ts_s = in.number("controller.ts_s", c->ts_s, 0.001, 1.0);
  c->line_lost_hold_s = in.number("controller.line_lost_hold_s", c->line_lost_hold_s, 0.0, 60.0);
  c->latency_compensation = in.boolean("controller.latency_compensation", c->latency_compensation);
  c->curve_turn_fraction =
      in.number("controller.curve_turn_fraction", c->curve_turn_fraction, 0.0, 1.0);
  read_finite_step(in, &c->finite_step, &c->finite_step_n_min_auto);
  read_pid(in, &c->pid);
  read_seed004(in, &c->seed004);
  read_dwa(in, &c->dwa);
}

void read_loop(YamlReader& in, LoopConfig* loop) {
  loop->mode = in.choice("loop.mode", loop->mode, kLoopModeWords);
  loop->queue_capacity = static_cast<std::size_t>(
      in.integer("loop.queue_capacity", static_cast<int>(loop->queue_capacity), 1, 10000));
  loop->queue_policy =
      in.choice("loop.queue_policy", loop->queue_policy,
                std::vector<std::pair<std::string, QueuePolicy>>{
                    {"drop_oldest", QueuePolicy::kDropOldest}, {"block", QueuePolicy::kBlock}});
  loop->time_scale = in.positive("loop.time_scale", loop->time_scale, 1000.0);
  loop->camera_fps = in.number("loop.camera_fps", loop->camera_fps, 0.0, 10000.0);
  loop->watchdog_timeout_s =
      in.positive("loop.watchdog_timeout_s", loop->watchdog_timeout_s, 3600.0);
  for (size_t i = 0; i < in.sequence_size("loop.hangs"); ++i) {
    const std::string key = "loop.hangs." + std::to_string(i);
    InjectedHang hang;
    hang.thread =
        in.choice(key + ".thread", LoopThread::kCamera,
                  std::vector<std::pair<std::string, LoopThread>>{
                      {"camera", LoopThread::kCamera}, {"control", LoopThread::kControl}});
    hang.at_s = in.number(key + ".at_s", 0.0, 0.0, 1e6);
    hang.for_s = in.positive(key + ".for_s", 0.0, 3600.0);
    loop->hangs.push_back(hang);
  }
}

}  // namespace

ScenarioText read_scenario_file(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError(path + ": is a directory, expected a scenario YAML file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the scenario file");
  std::stringstream text;
  text << in.rdbuf();
  ScenarioText source;
  source.text = text.str();
  source.name = path;
  source.base_dir = std::filesystem::path(path).parent_path().string();
  if (source.base_dir.empty()) source.base_dir = ".";
  return source;
}

std::pair<std::string, std::string> split_override(const std::string& option) {
  const size_t equals = option.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw InputError("--set " + option + ": expected key=value, such as controller.ts_s=0.05");
  }
  return {option.substr(0, equals), option.substr(equals + 1)};
}

Scenario load_scenario(const ScenarioText& source,
                       const std::vector<std::pair<std::string, std::string>>& overrides) {
  YamlReader in(parse_yaml(source.text, source.name), source.name);
  for (const auto& [key, value] : overrides) in.set_override(key, value);
  refuse_moved_keys(in);

  Scenario s;
  s.source_name = source.name;
  read_run(in, &s);
  read_tape(in, &s);
  read_floor(in, &s);
  read_image_effects(in, &s.effects);
  read_frame_faults(in, &s);
  read_perception(in, &s);
  read_odometry(in, &s.odometry);
  read_camera_and_tags(in, source, &s);
  read_vehicle(in, &s);
  read_controller(in, &s.controller);
  s.metrics.settle_band_e_d_m =
      in.positive("metrics.settle_band_e_d_m", s.metrics.settle_band_e_d_m, 1.0);
  s.metrics.settle_band_e_theta_rad =
      in.positive("metrics.settle_band_e_theta_rad", s.metrics.settle_band_e_theta_rad, 1.0);
  read_loop(in, &s.loop);
  in.finish();
  return s;
}

}  // namespace agv::pipeline
