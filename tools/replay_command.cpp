#include "tools/replay_command.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/recorded_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/open_frame_source.h"
#include "tools/progress_bar.h"
#include "tools/source_report.h"
#include "tools/source_setup.h"

namespace agv::tools {

void add_replay_command(CLI::App& app, ReplayArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "replay",
      "Runs perception and the controller on recorded frames, open loop (the commands it would "
      "have given), as fast as the computer goes: a dataset folder (frames/, manifest.csv, "
      "camera.yaml), a bare folder of images (with --camera and --fps) or a video file (with "
      "--camera). The controller, its period and the vehicle limits come from the scenario "
      "(default: the built-in one). Writes measurements.csv (one row per frame), commands.jsonl "
      "(one command per control period), summary.json (frames, lost, bad, timing, and "
      "perception RMS against the manifest's ground truth when it has one), errors.png, "
      "strip.png and annotated.avi.");
  add_source_options(sub, args);
  sub->add_flag("--skip-bad-frames", args.skip_bad_frames,
                "Count unreadable or wrong-sized frames, report them in summary.json and go on "
                "(default: stop)");
}

int run_replay_command(const ReplayArgs& args) {
  SourceSetup setup = set_up_source(args, args.skip_bad_frames);
  if (setup.opened.source->live()) {
    throw InputError(args.source + ": a live " + setup.opened.kind +
                     " cannot be replayed; track it with agv track");
  }
  pipeline::OutputFolder folder(args.out_dir);
  FrameAnnotator annotator(folder, setup.camera, !args.no_video,
                           1.0 / std::max(1e-3, setup.opened.source->frame_period_s()),
                           setup.opened.source->frame_count());
  pipeline::RecordedRunOptions options;
  options.perception = setup.perception;
  options.sink = annotator.sink();
  pipeline::RunResult result;
  {
    ProgressBar bar("replaying " + args.source, !args.quiet && !args.json);
    result = pipeline::run_on_source(*setup.opened.source, setup.camera, setup.scenario, options,
                                     [&](double f) { bar.update(f); });
  }
  annotator.finish();

  const bool has_truth = setup.opened.has_truth;
  const SourceFigures figures = source_figures(result);
  nlohmann::json summary = source_summary(result, figures, has_truth);
  summary["source"] = args.source;
  summary["source_kind"] = setup.opened.kind;
  summary["camera"] = setup.opened.camera_name;
  summary["scenario"] = setup.scenario.source_name;
  summary["branch"] = args.branch;
  summary["ts_s"] = setup.scenario.controller.ts_s;
  summary["frames_tracked"] = result.perception_counts.tracked;
  summary["frames_searched"] = result.perception_counts.searched;
  write_measurements(folder, result, has_truth);
  write_commands(folder, result);
  {
    std::ofstream json(folder.file("summary.json"));
    json << summary.dump(2) << '\n';
    if (!json) throw InputError(folder.target().string() + ": cannot write the results");
  }
  const std::string failure = plot_measurements(
      folder, result, has_truth, plot_title("replay of", setup.opened.kind, args.source));
  if (!failure.empty()) std::cerr << "agv replay: warning: plot skipped: " << failure << '\n';
  folder.commit();

  if (args.json) {
    summary["output"] = folder.target().string();
    std::cout << summary.dump(2) << '\n';
    return 0;
  }
  std::printf(
      "frames %d | lost %d | bad %d | junctions %d | perception rms %s mm / %s deg | %.2f ms per "
      "frame (median)\n",
      figures.frames, figures.lost, figures.bad, figures.junctions,
      rms_text(figures.error_e_d_m, 1e3).c_str(),
      rms_text(figures.error_e_theta_rad, 180.0 / M_PI).c_str(),
      summary["timing"]["perceive_ms_median"].get<double>());
  std::printf("output: %s\n", folder.target().c_str());
  return 0;
}

}  // namespace agv::tools
