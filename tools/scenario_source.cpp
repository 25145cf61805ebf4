#include "tools/scenario_source.h"

#include "pipeline/scenario_loader.h"
#include "tools/embedded_files.h"

namespace agv::tools {

pipeline::Scenario load_scenario_for_command(const std::string& scenario_file,
                                             const std::vector<std::string>& overrides) {
  pipeline::ScenarioText source;
  if (scenario_file.empty()) {
    source.text = embedded_files().at("default_scenario.yaml");
    source.name = "built-in default scenario";
  } else {
    source = pipeline::read_scenario_file(scenario_file);
  }
  source.builtin_files = embedded_files();
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& option : overrides) pairs.push_back(pipeline::split_override(option));
  return pipeline::load_scenario(source, pairs);
}

}  // namespace agv::tools
