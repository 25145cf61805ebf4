#pragma once

#include <CLI/CLI.hpp>

namespace agv::tools {

struct BenchArgs {
  int frames = 300;
  int threads = 1;
  bool json = false;
};

void add_bench_command(CLI::App& app, BenchArgs& args);

// Runs `agv bench`: speed of render, perceive, control and the closed loop on frames it
// renders itself (VGA, default scenario, varied poses); prints a table or one JSON object.
int run_bench(const BenchArgs& args);

}  // namespace agv::tools
