#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace agv::tools {

struct DetectTagsArgs {
  std::string input;  // folder of images or a video file
  std::string family = "tag36h11";
  std::string out;  // empty: runs/<date>-<time>
  bool refine_edges = true;
  bool force = false;
  bool json = false;
  bool quiet = false;
};

// `agv detect-tags`: every AprilTag in every image (or video frame), for checking prints and
// lighting before a mount calibration.
void add_detect_tags_command(CLI::App& app, DetectTagsArgs& args);

// Runs it; returns the exit code. Throws InputError on bad input.
int run_detect_tags(const DetectTagsArgs& args);

}  // namespace agv::tools
