#include "tools/evaluate_command.h"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

#include "common/angles.h"
#include "common/input_error.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/evaluation/perception_benchmark.h"
#include "tools/build_info.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"

namespace agv::tools {

void add_evaluate_command(CLI::App& app, EvaluateArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "evaluate",
      "Perception accuracy over randomised rendered frames: tape colours and polarities, widths "
      "10-50 mm, floors, lighting, shadow, glare, noise, motion blur, camera height and tilt, lens "
      "distortion, straight tape and arcs of 0.3-3 m radius, plus frames without tape. Prints "
      "the detection rate on frames showing at least half the tape, their RMS errors at the "
      "vehicle's origin (e_d, e_theta as DESIGN.md defines them) and at the nearest evidence "
      "(before the line is carried back to the origin), the lines reported where there is no "
      "tape; and the detection rate, errors at the origin and lines without tape of the usual "
      "blur + Canny + HoughLinesP detector on the same frames.");
  sub->add_option("--conditions", args.conditions, "Random draws of camera, floor, tape and light")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  sub->add_option("--frames-per-condition", args.frames_per_condition, "Poses per draw")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sub->add_option("--empty-conditions", args.empty_conditions, "Draws without tape")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  sub->add_option("--seed", args.seed, "Seed (same seed, same frames)")->capture_default_str();
  sub->add_option("--out", args.out_dir, "Also write frames.csv and summary.json to this folder");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
  sub->add_option(
      "--save-failures", args.save_failures,
      "Write annotated frames that were missed, off by more than 1 mm / 0.5 deg, or gave a line "
      "without tape, to this folder (at most 60)");
  sub->add_flag("--json", args.json, "Print the summary as JSON");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
}

int run_evaluate(const EvaluateArgs& args) {
  pipeline::PerceptionBenchmarkOptions options;
  options.conditions = args.conditions;
  options.frames_per_condition = args.frames_per_condition;
  options.empty_conditions = args.empty_conditions;
  options.seed = args.seed;
  options.save_failures_dir = args.save_failures;
  // The output folder first: a folder that may not be replaced is refused before the work.
  std::optional<pipeline::OutputFolder> folder;
  if (!args.out_dir.empty()) folder.emplace(args.out_dir, "summary.json", args.force);
  pipeline::PerceptionBenchmarkResult result;
  {
    ProgressBar bar("evaluating perception", !args.quiet);
    result = pipeline::run_perception_benchmark(options, [&](double f) { bar.update(f); });
  }
  nlohmann::json j = result.summary;
  j["agv"] = build_json();
  j["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
  if (folder) {
    std::ofstream csv(folder->file("frames.csv"));
    csv << "condition,has_tape,curved,visible_fraction,line_found,error_e_d_m,error_e_theta_rad,"
           "near_error_offset_m,near_error_heading_rad,perceive_ms,baseline_found,baseline_error_e_"
           "d_m,baseline_error_e_theta_rad,baseline_ms,"
           "conditions\n"
        << std::setprecision(9);
    for (const pipeline::BenchmarkFrame& b : result.frames) {
      csv << b.condition << ',' << b.has_tape << ',' << b.curved << ',' << b.visible_fraction << ','
          << b.line_found << ',' << b.error_e_d_m << ',' << b.error_e_theta_rad << ','
          << b.near_error_offset_m << ',' << b.near_error_heading_rad << ',' << b.perceive_ms << ','
          << b.baseline_found << ',' << b.baseline_error_e_d_m << ','
          << b.baseline_error_e_theta_rad << ',' << b.baseline_ms << ',' << b.conditions_text
          << '\n';
    }
    std::ofstream(folder->file("summary.json")) << j.dump(2) << '\n';
    if (!csv) throw InputError(folder->target().string() + ": cannot write the results");
    folder->commit();
  }
  if (args.json) {
    if (folder) j["output"] = folder->target().string();
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::printf(
      "frames %d (%d show at least half the tape) | found %.1f %% | RMS e_d %.3f mm, e_theta %.3f "
      "deg "
      "(p95 %.3f mm, %.3f deg) | straight %d: %.3f mm %.3f deg | arcs %d: %.3f mm %.3f deg | "
      "without tape: %d lines in %d frames | %.2f ms per frame\n"
      "the same found frames at the nearest evidence (before extrapolation to the vehicle's "
      "origin): RMS offset %.3f mm, heading %.3f deg (p95 %.3f mm, %.3f deg)\n",
      j["frames"].get<int>(), j["frames_half_visible"].get<int>(),
      100.0 * j["found_fraction"].get<double>(), 1e3 * j["rms_e_d_m"].get<double>(),
      rad_to_deg(j["rms_e_theta_rad"].get<double>()), 1e3 * j["p95_abs_e_d_m"].get<double>(),
      rad_to_deg(j["p95_abs_e_theta_rad"].get<double>()), j["straight"]["frames"].get<int>(),
      1e3 * j["straight"]["rms_e_d_m"].get<double>(),
      rad_to_deg(j["straight"]["rms_e_theta_rad"].get<double>()), j["arcs"]["frames"].get<int>(),
      1e3 * j["arcs"]["rms_e_d_m"].get<double>(),
      rad_to_deg(j["arcs"]["rms_e_theta_rad"].get<double>()),
      j["lines_reported_without_tape"].get<int>(), j["frames_without_tape"].get<int>(),
      j["perceive_ms_median"].get<double>(),
      1e3 * j["at_nearest_evidence"]["rms_offset_m"].get<double>(),
      rad_to_deg(j["at_nearest_evidence"]["rms_heading_rad"].get<double>()),
      1e3 * j["at_nearest_evidence"]["p95_abs_offset_m"].get<double>(),
      rad_to_deg(j["at_nearest_evidence"]["p95_abs_heading_rad"].get<double>()));
  const nlohmann::json& base = j["baseline_canny_hough"];
  std::printf(
      "baseline Canny+HoughLinesP on the same frames: found %.1f %% | RMS e_d %.3f mm, e_theta "
      "%.3f deg (p95 %.3f mm, %.3f deg) | without tape: %d lines | %.2f ms per frame\n",
      100.0 * base["found_fraction"].get<double>(), 1e3 * base["rms_e_d_m"].get<double>(),
      rad_to_deg(base["rms_e_theta_rad"].get<double>()), 1e3 * base["p95_abs_e_d_m"].get<double>(),
      rad_to_deg(base["p95_abs_e_theta_rad"].get<double>()),
      base["lines_reported_without_tape"].get<int>(), base["ms_median"].get<double>());
  return 0;
}

}  // namespace agv::tools
