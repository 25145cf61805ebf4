#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace agv::tools {

struct CompareArgs {
  std::string suite_file;               // empty: the built-in default suite
  std::string out_dir;                  // empty: runs/<timestamp>
  bool force = false;                   // --force: replace an existing output folder
  int jobs = 0;                         // worker threads (0: one per processor)
  int monte_carlo_runs = 0;             // > 0: a Monte Carlo study instead of the suite
  std::string shard;                    // "K/N": run only slice K of N
  std::vector<std::string> merge_dirs;  // join these shard folders instead of running
  long long seed = -1;                  // >= 0: replaces the suite's seed
  bool quiet = false;
  bool json = false;
};

void add_compare_command(CLI::App& app, CompareArgs& args);

// Runs `agv compare`; returns the process exit code. Throws InputError on bad input.
int run_compare(const CompareArgs& args);

}  // namespace agv::tools
