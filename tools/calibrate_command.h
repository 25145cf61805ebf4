#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace agv::tools {

struct CalibrateArgs {
  std::string command;  // "intrinsics" or "mount": the subcommand given
  std::string images_dir;
  // mount
  std::string frames;  // folder of images, or a dataset folder (its frames/)
  std::string tags_file;
  std::string camera_file;
  std::string board = "chessboard:9x6:0.025";
  std::string model = "pinhole";
  std::string out;  // empty: camera_<date>-<time>.yaml in the working directory
  bool force = false;
  bool json = false;
  bool quiet = false;
};

// `agv calibrate intrinsics` and `agv calibrate mount`.
void add_calibrate_command(CLI::App& app, CalibrateArgs& args);

// Runs the chosen `agv calibrate` command; returns the exit code. Throws InputError on bad
// input.
int run_calibrate(const CalibrateArgs& args);

}  // namespace agv::tools
