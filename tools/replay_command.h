#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct ReplayArgs {
  std::string dataset;
  std::string camera;  // overrides the dataset's camera.yaml; needed for a video
  std::string controller = "finite_step";
  std::string out_dir;
  bool skip_bad_frames = false;
  std::string branch = "straight";
  double tape_width_m = 0.0;  // 0: from camera.yaml, else 25 mm
  std::string tape_color;     // "B,G,R"; empty: from camera.yaml, else automatic
  double path_speed_m_s = 0.3;
  bool no_tracking = false;
  bool no_video = false;
  bool quiet = false;
};

void add_replay_command(CLI::App& app, ReplayArgs& args);

// Runs `agv replay`; returns the exit code. Throws InputError on bad input.
int run_replay_command(const ReplayArgs& args);

}  // namespace agv::tools
