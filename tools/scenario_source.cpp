#include "tools/scenario_source.h"

#include "pipeline/scenario_loader.h"
#include "tools/embedded_files.h"

namespace agv::tools {

pipeline::ScenarioText scenario_text_for_command(const std::string& file,
                                                 const std::string& builtin_name,
                                                 const std::string& label) {
  pipeline::ScenarioText source;
  if (file.empty()) {
    source.text = embedded_files().at(builtin_name);
    source.name = label;
  } else {
    source = pipeline::read_scenario_file(file);
  }
  source.builtin_files = embedded_files();
  return source;
}

pipeline::Scenario load_scenario_for_command(const std::string& scenario_file,
                                             const std::vector<std::string>& overrides) {
  const pipeline::ScenarioText source = scenario_text_for_command(
      scenario_file, "default_scenario.yaml", "built-in default scenario");
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& option : overrides) pairs.push_back(pipeline::split_override(option));
  return pipeline::load_scenario(source, pairs);
}

}  // namespace agv::tools
