#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct EvaluateArgs {
  int conditions = 60;
  int frames_per_condition = 10;
  int empty_conditions = 20;
  unsigned seed = 1;
  std::string out_dir;
  bool force = false;  // --force: replace an existing output folder
  std::string save_failures;
  bool json = false;
  bool quiet = false;
};

void add_evaluate_command(CLI::App& app, EvaluateArgs& args);

// Runs `agv evaluate`: perception accuracy over randomised rendered frames.
int run_evaluate(const EvaluateArgs& args);

}  // namespace agv::tools
