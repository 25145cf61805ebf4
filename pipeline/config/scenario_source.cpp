#include "pipeline/config/scenario_source.h"

#include "pipeline/config/builtin_files.h"
#include "pipeline/config/scenario_loader.h"

namespace agv::pipeline {

ScenarioText scenario_text_for_command(const std::string& file, const std::string& builtin_name,
                                       const std::string& label) {
  ScenarioText source;
  if (file.empty()) {
    source.text = builtin_files().at(builtin_name);
    source.name = label;
  } else {
    source = read_scenario_file(file);
  }
  source.builtin_files = builtin_files();
  return source;
}

Scenario load_scenario_for_command(const std::string& scenario_file,
                                   const std::vector<std::string>& overrides) {
  const ScenarioText source = scenario_text_for_command(scenario_file, "default_scenario.yaml",
                                                        "built-in default scenario");
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& option : overrides) pairs.push_back(split_override(option));
  return load_scenario(source, pairs);
}

}  // namespace agv::pipeline
