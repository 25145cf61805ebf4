#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct SimulateArgs {
  std::string scenario_file;           // empty: the built-in default scenario
  std::vector<std::string> overrides;  // "key=value"
  std::string out_dir;                 // empty: runs/<timestamp>
  bool force = false;                  // --force: replace an existing output folder
  bool json = false;                   // print summary.json instead of the summary line
  bool no_plots = false;
  bool quiet = false;
};

void add_simulate_command(CLI::App& app, SimulateArgs& args);

// Runs `agv simulate`; returns the process exit code. Throws InputError on bad input.
int run_simulate(const SimulateArgs& args);

}  // namespace agv::tools
