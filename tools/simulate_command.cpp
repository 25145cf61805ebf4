#include "tools/simulate_command.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>

#include "common/angles.h"
#include "common/input_error.h"
#include "perception/camera_file.h"
#include "pipeline/config/builtin_files.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/scenario_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/metrics.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/evaluation/trace_csv.h"
#include "tools/build_info.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"
#include "tools/run_plots.h"

namespace agv::tools {
namespace {

std::string format_optional(const std::optional<double>& value, double scale, const char* format) {
  if (!value) return "n/a";
  char text[64];
  std::snprintf(text, sizeof(text), format, *value * scale);
  return text;
}

}  // namespace

void add_simulate_command(CLI::App& app, SimulateArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Closed-loop simulation from camera images: renderer -> perception -> bounded queue -> "
      "controller -> "
      "vehicle. With no options it runs the built-in default scenario (seed 000's Table 1: 0.3 "
      "m/s, "
      "5 deg / 10 mm initial error, Mecanum AGV, finite-step controller). Writes trace.csv, "
      "frames.csv, "
      "summary.json, errors.png and path.png to the output folder and prints a one-line summary.");
  sub->add_option("--scenario", args.scenario_file,
                  "Scenario YAML (every key is shown, with its meaning, in "
                  "pipeline/config/default_scenario.yaml)");
  sub->add_option("--set", args.overrides,
                  "Override one scenario key, e.g. --set path_speed_m_s=0.5 --set "
                  "controller.finite_step.horizon=shrinking")
      ->type_name("KEY=VALUE");
  sub->add_option("--out", args.out_dir, "Output folder (default: runs/<date-time>)");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
  sub->add_flag("--json", args.json,
                "Print summary.json on stdout instead of the summary line, with the output "
                "folder (\"output\")");
  sub->add_flag("--no-plots", args.no_plots, "Skip errors.png and path.png");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
}

int run_simulate(const SimulateArgs& args) {
  const pipeline::Scenario scenario =
      pipeline::load_scenario_for_command(args.scenario_file, args.overrides);

  for (const std::string& warning : pipeline::scenario_warnings(scenario))
    std::cerr << "agv simulate: warning: " << warning << '\n';
  pipeline::OutputFolder folder(args.out_dir, "summary.json", args.force);
  pipeline::RunResult run;
  {
    ProgressBar bar("simulating " + std::to_string(scenario.duration_s).substr(0, 4) + " s",
                    !args.quiet);
    run = pipeline::run_scenario(scenario, [&](double f) { bar.update(f); });
  }
  const pipeline::RunMetrics metrics = pipeline::compute_metrics(run, scenario);
  nlohmann::json summary = pipeline::summary_json(metrics, run, scenario);
  summary["agv"] = build_json();
  summary["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
  {
    std::ofstream trace(folder.file("trace.csv"));
    pipeline::write_trace_csv(trace, run);
    std::ofstream frames(folder.file("frames.csv"));
    pipeline::write_frames_csv(frames, run);
    std::ofstream json(folder.file("summary.json"));
    json << summary.dump(2) << '\n';
    std::ofstream camera(folder.file("camera.yaml"));
    camera << perception::camera_file_text(scenario.camera);
    if (!trace || !frames || !json || !camera)
      throw InputError(folder.target().string() + ": cannot write the results");
  }
  write_path_csv(folder.file("path.csv").string(), scenario.path);
  if (!args.no_plots) {
    const std::string title =
        run.controller_name + ", " + std::to_string(scenario.path_speed_m_s).substr(0, 4) +
        " m/s, latency " + std::to_string(scenario.latency_frames) + " frame(s)";
    const std::string failure = plot_run(folder, scenario, title);
    if (!failure.empty()) std::cerr << "agv simulate: warning: plots skipped: " << failure << '\n';
  }
  folder.commit();

  if (args.json) {
    summary["output"] = folder.target().string();  // where the files are (not in the file)
    std::cout << summary.dump(2) << '\n';
  } else {
    // What happened, in words a person reads: settle time or "never", perception only where
    // the controller used the camera, and a stop for a lost line when there was one.
    char line[640];
    char perception[200] = "pose input (no perception)";
    if (scenario.controller.input == pipeline::ControllerInput::kCamera)
      std::snprintf(
          perception, sizeof(perception), "perception rms %s mm / %s deg | frames lost %d/%d",
          format_optional(metrics.perception_rms_e_d_m, 1e3, "%.3f").c_str(),
          format_optional(metrics.perception_rms_e_theta_rad, 180.0 / M_PI, "%.3f").c_str(),
          metrics.frames_lost, metrics.frames);
    const std::string settle =
        metrics.settle_time_s
            ? "settle " + format_optional(metrics.settle_time_s, 1.0, "%.2f") + " s"
            : std::string("never settled");
    std::snprintf(
        line, sizeof(line),
        "%s (bands %.1f mm / %.1f deg) | max |e_d| %.2f mm, max |e_theta| %.2f deg | %s | "
        "limit violations %d",
        settle.c_str(), 1e3 * scenario.metrics.settle_band_e_d_m,
        rad_to_deg(scenario.metrics.settle_band_e_theta_rad), 1e3 * metrics.max_abs_e_d_m,
        rad_to_deg(metrics.max_abs_e_theta_rad), perception, metrics.limit_violations);
    std::string stops;
    for (size_t i = 0; i < run.rows.size(); ++i) {
      const bool stopping = run.rows[i].output.flags & control::kStopping;
      const bool was = i > 0 && (run.rows[i - 1].output.flags & control::kStopping);
      if (stopping && !was && (run.rows[i].output.flags & control::kLineLost))
        stops += (stops.empty() ? "" : ", ") + format_optional(run.rows[i].t_s, 1.0, "%.1f") + " s";
    }
    if (!stops.empty())
      std::snprintf(line + std::strlen(line), sizeof(line) - std::strlen(line),
                    " | stopped for a lost line at %s", stops.c_str());
    std::cout << line;
    if (run.queue.dropped > 0) std::cout << " | queue dropped " << run.queue.dropped;
    for (const pipeline::WatchdogStall& stall : run.stalls) {
      std::printf(" | watchdog: %s silent %.2f s after %.2f s", stall.thread.c_str(),
                  stall.silent_for_s, stall.last_seen_s);
    }
    std::cout << '\n' << "output: " << folder.target().string() << '\n';
  }
  return 0;
}

}  // namespace agv::tools
