#include "tools/source_setup.h"

#include <algorithm>
#include <sstream>

#include "common/input_error.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/scenario_source.h"

namespace agv::tools {
namespace {

cv::Vec3d parse_colour(const std::string& text) {
  std::stringstream stream(text);
  std::string part;
  std::vector<double> values;
  const std::string message = "--tape-color-bgr " + text + ": expected three numbers B,G,R (0-255)";
  while (std::getline(stream, part, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stod(part, &used));
      if (used != part.size()) throw InputError(message);
    } catch (const std::exception&) {
      throw InputError(message);
    }
  }
  if (values.size() != 3 || *std::min_element(values.begin(), values.end()) < 0 ||
      *std::max_element(values.begin(), values.end()) > 255) {
    throw InputError(message);
  }
  return {values[0], values[1], values[2]};
}

}  // namespace

void add_source_options(CLI::App* sub, SourceArgs& args, const std::string& sources,
                        bool video_by_default) {
  sub->add_option("--camera", args.camera,
                  "Camera YAML (default: the dataset's camera.yaml; needed for anything else)");
  sub->add_option("--fps", args.fps,
                  "Frame rate of a bare folder of images (its times; required for one, no default)")
      ->check(CLI::Range(0.01, 10000.0));
  sub->add_option("--scenario", args.scenario_file,
                  "Scenario YAML for the controller, its period, the vehicle limits and "
                  "perception settings (default: the built-in one)");
  sub->add_option("--set", args.overrides, "Override one scenario key")->type_name("KEY=VALUE");
  sub->add_option("--controller", args.controller,
                  "Controller whose commands to compute (--set controller.kind=; default: the "
                  "scenario's)")
      ->check(CLI::IsMember({"finite_step", "pid", "seed004_ff_p", "dwa", "improved_dwa"}));
  sub->add_option("--path-speed", args.path_speed_m_s,
                  "Path speed the controller assumes, m/s (--set path_speed_m_s=; default: the "
                  "scenario's)")
      ->check(CLI::Range(0.0, 5.0));
  sub->add_option("--branch", args.branch,
                  "Way to take where the tape forks (kept to through the junction); a tape "
                  "crossing the one followed (an X) is driven straight through")
      ->check(CLI::IsMember({"left", "straight", "right"}))
      ->capture_default_str();
  sub->add_option("--tape-width-m", args.tape_width_m,
                  "Tape width (default: the camera file's tape_width_m, else the scenario's)")
      ->check(CLI::Range(0.0, 0.5));
  sub->add_option("--tape-color-bgr", args.tape_color,
                  "Tape colour hint B,G,R (default: the camera file's, else found automatically)");
  sub->add_flag("--no-tracking", args.no_tracking,
                "Search every whole frame (default: track the line between full searches, "
                "which is faster and as accurate)");
  if (video_by_default) {
    sub->add_flag("--no-video", args.no_video, "Skip annotated.avi");
  } else {
    sub->add_flag("--video", args.video,
                  "Also write annotated.avi (costs the camera thread a few ms a frame)");
  }
  sub->add_option("--out", args.out_dir, "Output folder (default: runs/<date-time>)");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
  sub->add_flag("--json", args.json, "Print summary.json (with the output folder) on stdout");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
  sub->add_option("source", args.source, sources)->required();
}

SourceSetup set_up_source(const SourceArgs& args, bool pass_bad_frames) {
  std::vector<std::string> overrides = args.overrides;
  if (!args.controller.empty()) overrides.push_back("controller.kind=" + args.controller);
  if (args.path_speed_m_s > 0.0)
    overrides.push_back("path_speed_m_s=" + std::to_string(args.path_speed_m_s));
  pipeline::Scenario scenario = pipeline::load_scenario_for_command(args.scenario_file, overrides);
  pipeline::OpenedSource opened =
      pipeline::open_frame_source(args.source, args.camera, args.fps, pass_bad_frames);
  const perception::CameraModel camera =
      perception::camera_model_of(opened.camera, opened.camera_name);
  perception::LineEstimator::Options perception =
      pipeline::recorded_perception_options(scenario, opened.camera);
  perception.branch = perception::parse_branch_choice(args.branch);
  perception.tracking = !args.no_tracking;
  if (args.tape_width_m > 0.0) perception.tape.width_m = args.tape_width_m;
  if (!args.tape_color.empty()) perception.tape.color_bgr = parse_colour(args.tape_color);
  return {std::move(opened), std::move(scenario), camera, perception};
}

}  // namespace agv::tools
