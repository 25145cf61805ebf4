#pragma once

#include <string>
#include <vector>

#include "pipeline/scenario.h"

namespace agv::tools {

// The scenario a command runs: the file given (or the built-in default scenario) with the
// --set overrides applied. Throws InputError on bad input.
pipeline::Scenario load_scenario_for_command(const std::string& scenario_file,
                                             const std::vector<std::string>& overrides);

}  // namespace agv::tools
