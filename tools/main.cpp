// agv: command-line program of the AGV vision-in-the-loop path tracker.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>

#include "common/input_error.h"
#include "tools/bench_command.h"
#include "tools/build_info.h"
#include "tools/calibrate_command.h"
#include "tools/compare_command.h"
#include "tools/detect_tags_command.h"
#include "tools/evaluate_command.h"
#include "tools/record_command.h"
#include "tools/replay_command.h"
#include "tools/simulate_command.h"
#include "tools/track_command.h"

int main(int argc, char** argv) {
  CLI::App app{
      "agv: vision-in-the-loop AGV path tracker (perception, finite-step control, closed-loop "
      "simulation)"};
  app.set_version_flag("--version", "agv " + agv::tools::agv_version() + " (commit " +
                                        agv::tools::agv_commit() + ")");
  app.require_subcommand(1);
  agv::tools::SimulateArgs simulate;
  agv::tools::BenchArgs bench;
  agv::tools::add_simulate_command(app, simulate);
  agv::tools::add_bench_command(app, bench);
  agv::tools::EvaluateArgs evaluate;
  agv::tools::add_evaluate_command(app, evaluate);
  agv::tools::RecordArgs record;
  agv::tools::ReplayArgs replay;
  agv::tools::add_record_command(app, record);
  agv::tools::add_replay_command(app, replay);
  agv::tools::CalibrateArgs calibrate;
  agv::tools::add_calibrate_command(app, calibrate);
  agv::tools::CompareArgs compare;
  agv::tools::add_compare_command(app, compare);
  agv::tools::TrackArgs track;
  agv::tools::add_track_command(app, track);
  agv::tools::DetectTagsArgs detect_tags;
  agv::tools::add_detect_tags_command(app, detect_tags);

  // OpenCV's own warnings (a GStreamer pipeline that cannot report its position, ...) are not
  // the user's concern; errors it cannot recover from still reach us as failures.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Usage errors are bad input: worded as the program's own errors, naming the command.
    std::string command = "agv";
    for (const CLI::App* sub = &app; !sub->get_subcommands().empty();) {
      sub = sub->get_subcommands().front();
      command += " " + sub->get_name();
    }
    std::cerr << command << ": error: " << e.what() << " (`" << command
              << " --help` lists the options)\n";
    return 2;
  }
  const std::string command = app.get_subcommands().front()->get_name();
  try {
    if (command == "simulate") return agv::tools::run_simulate(simulate);
    if (command == "bench") return agv::tools::run_bench(bench);
    if (command == "record") return agv::tools::run_record(record);
    if (command == "evaluate") return agv::tools::run_evaluate(evaluate);
    if (command == "replay") return agv::tools::run_replay_command(replay);
    if (command == "calibrate") return agv::tools::run_calibrate(calibrate);
    if (command == "compare") return agv::tools::run_compare(compare);
    if (command == "track") return agv::tools::run_track_command(track);
    if (command == "detect-tags") return agv::tools::run_detect_tags(detect_tags);
  } catch (const agv::InputError& e) {
    std::cerr << "agv " << command << ": error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "agv " << command << ": internal error: " << e.what() << '\n';
    return 1;
  }
  return 1;
}
