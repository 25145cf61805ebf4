#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct EvaluateArgs {
  int conditions = 60;
  int frames_per_condition = 10;
  int empty_conditions = 20;
  int sequences = 12;
  int empty_sequences = 2;
  double sequence_length_m = 3.0;
  std::vector<std::string> sequence_pieces = {"line", "arc", "s-bend", "corner", "fork"};
  unsigned seed = 1;
  int only_sequence = -1;
  std::string out_dir;
  bool force = false;  // --force: replace an existing output folder
  std::string save_failures;
  std::optional<std::pair<int, int>> save_frames;  // --save-frames FIRST LAST
  bool json = false;
  bool quiet = false;
};

void add_evaluate_command(CLI::App& app, EvaluateArgs& args);

// Runs `agv evaluate`: perception accuracy over randomised rendered frames and sequences.
int run_evaluate(const EvaluateArgs& args);

}  // namespace agv::tools
