#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/config/scenario.h"

namespace agv::pipeline {

// Where scenario text comes from. Relative paths inside it (the camera file) are resolved
// against base_dir, or, for a built-in scenario, first against `builtin_files` (name -> text).
struct ScenarioText {
  std::string text;
  std::string name;      // for messages
  std::string base_dir;  // directory of the file ("" for built-in)
  std::map<std::string, std::string> builtin_files;
};

// Reads a scenario file; throws InputError naming the file and key on anything wrong.
ScenarioText read_scenario_file(const std::string& path);

// Parses scenario text with --set overrides ("key", "value") applied on top, loads the camera
// it names and checks every value. Unknown keys are errors.
Scenario load_scenario(const ScenarioText& source,
                       const std::vector<std::pair<std::string, std::string>>& overrides);

// Splits "key=value" as given to --set; throws InputError when there is no '='.
std::pair<std::string, std::string> split_override(const std::string& option);

}  // namespace agv::pipeline
