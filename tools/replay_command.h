#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace agv::tools {

// What replay and track both take: where the frames come from and how to measure them.
struct SourceArgs {
  std::string source;         // dataset folder, image folder, video file (track: or a live source)
  std::string camera;         // overrides the dataset's camera.yaml; needed for anything else
  double fps = 0.0;           // a bare image folder's frame rate
  std::string scenario_file;  // controller, vehicle limits, perception settings
  std::vector<std::string> overrides;
  std::string controller;       // shorthand for --set controller.kind=
  double path_speed_m_s = 0.0;  // shorthand for --set path_speed_m_s= (0: the scenario's)
  std::string branch = "straight";
  double tape_width_m = 0.0;  // 0: from the camera file, else the scenario's
  std::string tape_color;     // "B,G,R"; empty: from the camera file, else automatic
  bool no_tracking = false;
  bool no_video = false;  // replay: --no-video
  bool video = false;     // track: --video
  std::string out_dir;
  bool force = false;  // --force: replace an existing output folder
  bool json = false;
  bool quiet = false;
};

struct ReplayArgs : SourceArgs {
  bool skip_bad_frames = false;
};

// The options replay and track share, the source described as `sources`. Replay writes
// annotated.avi unless --no-video; track (live: video_by_default false) only with --video.
void add_source_options(CLI::App* sub, SourceArgs& args, const std::string& sources,
                        bool video_by_default);

void add_replay_command(CLI::App& app, ReplayArgs& args);

// Runs `agv replay`; returns the exit code. Throws InputError on bad input.
int run_replay_command(const ReplayArgs& args);

}  // namespace agv::tools
