#include "tools/track_command.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "common/statistics.h"
#include "pipeline/command_stream.h"
#include "pipeline/config/recorded_run.h"
#include "pipeline/evaluation/output_folder.h"
#include "tools/progress_bar.h"
#include "tools/source_report.h"
#include "tools/source_setup.h"
#include "tools/tape_width_check.h"

namespace agv::tools {
namespace {

std::atomic<bool> stop_requested{false};

// The first Ctrl-C (or SIGTERM) asks the run to stop cleanly; a second one ends the program.
extern "C" void request_stop(int signal_number) {
  stop_requested.store(true);
  std::signal(signal_number, SIG_DFL);
}

// Installs request_stop for the lifetime of the object.
class StopOnSignal {
 public:
  StopOnSignal() {
    stop_requested.store(false);
    previous_int_ = std::signal(SIGINT, request_stop);
    previous_term_ = std::signal(SIGTERM, request_stop);
  }
  ~StopOnSignal() {
    std::signal(SIGINT, previous_int_);
    std::signal(SIGTERM, previous_term_);
  }

 private:
  void (*previous_int_)(int);
  void (*previous_term_)(int);
};

// Measurement ages (from the frame's capture to the control period that first acts on it) and
// the command rate of a run.
nlohmann::json tracking_figures(const pipeline::RunResult& result) {
  std::vector<double> ages_s;
  for (const pipeline::TraceRow& row : result.rows)
    if (row.measurement_arrived) ages_s.push_back(row.measurement_age_s);
  const double span_s =
      result.rows.size() > 1 ? result.rows.back().t_s - result.rows.front().t_s : 0.0;
  nlohmann::json stalls = nlohmann::json::array();
  for (const pipeline::WatchdogStall& stall : result.stalls) {
    stalls.push_back({{"thread", stall.thread},
                      {"last_seen_s", stall.last_seen_s},
                      {"silent_for_s", stall.silent_for_s}});
  }
  return {{"measurement_age_s_median", percentile(ages_s, 0.5)},
          {"measurement_age_s_p99", percentile(ages_s, 0.99)},
          {"commands_per_s", span_s > 0.0 ? (result.rows.size() - 1) / span_s : 0.0},
          {"max_tick_lateness_s", result.max_tick_lateness_s},
          {"watchdog_stalls", stalls}};
}

}  // namespace

void add_track_command(CLI::App& app, TrackArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "track",
      "Real-time tracking from a live camera or a recording: perception on the frames the "
      "source gives (frames it cannot keep up with are dropped and counted), the controller every "
      "controller.ts_s of the scenario, and one JSON command per period into commands.jsonl "
      "and, with --udp, to a vehicle computer. SOURCE is a V4L2 device (/dev/video0 or an index), "
      "a GStreamer pipeline ending in appsink, a network stream URL, a video file (played at its "
      "own frame rate), a dataset or an image folder. Ctrl-C, --duration or the end of the "
      "source stop it cleanly: the vehicle is braked within its limits and the last command is "
      "a stop; a source that stalls is reported by the watchdog and the vehicle is stopped. "
      "Writes measurements.csv, commands.jsonl, summary.json, errors.png and strip.png.");
  add_source_options(sub, args,
                     "/dev/videoN or a device index, a GStreamer pipeline (with '!'), a stream "
                     "URL, a video file, a dataset or an image folder",
                     /*video_by_default=*/false);
  sub->add_option("--duration", args.duration_s, "Stop after this many seconds of the source")
      ->check(CLI::PositiveNumber);
  sub->add_option("--udp", args.udp,
                  "Also send each command as one UDP datagram of JSON to HOST:PORT");
  sub->add_flag("--as-fast-as-possible", args.as_fast_as_possible,
                "A recording: do not wait for each frame's time (lockstep on the frames' clock)");
}

int run_track_command(const TrackArgs& args) {
  SourceSetup setup = set_up_source(args, /*pass_bad_frames=*/false);
  pipeline::FrameSource& source = *setup.opened.source;
  if (args.as_fast_as_possible && source.live())
    throw InputError("--as-fast-as-possible: " + args.source + " is a live " + setup.opened.kind +
                     "; its frames come when they come");
  pipeline::OutputFolder folder(args.out_dir, "summary.json", args.force);
  pipeline::CommandStream commands(folder.file("commands.jsonl"), args.udp);
  FrameAnnotator annotator(folder, setup, args.video);
  pipeline::RecordedRunOptions options;
  options.real_time = !args.as_fast_as_possible;
  options.brake_at_end = true;
  options.duration_s = args.duration_s;
  options.stop = &stop_requested;
  options.perception = setup.perception;
  // The tape's width against the camera file's hint, said as soon as the frames show it.
  TapeWidthWatch width_watch(setup.opened.camera.tape_width_m, "track");
  options.sink = [&width_watch, annotate = annotator.sink()](
                     const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
                     const perception::LineDetection* detection) {
    width_watch.add(record);
    annotate(record, frame, detection);
  };
  options.on_period = [&](const pipeline::TraceRow& row) { commands.send(row); };
  pipeline::RunResult result;
  {
    const StopOnSignal stop_on_signal;
    if (!args.quiet && !args.json)
      std::fprintf(stderr, "agv track: tracking %s (%s); Ctrl-C stops\n", args.source.c_str(),
                   setup.opened.kind.c_str());
    result = pipeline::run_on_source(source, setup.camera, setup.scenario, options);
  }
  annotator.finish();
  if (!commands.finish())
    throw InputError(folder.file("commands.jsonl").string() + ": cannot write");

  const SourceFigures figures = source_figures(result);
  nlohmann::json summary = source_summary(result, figures, setup, args);
  summary["real_time"] = options.real_time;
  summary["udp"] = args.udp;
  summary["udp_failures"] = commands.udp_failures();
  summary["tracking"] = tracking_figures(result);
  // The width warning as it was said during the run (the end-of-run one counts every frame).
  std::vector<std::string> already_said;
  if (!width_watch.said().empty()) {
    nlohmann::json warnings = nlohmann::json::array({width_watch.said()});
    for (const nlohmann::json& w : summary["warnings"])
      if (w.get<std::string>().rfind("the tape measures", 0) != 0) warnings.push_back(w);
    summary["warnings"] = warnings;
    already_said.push_back(width_watch.said());
  }
  finish_source_run(folder, result, setup, summary, "tracking", "track", args.json, already_said);
  if (args.json) return 0;
  const nlohmann::json& t = summary["tracking"];
  std::printf(
      "frames %d processed, %llu dropped | lost %d | measurement age median %.1f ms, p99 %.1f "
      "ms | %.1f commands/s | watchdog stalls %zu | ended: %s\n",
      figures.frames, static_cast<unsigned long long>(result.frames_dropped), figures.lost,
      1e3 * t["measurement_age_s_median"].get<double>(),
      1e3 * t["measurement_age_s_p99"].get<double>(), t["commands_per_s"].get<double>(),
      result.stalls.size(), result.stop_reason.c_str());
  std::printf("output: %s\n", folder.target().c_str());
  return 0;
}

}  // namespace agv::tools
