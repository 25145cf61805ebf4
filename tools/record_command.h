#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct RecordArgs {
  std::string scenario_file;
  std::vector<std::string> overrides;
  std::string out_dir;
  bool force = false;  // --force: replace an existing output folder
  std::string format = "png";
  int jpeg_quality = 90;
  bool quiet = false;
  bool json = false;
};

void add_record_command(CLI::App& app, RecordArgs& args);

// Runs `agv record`: a simulated run written as a dataset (frames/, manifest.csv with ground
// truth, camera.yaml, recording.yaml). Returns the exit code; throws InputError on bad input.
int run_record(const RecordArgs& args);

}  // namespace agv::tools
