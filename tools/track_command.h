#pragma once

#include <limits>
#include <string>

#include <CLI/CLI.hpp>

#include "tools/replay_command.h"

namespace agv::tools {

struct TrackArgs : SourceArgs {
  double duration_s = std::numeric_limits<double>::infinity();
  std::string udp;  // HOST:PORT
  bool as_fast_as_possible = false;
};

void add_track_command(CLI::App& app, TrackArgs& args);

// Runs `agv track`; returns the exit code. Throws InputError on bad input.
int run_track_command(const TrackArgs& args);

}  // namespace agv::tools
