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
  add_source_options(sub, args,
                     "Dataset folder, bare folder of images (with --camera, --fps) or video file "
                     "(with --camera)",
                     /*video_by_default=*/true);
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
  pipeline::OutputFolder folder(args.out_dir, "summary.json", args.force);
  FrameAnnotator annotator(folder, setup, !args.no_video);
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
  write_commands(folder, result);
  const SourceFigures figures = source_figures(result);
  nlohmann::json summary = source_summary(result, figures, setup, args);
  finish_source_run(folder, result, setup, summary, "replay of", "replay", args.json);
  if (args.json) return 0;
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
