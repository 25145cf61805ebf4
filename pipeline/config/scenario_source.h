#pragma once

#include <string>
#include <vector>

#include "pipeline/config/scenario.h"
#include "pipeline/config/scenario_loader.h"

namespace agv::pipeline {

// The text of a scenario (or suite) file for a command: `file`, or, when it is empty, the
// built-in file `builtin_name` under the name `label`. Relative paths inside may name built-in
// files. Throws InputError when the file cannot be read.
ScenarioText scenario_text_for_command(const std::string& file, const std::string& builtin_name,
                                       const std::string& label);

// The scenario a command runs: the file given (or the built-in default scenario) with the
// --set overrides applied. Throws InputError on bad input.
Scenario load_scenario_for_command(const std::string& scenario_file,
                                   const std::vector<std::string>& overrides);

}  // namespace agv::pipeline
