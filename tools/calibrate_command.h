#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace agv::tools {

struct CalibrateArgs {
  std::string images_dir;
  std::string board = "chessboard:9x6:0.025";
  std::string out = "camera.yaml";
  bool json = false;
};

// `agv calibrate intrinsics`.
void add_calibrate_command(CLI::App& app, CalibrateArgs& args);

// Runs `agv calibrate intrinsics`; returns the exit code. Throws InputError on bad input.
int run_calibrate(const CalibrateArgs& args);

}  // namespace agv::tools
