#include "tools/bench_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <nlohmann/json.hpp>

#include "common/angles.h"
#include "control/line_tracker.h"
#include "perception/line_estimator.h"
#include "pipeline/closed_loop.h"
#include "pipeline/frame_renderer.h"
#include "pipeline/scenario_loader.h"
#include "tools/embedded_files.h"

namespace agv::tools {
namespace {

using Clock = std::chrono::steady_clock;

double microseconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(p * (values.size() - 1) + 0.5));
  return values[i];
}

// The detector most line followers use: blur, Canny edges, probabilistic Hough lines.
size_t baseline_canny_hough(const cv::Mat& frame) {
  cv::Mat grey, blurred, edges;
  cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
  cv::GaussianBlur(grey, blurred, cv::Size(5, 5), 1.5);
  cv::Canny(blurred, edges, 50, 150);
  std::vector<cv::Vec4i> lines;
  cv::HoughLinesP(edges, lines, 1.0, CV_PI / 180.0, 50, 50, 10);
  return lines.size();
}

}  // namespace

void add_bench_command(CLI::App& app, BenchArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "bench",
      "Speed benchmark on frames it renders itself (VGA, built-in default scenario, varied poses): "
      "per-frame time of render, perceive (and the usual GaussianBlur + Canny + HoughLinesP "
      "detector "
      "on the same frames), control, and closed-loop frames per second.");
  sub->add_option("--frames", args.frames, "Frames to time")->check(CLI::Range(10, 100000));
  sub->add_option("--threads", args.threads, "OpenCV threads (default 1)")
      ->check(CLI::Range(1, 256));
  sub->add_flag("--json", args.json, "Print one JSON object instead of the table");
}

int run_bench(const BenchArgs& args) {
  cv::setNumThreads(args.threads);
  pipeline::ScenarioText source{embedded_files().at("default_scenario.yaml"),
                                "built-in default scenario", "", embedded_files()};
  const pipeline::Scenario scenario = pipeline::load_scenario(source, {});
  const perception::CameraModel camera =
      perception::camera_model_of(scenario.camera, scenario.camera_name);
  const pipeline::FrameRenderer renderer(camera, pipeline::render_scene(scenario));
  const perception::LineEstimator estimator(camera, pipeline::perception_options(scenario));
  control::LineTracker::Options tracker_options;
  tracker_options.path_speed_m_s = scenario.path_speed_m_s;
  control::LineTracker tracker(pipeline::make_controller(scenario.controller),
                               scenario.vehicle.limits, tracker_options,
                               BodyTwist{scenario.path_speed_m_s, 0.0, 0.0});

  std::vector<double> render_us, perceive_us, baseline_us, control_us;
  cv::RNG rng(12345);
  cv::Mat frame;
  int found = 0;
  for (int i = 0; i < args.frames; ++i) {
    const Pose2 pose{1.0 + 0.003 * i, rng.uniform(-0.03, 0.03),
                     rng.uniform(-deg_to_rad(8), deg_to_rad(8))};
    const Clock::time_point t0 = Clock::now();
    renderer.render_into(pose, BodyTwist{scenario.path_speed_m_s, 0.0, 0.0},
                         static_cast<std::uint64_t>(i), &frame);
    const Clock::time_point t1 = Clock::now();
    const LineMeasurement m = estimator.estimate(frame, 0.1 * i);
    const Clock::time_point t2 = Clock::now();
    tracker.step(m, 0.1 * i);
    const Clock::time_point t3 = Clock::now();
    baseline_canny_hough(frame);
    const Clock::time_point t4 = Clock::now();
    render_us.push_back(microseconds(t0, t1));
    perceive_us.push_back(microseconds(t1, t2));
    control_us.push_back(microseconds(t2, t3));
    baseline_us.push_back(microseconds(t3, t4));
    found += m.line_found ? 1 : 0;
  }

  // The closed loop as `agv simulate` runs it (lockstep), over the same number of periods.
  pipeline::Scenario loop = scenario;
  loop.duration_s = (args.frames - 1) * scenario.controller.ts_s;
  const pipeline::RunResult run = pipeline::run_lockstep(loop);
  const double closed_loop_fps = run.rows.size() / std::max(1e-9, run.wall_s - run.setup_wall_s);

  nlohmann::json j;
  j["frames"] = args.frames;
  j["threads"] = args.threads;
  j["image"] = std::to_string(camera.intrinsics().width_px) + "x" +
               std::to_string(camera.intrinsics().height_px);
  j["line_found_fraction"] = static_cast<double>(found) / args.frames;
  j["render_us_median"] = percentile(render_us, 0.5);
  j["render_us_p99"] = percentile(render_us, 0.99);
  j["perceive_us_median"] = percentile(perceive_us, 0.5);
  j["perceive_us_p99"] = percentile(perceive_us, 0.99);
  j["baseline_canny_hough_us_median"] = percentile(baseline_us, 0.5);
  j["baseline_canny_hough_us_p99"] = percentile(baseline_us, 0.99);
  j["control_us_median"] = percentile(control_us, 0.5);
  j["control_us_p99"] = percentile(control_us, 0.99);
  j["closed_loop_fps"] = closed_loop_fps;
  j["setup_ms"] = 1e3 * run.setup_wall_s;
  if (args.json) {
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::printf("agv bench: %d frames %s, %d thread(s); line found on %d\n", args.frames,
              j["image"].get<std::string>().c_str(), args.threads, found);
  std::printf("%-34s %12s %12s\n", "stage (per frame)", "median_us", "p99_us");
  std::printf("%-34s %12.1f %12.1f\n", "render", percentile(render_us, 0.5),
              percentile(render_us, 0.99));
  std::printf("%-34s %12.1f %12.1f\n", "perceive", percentile(perceive_us, 0.5),
              percentile(perceive_us, 0.99));
  std::printf("%-34s %12.1f %12.1f\n", "baseline blur+Canny+HoughLinesP",
              percentile(baseline_us, 0.5), percentile(baseline_us, 0.99));
  std::printf("%-34s %12.2f %12.2f\n", "control", percentile(control_us, 0.5),
              percentile(control_us, 0.99));
  std::printf(
      "closed loop (render + perceive + control, lockstep): %.0f frames/s (after %.0f ms of "
      "set-up)\n",
      closed_loop_fps, 1e3 * run.setup_wall_s);
  return 0;
}

}  // namespace agv::tools
