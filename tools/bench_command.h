#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace agv::tools {

struct BenchArgs {
  int frames = 300;
  std::string scenario;                // "": the built-in default scenario
  std::vector<std::string> overrides;  // --set KEY=VALUE
  int threads = 1;
  bool json = false;
  bool quiet = false;
  std::string out;  // "": no files; else a folder for bench.txt and bench.json
  bool force = false;
};

void add_bench_command(CLI::App& app, BenchArgs& args);

// Runs `agv bench`: speed and accuracy of render, perceive (tracking, full search, and a Canny +
// HoughLinesP baseline), control and the closed loop on the consecutive frames of a closed-loop
// run of the scenario; prints a table or one JSON object.
int run_bench(const BenchArgs& args);

}  // namespace agv::tools
