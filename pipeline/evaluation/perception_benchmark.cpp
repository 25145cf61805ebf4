#include "pipeline/evaluation/perception_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <utility>

#include "common/angles.h"
#include "common/statistics.h"
#include "perception/hough_baseline.h"
#include "perception/line_estimator.h"
#include "pipeline/evaluation/frame_annotation.h"
#include "pipeline/evaluation/random_conditions.h"
#include "pipeline/sim/frame_renderer.h"

namespace agv::pipeline {
namespace {

struct Draw {
  perception::CameraModel camera;
  Scene scene;
  perception::LineEstimator::Options perception;
  bool curved = false;
  double radius_m = 0.0;
  std::string text;
};

Draw draw_condition(cv::RNG& rng, bool with_tape, std::uint64_t seed) {
  const RandomCamera camera = draw_camera(rng);
  Draw d{camera.camera, {}, {}, false, 0.0, {}};
  const double height = camera.height_m, tilt = camera.tilt_rad;
  Scene& scene = d.scene;
  scene.seed = seed;
  const bool light_floor = draw_floor_and_light(rng, &scene);
  const ImageEffects& fx = scene.effects;

  TapeStrip tape;
  tape.width_m = rng.uniform(0.010, 0.050);
  tape.color_bgr = draw_tape_colour(rng, scene.floor.color_bgr);
  tape.wear = rng.uniform(0.0, 1.0) < 0.2 ? rng.uniform(0.0, 0.1) : 0.0;
  d.curved = rng.uniform(0.0, 1.0) < 0.4;
  if (d.curved) {
    // A long arc through the origin's neighbourhood, turning either way.
    d.radius_m = std::exp(rng.uniform(std::log(0.3), std::log(3.0)));
    const double sweep = std::min(1.9 * kPi, 4.0 / d.radius_m);
    const double turn = rng.uniform(0.0, 1.0) < 0.5 ? 1.0 : -1.0;
    tape.path = control::Path::starting_at({-0.5 * sweep * d.radius_m, 0.0, 0.0})
                    .add_arc(d.radius_m, turn * sweep);
  } else {
    tape.path = control::Path::starting_at({-2.0, 0.0, 0.0}).add_line(6.0);
  }
  if (with_tape) {
    scene.tapes.push_back(tape);
  } else {
    // No tape in view: the path lies far away (the floor, light and noise still vary).
    tape.path = control::Path::starting_at({100.0, 100.0, 0.0}).add_line(1.0);
    scene.tapes.push_back(tape);
  }
  d.perception.tape.width_m = tape.width_m;
  if (rng.uniform(0.0, 1.0) < 0.5)
    d.perception.tape.color_bgr = tape.color_bgr;  // half without hint
  char text[256];
  std::snprintf(text, sizeof(text), "h%.2f tilt%.1f width%.0fmm %s %s noise%.1f exp%.0fms%s%s%s",
                height, rad_to_deg(tilt), 1e3 * tape.width_m,
                d.curved ? ("R" + std::to_string(d.radius_m).substr(0, 4)).c_str() : "straight",
                light_floor ? "light-floor" : "dark-floor", fx.noise_sigma, 1e3 * fx.exposure_s,
                fx.shadow_darkness > 0 ? " shadow" : "", fx.specular_strength > 0 ? " glare" : "",
                d.perception.tape.color_bgr ? " hint" : "");
  d.text = text;
  return d;
}

// Length of the path's centre line seen in the image, by sampling it every millimetre.
double visible_length_m(const control::Path& path, const Pose2& pose,
                        const perception::CameraModel& camera, double s_centre) {
  const Pose2 to_vehicle = pose.inverse();
  const int w = camera.intrinsics().width_px, h = camera.intrinsics().height_px;
  double length = 0.0;
  for (double s = std::max(0.0, s_centre - 0.8); s <= std::min(path.length_m(), s_centre + 0.8);
       s += 0.001) {
    const auto pixel = camera.floor_to_pixel(to_vehicle.transform(path.point_at(s)));
    if (pixel && pixel->x >= 0 && pixel->y >= 0 && pixel->x <= w - 1 && pixel->y <= h - 1)
      length += 0.001;
  }
  return length;
}

// The q-quantile of the magnitudes.
double quantile(std::vector<double> v, double q) {
  for (double& x : v) x = std::abs(x);
  return percentile(std::move(v), q);
}

}  // namespace

NearEvidenceError error_at_nearest_evidence(const perception::LineDetection& detection,
                                            const control::Path& path, const Pose2& pose,
                                            double s_hint_m) {
  const perception::DetectedLine& line = detection.lines[detection.followed];
  const Eigen::Vector2d a = line.model.point_at(line.s_min_m),
                        b = line.model.point_at(line.s_max_m);
  const Eigen::Vector2d nearest_evidence = a.norm() <= b.norm() ? a : b;
  const perception::CurveModel& model = detection.followed_model;
  const double s_m = model.arc_position(nearest_evidence);
  const Eigen::Vector2d on_line = pose.transform(model.point_at(s_m));
  const Eigen::Vector2d ahead = model.tangent_at(s_m);
  const double yaw = pose.yaw_rad + std::atan2(ahead.y(), ahead.x());
  const Pose2 probe{on_line.x(), on_line.y(), yaw};
  const control::TrackingError error =
      path.tracking_error(probe, path.project(on_line, s_hint_m, 0.8));
  return {error.e_d_m, error.e_theta_rad};
}

namespace {

// A pose near the path (on it at a random place, offset and turned; anywhere without tape) and
// the vehicle's twist, drawn in this order.
struct DrawnPose {
  Pose2 pose;
  BodyTwist twist;
  double s_m = 0.0;
};

DrawnPose draw_pose(cv::RNG& rng, const control::Path& path, bool with_tape) {
  const double s = path.length_m() * rng.uniform(0.35, 0.65);
  const double e_d = rng.uniform(-0.03, 0.03), e_theta = deg_to_rad(rng.uniform(-8.0, 8.0));
  const Eigen::Vector2d foot =
      with_tape ? path.point_at(s)
                : Eigen::Vector2d(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
  const double heading = with_tape ? path.heading_at(s) : rng.uniform(-kPi, kPi);
  const Eigen::Vector2d p = foot + e_d * Eigen::Vector2d(-std::sin(heading), std::cos(heading));
  const Pose2 pose{p.x(), p.y(), wrap_angle_rad(heading + e_theta)};
  const BodyTwist twist{rng.uniform(0.0, 1.0), rng.uniform(-0.05, 0.05), rng.uniform(-0.2, 0.2)};
  return {pose, twist, s};
}

// What one condition measures with: its renderer, our estimator and the baseline.
struct ConditionTools {
  const Draw& draw;
  const FrameRenderer& renderer;
  const perception::LineEstimator& estimator;
  const perception::HoughBaseline& baseline;
  double full_view_m;  // the longest the tape could be in view
};

// One frame at the drawn pose: both detectors' times and errors against the truth.
BenchmarkFrame measure_frame(const ConditionTools& tools, const DrawnPose& drawn, int frame_index,
                             bool with_tape, cv::Mat* frame, perception::LineDetection* detection,
                             LineMeasurement* m) {
  const control::Path& path = tools.draw.scene.tapes.front().path;
  *frame = tools.renderer.render(drawn.pose, drawn.twist, static_cast<std::uint64_t>(frame_index));
  const auto t0 = std::chrono::steady_clock::now();
  *m = tools.estimator.estimate(*frame, 0.0, detection);
  BenchmarkFrame b;
  b.perceive_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const auto t1 = std::chrono::steady_clock::now();
  const LineMeasurement mb = tools.baseline.estimate(*frame, 0.0);
  b.baseline_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  b.baseline_found = mb.line_found;
  b.has_tape = with_tape;
  b.curved = tools.draw.curved;
  b.line_found = m->line_found;
  b.conditions_text = tools.draw.text;
  if (!with_tape) return b;
  const control::PathProjection foot_now = path.project(drawn.pose.translation(), drawn.s_m, 0.5);
  const control::TrackingError truth = path.tracking_error(drawn.pose, foot_now);
  b.visible_fraction = std::min(
      1.0, visible_length_m(path, drawn.pose, tools.draw.camera, drawn.s_m) / tools.full_view_m);
  if (m->line_found) {
    b.error_e_d_m = m->e_d_m - truth.e_d_m;
    b.error_e_theta_rad = wrap_angle_rad(m->e_theta_rad - truth.e_theta_rad);
    const NearEvidenceError near =
        error_at_nearest_evidence(*detection, path, drawn.pose, drawn.s_m);
    b.near_error_offset_m = near.offset_m;
    b.near_error_heading_rad = near.heading_rad;
  }
  if (mb.line_found) {
    b.baseline_error_e_d_m = mb.e_d_m - truth.e_d_m;
    b.baseline_error_e_theta_rad = wrap_angle_rad(mb.e_theta_rad - truth.e_theta_rad);
  }
  return b;
}

// A frame that should have shown its line within 1 mm / 0.5 deg and did not, or a line where
// there is no tape.
bool failed(const BenchmarkFrame& b) {
  return (b.has_tape && b.visible_fraction >= 0.5 &&
          (!b.line_found || std::abs(b.error_e_d_m) > 0.001 ||
           std::abs(b.error_e_theta_rad) > deg_to_rad(0.5))) ||
         (!b.has_tape && b.line_found);
}

// The figures of summary.json: accuracy on frames showing at least half the tape, detection on
// those, false lines, and the same for the baseline.
nlohmann::json summarise(const std::vector<BenchmarkFrame>& frames, std::uint64_t seed) {
  std::vector<double> d_all, t_all, d_straight, t_straight, d_arc, t_arc, times;
  std::vector<double> near_d, near_t;
  std::vector<double> baseline_d, baseline_t, baseline_times;
  int qualifying = 0, found = 0, empty = 0, false_lines = 0, partial = 0, partial_found = 0;
  int baseline_found = 0, baseline_false_lines = 0;
  for (const BenchmarkFrame& b : frames) {
    times.push_back(b.perceive_ms);
    baseline_times.push_back(b.baseline_ms);
    if (!b.has_tape) {
      ++empty;
      false_lines += b.line_found ? 1 : 0;
      baseline_false_lines += b.baseline_found ? 1 : 0;
      continue;
    }
    if (b.visible_fraction < 0.5) {
      ++partial;
      partial_found += b.line_found ? 1 : 0;
      continue;
    }
    ++qualifying;
    if (b.baseline_found) {
      ++baseline_found;
      baseline_d.push_back(b.baseline_error_e_d_m);
      baseline_t.push_back(b.baseline_error_e_theta_rad);
    }
    if (!b.line_found) continue;
    ++found;
    d_all.push_back(b.error_e_d_m);
    t_all.push_back(b.error_e_theta_rad);
    near_d.push_back(b.near_error_offset_m);
    near_t.push_back(b.near_error_heading_rad);
    (b.curved ? d_arc : d_straight).push_back(b.error_e_d_m);
    (b.curved ? t_arc : t_straight).push_back(b.error_e_theta_rad);
  }
  nlohmann::json j;
  j["seed"] = seed;
  j["frames"] = frames.size();
  j["frames_half_visible"] = qualifying;
  j["found_fraction"] = qualifying ? static_cast<double>(found) / qualifying : 0.0;
  j["rms_e_d_m"] = rms(d_all);
  j["rms_e_theta_rad"] = rms(t_all);
  j["p95_abs_e_d_m"] = quantile(d_all, 0.95);
  j["p95_abs_e_theta_rad"] = quantile(t_all, 0.95);
  j["straight"] = {{"frames", d_straight.size()},
                   {"rms_e_d_m", rms(d_straight)},
                   {"rms_e_theta_rad", rms(t_straight)}};
  j["arcs"] = {
      {"frames", d_arc.size()}, {"rms_e_d_m", rms(d_arc)}, {"rms_e_theta_rad", rms(t_arc)}};
  j["at_nearest_evidence"] = {{"rms_offset_m", rms(near_d)},
                              {"rms_heading_rad", rms(near_t)},
                              {"p95_abs_offset_m", quantile(near_d, 0.95)},
                              {"p95_abs_heading_rad", quantile(near_t, 0.95)}};
  j["frames_less_than_half_visible"] = partial;
  j["found_fraction_less_than_half_visible"] =
      partial ? static_cast<double>(partial_found) / partial : 0.0;
  j["frames_without_tape"] = empty;
  j["lines_reported_without_tape"] = false_lines;
  j["perceive_ms_median"] = quantile(times, 0.5);
  j["baseline_canny_hough"] = {
      {"found_fraction", qualifying ? static_cast<double>(baseline_found) / qualifying : 0.0},
      {"rms_e_d_m", rms(baseline_d)},
      {"rms_e_theta_rad", rms(baseline_t)},
      {"p95_abs_e_d_m", quantile(baseline_d, 0.95)},
      {"p95_abs_e_theta_rad", quantile(baseline_t, 0.95)},
      {"lines_reported_without_tape", baseline_false_lines},
      {"ms_median", quantile(baseline_times, 0.5)}};
  return j;
}

}  // namespace

PerceptionBenchmarkResult run_perception_benchmark(const PerceptionBenchmarkOptions& options,
                                                   const std::function<void(double)>& progress) {
  PerceptionBenchmarkResult result;
  cv::RNG rng(options.seed * 2654435761u + 99);
  int saved = 0;
  if (!options.save_failures_dir.empty())
    std::filesystem::create_directories(options.save_failures_dir);
  const int total = options.conditions + options.empty_conditions;
  for (int c = 0; c < total; ++c) {
    const bool with_tape = c < options.conditions;
    const Draw draw = draw_condition(rng, with_tape, options.seed * 1000 + c);
    const FrameRenderer renderer(draw.camera, draw.scene);
    const perception::LineEstimator estimator(draw.camera, draw.perception);
    const perception::HoughBaseline baseline(draw.camera, draw.perception.tape.width_m);
    // The longest the tape could be in view: through the image centre along the image's longer
    // extent, about the floor view's diameter in the forward direction.
    const ConditionTools tools{draw, renderer, estimator, baseline,
                               2.0 * renderer.floor_map().view_radius_m() * 0.8};
    for (int f = 0; f < options.frames_per_condition; ++f) {
      const DrawnPose drawn = draw_pose(rng, draw.scene.tapes.front().path, with_tape);
      cv::Mat frame;
      perception::LineDetection detection;
      LineMeasurement m;
      BenchmarkFrame b = measure_frame(tools, drawn, f, with_tape, &frame, &detection, &m);
      b.condition = c;
      result.frames.push_back(b);
      if (failed(b) && !options.save_failures_dir.empty() && saved < options.max_saved) {
        char name[96], caption[128];
        std::snprintf(name, sizeof(name), "/condition%03d_frame%02d.png", c, f);
        std::snprintf(caption, sizeof(caption), "c%d f%d error %.2f mm %.2f deg | %s", c, f,
                      1e3 * b.error_e_d_m, rad_to_deg(b.error_e_theta_rad), draw.text.c_str());
        cv::imwrite(options.save_failures_dir + name,
                    annotate_frame(frame, draw.camera, detection, m, caption));
        ++saved;
      }
    }
    if (progress) progress(static_cast<double>(c + 1) / total);
  }
  result.summary = summarise(result.frames, options.seed);
  return result;
}

}  // namespace agv::pipeline
