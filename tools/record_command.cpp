#include "tools/record_command.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/scenario_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/dataset.h"
#include "pipeline/evaluation/output_folder.h"
#include "tools/build_info.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"

namespace agv::tools {

void add_record_command(CLI::App& app, RecordArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "record",
      "Records a simulated closed-loop run as a dataset: frames/ (one image per control period), "
      "manifest.csv "
      "(index,t_s,file,x_m,y_m,yaw_rad,e_theta_rad,e_d_m,odom_x_m,odom_y_m,odom_yaw_rad: "
      "the true pose and errors of each frame and the wheel odometry) and camera.yaml (with the "
      "tape's width and colour as hints), for `agv replay` or "
      "other tools.");
  sub->add_option("--scenario", args.scenario_file,
                  "Scenario YAML (default: the built-in default scenario)");
  sub->add_option("--set", args.overrides, "Override one scenario key, e.g. --set duration_s=3")
      ->type_name("KEY=VALUE");
  sub->add_option("--out", args.out_dir, "Dataset folder to write")->required();
  sub->add_flag("--force", args.force, "Replace an existing dataset folder (a previous recording)");
  sub->add_option("--format", args.format, "Frame format")
      ->check(CLI::IsMember({"png", "jpg"}))
      ->capture_default_str();
  sub->add_option("--jpeg-quality", args.jpeg_quality, "JPEG quality (with --format jpg)")
      ->check(CLI::Range(10, 100))
      ->capture_default_str();
  sub->add_flag("--quiet", args.quiet, "No progress bar");
  sub->add_flag("--json", args.json, "Print the result (frames, bytes, output folder) as JSON");
}

int run_record(const RecordArgs& args) {
  const pipeline::Scenario scenario =
      pipeline::load_scenario_for_command(args.scenario_file, args.overrides);
  for (const std::string& warning : pipeline::scenario_warnings(scenario))
    std::cerr << "agv record: warning: " << warning << '\n';
  pipeline::OutputFolder folder(args.out_dir, "manifest.csv", args.force);
  perception::CameraFile camera = scenario.camera;
  camera.tape_width_m = scenario.tape.width_m;
  if (scenario.tape_color_hint) camera.tape_color_bgr = scenario.tape.color_bgr;
  pipeline::DatasetWriter writer(folder.file(""), camera, args.format, args.jpeg_quality);
  {
    ProgressBar bar("recording " + std::to_string(scenario.duration_s).substr(0, 4) + " s",
                    !args.quiet);
    pipeline::run_scenario(
        scenario, [&](double f) { bar.update(f); },
        [&](const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
            const perception::LineDetection*) {
          writer.add(static_cast<int>(record.index), record.stamp_s, frame.image, *frame.pose,
                     *record.truth, *frame.odometry);
        });
  }
  writer.finish();
  {
    std::ofstream provenance(folder.file("recording.yaml"));
    provenance << "# How this dataset was made (agv record)\n";
    provenance << "scenario: \"" << scenario.source_name << "\"\n";
    provenance << "overrides:\n";
    for (const std::string& option : args.overrides) provenance << "  - \"" << option << "\"\n";
    provenance << "seed: " << scenario.seed << "\n";
    provenance << "frames: " << writer.frames() << "\n";
    provenance << "format: " << args.format << "\n";
  }
  folder.commit();
  std::uintmax_t bytes = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder.target())) {
    if (entry.is_regular_file()) bytes += entry.file_size();
  }
  if (args.json) {
    nlohmann::json j;
    j["frames"] = writer.frames();
    j["bytes"] = bytes;
    j["output"] = folder.target().string();
    j["agv"] = build_json();
    j["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::printf("recorded %d frames (%.1f MB) to %s\n", writer.frames(), bytes / 1e6,
              folder.target().c_str());
  return 0;
}

}  // namespace agv::tools
