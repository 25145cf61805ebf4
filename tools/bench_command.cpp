#include "tools/bench_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include <nlohmann/json.hpp>

#include "common/angles.h"
#include "common/input_error.h"
#include "common/statistics.h"
#include "control/line_tracker.h"
#include "perception/hough_baseline.h"
#include "perception/path_memory.h"
#include "perception/tracking_line_estimator.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/scenario_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/perceiver.h"
#include "pipeline/sim/frame_renderer.h"
#include "tools/build_info.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"

namespace agv::tools {
namespace {

using Clock = std::chrono::steady_clock;

double microseconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

// Per-frame times and errors against the ground truth of one way of measuring a frame.
struct StageRecord {
  std::vector<double> us, error_e_d_m, error_e_theta_rad;
  int found = 0;
  void add(double microseconds, const LineMeasurement& m, const control::TrackingError& truth) {
    us.push_back(microseconds);
    if (!m.line_found) return;
    ++found;
    error_e_d_m.push_back(m.e_d_m - truth.e_d_m);
    error_e_theta_rad.push_back(wrap_angle_rad(m.e_theta_rad - truth.e_theta_rad));
  }
  nlohmann::json json() const {
    return {{"us_median", percentile(us, 0.5)},
            {"us_p99", percentile(us, 0.99)},
            {"found", found},
            {"rms_e_d_m", rms(error_e_d_m)},
            {"rms_e_theta_rad", rms(error_e_theta_rad)}};
  }
};

}  // namespace

void add_bench_command(CLI::App& app, BenchArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "bench",
      "Speed benchmark on the consecutive frames of a closed-loop run of the scenario (default: "
      "the built-in one, VGA): per-frame time (median, p99) and accuracy against the ground truth "
      "of perception as the loop runs it (tracking between full searches, then the path memory "
      "on the frames' wheel odometry), of the line estimator alone, of the path memory alone (on "
      "the line estimator's detections, with the points it holds), of the full search alone, "
      "and of the usual GaussianBlur + Canny + HoughLinesP detector on the same frames; "
      "render and control times; closed-loop frames per second.");
  sub->add_option("--scenario", args.scenario, "Scenario YAML (default: the built-in one)");
  sub->add_option("--set", args.overrides, "Override one scenario key")->type_name("KEY=VALUE");
  sub->add_option("--frames", args.frames, "Frames to time")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  sub->add_option("--threads", args.threads, "OpenCV threads")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  sub->add_flag("--json", args.json, "Print one JSON object instead of the table");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
  sub->add_option("--out", args.out,
                  "Also write the table (bench.txt) and the JSON (bench.json) to this folder");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
}

int run_bench(const BenchArgs& args) {
  // The output folder first: a folder that may not be replaced is refused before the work.
  std::optional<pipeline::OutputFolder> folder;
  if (!args.out.empty()) folder.emplace(args.out, "bench.json", args.force);
  cv::setNumThreads(args.threads);
  const pipeline::Scenario scenario =
      pipeline::load_scenario_for_command(args.scenario, args.overrides);
  const perception::CameraModel camera =
      perception::camera_model_of(scenario.camera, scenario.camera_name);
  const std::unique_ptr<pipeline::FrameRenderer> renderer = pipeline::make_renderer(scenario);

  // A continuous sequence: the poses of the closed loop as `agv simulate` runs it (lockstep).
  pipeline::Scenario loop = scenario;
  loop.duration_s = (args.frames - 1) * pipeline::camera_period_s(scenario);
  loop.loop.mode = pipeline::LoopMode::kLockstep;
  std::vector<Pose2> poses;
  std::vector<BodyTwist> twists;
  std::vector<std::optional<Pose2>> odometry;
  std::vector<control::TrackingError> truths;
  const pipeline::RunResult run = pipeline::run_scenario(
      loop, {},
      [&](const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
          const perception::LineDetection*) {
        poses.push_back(*frame.pose);
        twists.push_back(frame.twist);
        odometry.push_back(frame.odometry);
        truths.push_back(*record.truth);
      });
  const double closed_loop_fps = run.rows.size() / std::max(1e-9, run.wall_s - run.setup_wall_s);

  // The closed loop as lockstep runs it: render, perceive (tracking between full searches, then
  // the path memory on the frame's wheel odometry, when the scenario has one), control, and
  // nothing else between two steps (the comparisons below run between them left each step's
  // caches colder than the loop leaves them). Then the same frames, rendered again, measured apart:
  // the line estimator alone (tracking between searches), the path memory alone on its
  // detections and the frames' wheel odometry (what the loop adds to the line estimator; timed
  // only where the scenario has odometry), the full search alone, and the Canny + HoughLinesP
  // baseline. The two alternate in blocks of kBlockFrames frames, so that a change in the
  // machine's speed during the run (other programs on it) moves both alike.
  constexpr size_t kBlockFrames = 10;
  perception::LineEstimator::Options options = pipeline::perception_options(scenario);
  options.tracking = true;
  pipeline::ImagePerceiver loop_perception(camera, options, scenario.perception_path_memory);
  control::LineTracker tracker = pipeline::make_tracker(scenario, scenario.controller.ts_s);
  perception::TrackingLineEstimator tracking(camera, options);
  const perception::LineEstimator full_search(camera, options);
  const perception::HoughBaseline baseline(camera, options.tape.width_m);
  perception::PathMemory memory;
  std::vector<double> memory_points;
  StageRecord perceived, tracked, remembered, searched, hough;
  std::vector<double> render_us, control_us, step_us;
  cv::Mat frame;
  ProgressBar bar("timing " + std::to_string(poses.size()) + " frames", !args.quiet && !args.json);
  const auto frame_time_s = [&](size_t i) { return i * pipeline::camera_period_s(scenario); };
  for (size_t block = 0; block < poses.size(); block += kBlockFrames) {
    bar.update(static_cast<double>(block) / poses.size());
    const size_t end = std::min(poses.size(), block + kBlockFrames);
    for (size_t i = block; i < end; ++i) {
      const Clock::time_point t0 = Clock::now();
      renderer->render_into(poses[i], twists[i], static_cast<std::uint64_t>(i), &frame);
      const Clock::time_point t1 = Clock::now();
      pipeline::SourceFrame source_frame;
      source_frame.index = i;
      source_frame.t_s = frame_time_s(i);
      source_frame.image = frame;
      source_frame.pose = poses[i];
      source_frame.twist = twists[i];
      source_frame.odometry = odometry[i];
      const LineMeasurement m = loop_perception.measure(source_frame, nullptr);
      const Clock::time_point t2 = Clock::now();
      tracker.step(m, frame_time_s(i));
      const Clock::time_point t3 = Clock::now();
      render_us.push_back(microseconds(t0, t1));
      perceived.add(microseconds(t1, t2), m, truths[i]);
      control_us.push_back(microseconds(t2, t3));
      step_us.push_back(microseconds(t0, t3));
    }
    for (size_t i = block; i < end; ++i) {
      const double t = frame_time_s(i);
      renderer->render_into(poses[i], twists[i], static_cast<std::uint64_t>(i), &frame);
      const Clock::time_point t0 = Clock::now();
      perception::LineDetection detection;
      const LineMeasurement m_tracked = tracking.measure(frame, t, &detection);
      const Clock::time_point t1 = Clock::now();
      if (scenario.perception_path_memory && odometry[i]) {
        const LineMeasurement m_memory = memory.update(m_tracked, detection, odometry[i]);
        remembered.add(microseconds(t1, Clock::now()), m_memory, truths[i]);
        memory_points.push_back(static_cast<double>(memory.size()));
      }
      const Clock::time_point t2 = Clock::now();
      const LineMeasurement m_full = full_search.estimate(frame, t);
      const Clock::time_point t3 = Clock::now();
      const LineMeasurement m_hough = baseline.estimate(frame, t);
      const Clock::time_point t4 = Clock::now();
      tracked.add(microseconds(t0, t1), m_tracked, truths[i]);
      searched.add(microseconds(t2, t3), m_full, truths[i]);
      hough.add(microseconds(t3, t4), m_hough, truths[i]);
    }
  }
  bar.finish();
  const int frames = static_cast<int>(poses.size());
  const double baseline_median_us = percentile(hough.us, 0.5);
  const double speedup = baseline_median_us / std::max(1e-9, percentile(perceived.us, 0.5));

  nlohmann::json j;
  j["scenario"] = scenario.source_name;
  j["frames"] = frames;
  j["threads"] = args.threads;
  j["image"] = std::to_string(camera.intrinsics().width_px) + "x" +
               std::to_string(camera.intrinsics().height_px);
  j["render_us_median"] = percentile(render_us, 0.5);
  j["render_us_p99"] = percentile(render_us, 0.99);
  // The keys of DESIGN.md ("Speed figures"), then the detail.
  j["perceive_us_median"] = percentile(perceived.us, 0.5);
  j["perceive_us_p99"] = percentile(perceived.us, 0.99);
  j["baseline_canny_hough_us_median"] = baseline_median_us;
  j["perceive"] = perceived.json();
  j["perceive"]["frames_tracked"] = loop_perception.counts().tracked;
  j["perceive"]["path_memory"] = scenario.perception_path_memory;
  j["perceive_line_estimator"] = tracked.json();
  j["perceive_line_estimator"]["frames_tracked"] = tracking.counts().tracked;
  j["baseline_over_line_estimator_median"] =
      baseline_median_us / std::max(1e-9, percentile(tracked.us, 0.5));
  if (!remembered.us.empty()) {
    j["perceive_path_memory"] = remembered.json();
    j["perceive_path_memory"]["points_median"] = percentile(memory_points, 0.5);
  }
  j["perceive_full_search"] = searched.json();
  j["baseline_canny_hough"] = hough.json();
  j["baseline_over_perceive_median"] = speedup;
  j["full_search_over_baseline_median"] =
      percentile(searched.us, 0.5) / std::max(1e-9, baseline_median_us);
  j["full_search_over_baseline_p99"] =
      percentile(searched.us, 0.99) / std::max(1e-9, percentile(hough.us, 0.99));
  j["perceive_p99_over_baseline_median"] =
      percentile(perceived.us, 0.99) / std::max(1e-9, baseline_median_us);
  j["control_us_median"] = percentile(control_us, 0.5);
  j["control_us_p99"] = percentile(control_us, 0.99);
  j["closed_loop_step_us_median"] = percentile(step_us, 0.5);
  j["closed_loop_step_over_baseline_median"] =
      percentile(step_us, 0.5) / std::max(1e-9, baseline_median_us);
  j["closed_loop_fps"] = closed_loop_fps;
  j["setup_ms"] = 1e3 * run.setup_wall_s;
  j["peak_rss_mb"] = peak_rss_mb();
  j["agv"] = build_json();

  std::string table;
  auto line = [&table](const std::string& text) { table += text + "\n"; };
  line(cv::format("agv bench: %d consecutive frames %s of the closed loop (%s), %d thread(s)",
                  frames, j["image"].get<std::string>().c_str(), scenario.source_name.c_str(),
                  args.threads));
  line(cv::format("%-44s %10s %10s %7s %10s %10s", "stage (per frame)", "median_us", "p99_us",
                  "found", "rms_e_d_mm", "rms_e_th_deg"));
  auto row = [&](const char* name, const StageRecord& r) {
    line(cv::format("%-44s %10.1f %10.1f %7d %10.3f %10.3f", name, percentile(r.us, 0.5),
                    percentile(r.us, 0.99), r.found, 1e3 * rms(r.error_e_d_m),
                    rad_to_deg(rms(r.error_e_theta_rad))));
  };
  line(cv::format("%-44s %10.1f %10.1f", "render", percentile(render_us, 0.5),
                  percentile(render_us, 0.99)));
  row(scenario.perception_path_memory ? "perceive as the loop runs it (+ path memory)"
                                      : "perceive as the loop runs it",
      perceived);
  row("  line estimator alone (tracking)", tracked);
  if (!remembered.us.empty())
    row(cv::format("  path memory alone (%.0f points)", percentile(memory_points, 0.5)).c_str(),
        remembered);
  row("  full search only", searched);
  row("baseline blur+Canny+HoughLinesP", hough);
  line(cv::format("%-44s %10.2f %10.2f", "control", percentile(control_us, 0.5),
                  percentile(control_us, 0.99)));
  line(cv::format("%-44s %10.1f %10.1f", "closed-loop step (render + perceive + control)",
                  percentile(step_us, 0.5), percentile(step_us, 0.99)));
  line(cv::format(
      "baseline / perceive (median): %.1fx (line estimator alone %.1fx); perceive p99 / "
      "baseline median: %.2f; full search / baseline: %.2f (median), %.2f (p99); tracked %d of "
      "%d frames",
      speedup, j["baseline_over_line_estimator_median"].get<double>(),
      j["perceive_p99_over_baseline_median"].get<double>(),
      j["full_search_over_baseline_median"].get<double>(),
      j["full_search_over_baseline_p99"].get<double>(), loop_perception.counts().tracked, frames));
  line(
      cv::format("closed-loop step / baseline (median): %.2f; closed loop (lockstep): %.0f "
                 "frames/s (after %.0f ms of set-up); peak RSS %.0f MB",
                 j["closed_loop_step_over_baseline_median"].get<double>(), closed_loop_fps,
                 1e3 * run.setup_wall_s, j["peak_rss_mb"].get<double>()));
  if (folder) {
    std::ofstream(folder->file("bench.txt")) << table;
    std::ofstream json(folder->file("bench.json"));
    json << j.dump(2) << '\n';
    if (!json) throw InputError(folder->target().string() + ": cannot write bench.json");
    folder->commit();
    j["output"] = folder->target().string();
  }
  if (args.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << table;
    if (folder) std::cout << "output: " << folder->target().string() << '\n';
  }
  return 0;
}

}  // namespace agv::tools
