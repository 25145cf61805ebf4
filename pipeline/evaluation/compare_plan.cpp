#include "pipeline/evaluation/compare_plan.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include <filesystem>
#include <random>
#include <set>

#include "common/input_error.h"
#include "pipeline/config/yaml_reader.h"

namespace agv::pipeline {
namespace {

std::string number_text(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// FNV-1a, 64 bit: a fingerprint that is the same on every machine (std::hash is not).
std::uint64_t fnv1a(const std::string& text, std::uint64_t hash = 14695981039346656037ull) {
  for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
  return hash;
}

bool is_word(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

std::vector<SuiteEntry> read_entries(YamlReader& in, const std::string& key, bool controllers) {
  std::vector<SuiteEntry> entries;
  std::set<std::string> names;
  const size_t count = in.sequence_size(key);
  if (count == 0) throw InputError(in.origin(key) + ": key '" + key + "': the list is empty");
  for (size_t i = 0; i < count; ++i) {
    const std::string prefix = key + "." + std::to_string(i) + ".";
    SuiteEntry entry;
    entry.name = in.text(prefix + "name", "");
    if (!is_word(entry.name)) {
      throw InputError(in.origin(prefix + "name") + ": key '" + prefix +
                       "name': expected a word of letters, digits, '_' or '-', got '" + entry.name +
                       "'");
    }
    if (!names.insert(entry.name).second) {
      throw InputError(in.origin(prefix + "name") + ": key '" + prefix + "name': '" + entry.name +
                       "' is used twice");
    }
    entry.about = in.text(prefix + "about", "");
    entry.settings = in.settings(prefix + "set");
    if (controllers) {
      for (size_t v = 0; v < in.sequence_size(prefix + "vehicles"); ++v) {
        entry.vehicles.push_back(in.choice(prefix + "vehicles." + std::to_string(v),
                                           control::VehicleKind::kMecanum, kVehicleKindWords));
      }
    }
    entries.push_back(std::move(entry));
  }
  return entries;
}

const SuiteEntry& find_scenario(const CompareSuite& suite, const std::string& name,
                                const std::string& key) {
  for (const SuiteEntry& s : suite.scenarios)
    if (s.name == name) return s;
  throw InputError(suite.source_name + ": key '" + key + "': no scenario named '" + name + "'");
}

std::string plan_fingerprint(const CompareSuite& suite, const std::string& mode, int runs) {
  std::uint64_t hash = fnv1a(suite.text);
  hash = fnv1a(suite.base.text, hash);
  hash = fnv1a(mode + "/" + std::to_string(suite.seed) + "/" + std::to_string(runs), hash);
  char text[20];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

ComparePlan empty_plan(const CompareSuite& suite, const std::string& mode, int runs) {
  ComparePlan plan;
  plan.mode = mode;
  plan.suite_name = suite.name;
  plan.seed = suite.seed;
  plan.monte_carlo_runs = runs;
  plan.base = suite.base;
  plan.controllers = suite.controllers;
  plan.fingerprint = plan_fingerprint(suite, mode, runs);
  return plan;
}

Scenario load_with(const ComparePlan& plan, const Settings& settings) {
  Settings all{{"seed", std::to_string(plan.seed)}};
  all.insert(all.end(), settings.begin(), settings.end());
  return load_scenario(plan.base, all);
}

// Adds a job for every controller that runs on the scenario's vehicle. Loads the scenario, so
// that a bad key stops the plan before any run starts.
void add_jobs(ComparePlan* plan, const PlannedScenario& scenario, bool check_controllers,
              const std::string& suite_file) {
  auto in_context = [&](const std::string& what, const Settings& settings) {
    try {
      return load_with(*plan, settings);
    } catch (const InputError& e) {
      throw InputError(suite_file + ": " + what + ": " + e.what());
    }
  };
  const Scenario loaded =
      in_context("scenario '" + scenario.entry.name + "'", scenario.entry.settings);
  plan->scenarios.push_back(scenario);
  const int scenario_index = static_cast<int>(plan->scenarios.size()) - 1;
  for (size_t c = 0; c < plan->controllers.size(); ++c) {
    const SuiteEntry& controller = plan->controllers[c];
    const std::vector<control::VehicleKind>& kinds = controller.vehicles;
    if (!kinds.empty() &&
        std::find(kinds.begin(), kinds.end(), loaded.vehicle.kind()) == kinds.end())
      continue;
    if (check_controllers) {
      Settings all = scenario.entry.settings;
      all.insert(all.end(), controller.settings.begin(), controller.settings.end());
      in_context("controller '" + controller.name + "' on scenario '" + scenario.entry.name + "'",
                 all);
    }
    plan->jobs.push_back(
        {static_cast<int>(plan->jobs.size()), scenario_index, static_cast<int>(c)});
  }
}

}  // namespace

CompareSuite load_suite(const ScenarioText& source, const ScenarioText& base_default) {
  YamlReader in(parse_yaml(source.text, source.name), source.name);
  CompareSuite suite;
  suite.source_name = source.name;
  suite.text = source.text;
  suite.name = in.text("name", "suite");
  suite.seed = static_cast<std::uint64_t>(in.integer("seed", 1, 0, 2147483647));
  const std::string base_file = in.text("base_scenario", "");
  if (base_file.empty()) {
    suite.base = base_default;
  } else {
    std::filesystem::path path(base_file);
    if (path.is_relative() && !source.base_dir.empty()) path = source.base_dir / path;
    suite.base = read_scenario_file(path.string());
  }
  suite.controllers = read_entries(in, "controllers", true);
  suite.scenarios = read_entries(in, "scenarios", false);

  if (in.has("latency_study")) {
    LatencyStudy study;
    study.scenario = in.text("latency_study.scenario", suite.scenarios.front().name);
    find_scenario(suite, study.scenario, "latency_study.scenario");
    const size_t count = in.sequence_size("latency_study.frames");
    for (size_t i = 0; i < count; ++i)
      study.frames.push_back(in.integer("latency_study.frames." + std::to_string(i), 0, 0, 50));
    study.threaded = in.has("latency_study.threaded");
    study.camera_fps = in.positive("latency_study.threaded.camera_fps", study.camera_fps, 1000.0);
    study.time_scale = in.positive("latency_study.threaded.time_scale", study.time_scale, 100.0);
    study.threaded_latency_frames =
        in.integer("latency_study.threaded.latency_frames", study.threaded_latency_frames, 0, 50);
    suite.latency = study;
  }
  MonteCarloSettings& mc = suite.monte_carlo;
  mc.scenario = in.text("monte_carlo.scenario", suite.scenarios.front().name);
  find_scenario(suite, mc.scenario, "monte_carlo.scenario");
  mc.e_theta_max_rad = in.number("monte_carlo.e_theta_max_rad", mc.e_theta_max_rad, 0.0, 1.5);
  mc.e_d_max_m = in.number("monte_carlo.e_d_max_m", mc.e_d_max_m, 0.0, 0.5);
  in.finish();
  return suite;
}

ComparePlan plan_suite(const CompareSuite& suite) {
  ComparePlan plan = empty_plan(suite, "suite", 0);
  bool first = true;
  for (const SuiteEntry& entry : suite.scenarios) {
    add_jobs(&plan, {entry, "", true, false}, first, suite.source_name);
    first = false;
  }
  if (!suite.latency) return plan;
  const LatencyStudy& study = *suite.latency;
  const SuiteEntry& base = find_scenario(suite, study.scenario, "latency_study.scenario");
  auto add_cell = [&](const std::string& label, bool compensation, const Settings& extra) {
    PlannedScenario cell;
    cell.entry.name = (label == "threaded" ? std::string("threaded") : "latency_" + label) +
                      (compensation ? "_comp" : "_nocomp");
    cell.entry.about = base.name +
                       (label == "threaded" ? ", camera and control threads"
                                            : ", " + label + " frame(s) of latency") +
                       ", compensation " + (compensation ? "on" : "off");
    cell.entry.settings = base.settings;
    cell.entry.settings.insert(cell.entry.settings.end(), extra.begin(), extra.end());
    cell.entry.settings.emplace_back("controller.latency_compensation",
                                     compensation ? "true" : "false");
    cell.latency_label = label;
    cell.compensation = compensation;
    cell.threaded = label == "threaded";
    add_jobs(&plan, cell, false, suite.source_name);
  };
  for (int frames : study.frames) {
    for (bool compensation : {true, false})
      add_cell(std::to_string(frames), compensation, {{"latency_frames", std::to_string(frames)}});
  }
  if (study.threaded) {
    for (bool compensation : {true, false}) {
      add_cell("threaded", compensation,
               {{"loop.mode", "threaded"},
                {"loop.camera_fps", number_text(study.camera_fps)},
                {"loop.time_scale", number_text(study.time_scale)},
                {"latency_frames", std::to_string(study.threaded_latency_frames)}});
    }
  }
  return plan;
}

ComparePlan plan_monte_carlo(const CompareSuite& suite, int runs) {
  if (runs < 1)
    throw InputError("--monte-carlo: expected at least 1 run, got " + std::to_string(runs));
  ComparePlan plan = empty_plan(suite, "monte_carlo", runs);
  const MonteCarloSettings& mc = suite.monte_carlo;
  const SuiteEntry& base = find_scenario(suite, mc.scenario, "monte_carlo.scenario");
  // mt19937_64's sequence is fixed by the standard; the mapping to [-1, 1) is ours, so the
  // draws are the same with every standard library.
  std::mt19937_64 random(suite.seed * 0x9E3779B97F4A7C15ull + 12345);
  auto symmetric = [&] { return 2.0 * static_cast<double>(random() >> 11) * 0x1.0p-53 - 1.0; };
  for (int i = 0; i < runs; ++i) {
    PlannedScenario run;
    char name[32];
    std::snprintf(name, sizeof(name), "mc_%05d", i + 1);
    run.entry.name = name;
    const double e_theta_rad = mc.e_theta_max_rad * symmetric();
    const double e_d_m = mc.e_d_max_m * symmetric();
    const std::uint64_t seed = random() % 2147483647u;
    run.entry.about = base.name + " from e_theta " + number_text(e_theta_rad) + " rad, e_d " +
                      number_text(e_d_m) + " m, seed " + std::to_string(seed);
    run.entry.settings = base.settings;
    run.entry.settings.emplace_back("initial_error.e_theta_rad", number_text(e_theta_rad));
    run.entry.settings.emplace_back("initial_error.e_d_m", number_text(e_d_m));
    run.entry.settings.emplace_back("seed", std::to_string(seed));
    add_jobs(&plan, run, i == 0, suite.source_name);
  }
  return plan;
}

std::vector<int> shard_jobs(const ComparePlan& plan, int k, int n) {
  if (n < 1 || k < 1 || k > n) {
    throw InputError("--shard " + std::to_string(k) + "/" + std::to_string(n) +
                     ": expected K/N with 1 <= K <= N");
  }
  std::vector<int> jobs;
  for (size_t i = static_cast<size_t>(k - 1); i < plan.jobs.size(); i += static_cast<size_t>(n))
    jobs.push_back(static_cast<int>(i));
  return jobs;
}

Scenario job_scenario(const ComparePlan& plan, const CompareJob& job) {
  Settings all = plan.scenarios.at(job.scenario).entry.settings;
  const Settings& controller = plan.controllers.at(job.controller).settings;
  all.insert(all.end(), controller.begin(), controller.end());
  return load_with(plan, all);
}

namespace {

nlohmann::json entry_json(const SuiteEntry& e) {
  nlohmann::json settings = nlohmann::json::array();
  for (const auto& [key, value] : e.settings) settings.push_back({key, value});
  nlohmann::json vehicles = nlohmann::json::array();
  for (control::VehicleKind kind : e.vehicles) vehicles.push_back(word_of(kVehicleKindWords, kind));
  return {{"name", e.name}, {"about", e.about}, {"settings", settings}, {"vehicles", vehicles}};
}

SuiteEntry entry_from(const nlohmann::json& j) {
  SuiteEntry e;
  e.name = j.at("name").get<std::string>();
  e.about = j.at("about").get<std::string>();
  for (const auto& pair : j.at("settings"))
    e.settings.emplace_back(pair.at(0).get<std::string>(), pair.at(1).get<std::string>());
  for (const auto& word : j.at("vehicles")) {
    bool known = false;
    for (const auto& [name, kind] : kVehicleKindWords) {
      if (name != word.get<std::string>()) continue;
      e.vehicles.push_back(kind);
      known = true;
    }
    if (!known) throw InputError("unknown vehicle kind '" + word.get<std::string>() + "'");
  }
  return e;
}

}  // namespace

nlohmann::json plan_json(const ComparePlan& plan) {
  nlohmann::json controllers = nlohmann::json::array(), scenarios = nlohmann::json::array(),
                 jobs = nlohmann::json::array();
  for (const SuiteEntry& c : plan.controllers) controllers.push_back(entry_json(c));
  for (const PlannedScenario& s : plan.scenarios) {
    nlohmann::json j = entry_json(s.entry);
    j["latency_label"] = s.latency_label;
    j["compensation"] = s.compensation;
    j["threaded"] = s.threaded;
    scenarios.push_back(j);
  }
  for (const CompareJob& job : plan.jobs) jobs.push_back({job.scenario, job.controller});
  return {{"mode", plan.mode},
          {"suite", plan.suite_name},
          {"seed", plan.seed},
          {"monte_carlo_runs", plan.monte_carlo_runs},
          {"base_scenario", plan.base.name},
          {"fingerprint", plan.fingerprint},
          {"controllers", controllers},
          {"scenarios", scenarios},
          {"jobs", jobs}};
}

ComparePlan plan_from_json(const nlohmann::json& json, const std::string& origin) {
  try {
    ComparePlan plan;
    plan.mode = json.at("mode").get<std::string>();
    plan.suite_name = json.at("suite").get<std::string>();
    plan.seed = json.at("seed").get<std::uint64_t>();
    plan.monte_carlo_runs = json.at("monte_carlo_runs").get<int>();
    plan.base.name = json.at("base_scenario").get<std::string>();
    plan.fingerprint = json.at("fingerprint").get<std::string>();
    for (const auto& c : json.at("controllers")) plan.controllers.push_back(entry_from(c));
    for (const auto& s : json.at("scenarios")) {
      PlannedScenario p{entry_from(s), s.at("latency_label").get<std::string>(),
                        s.at("compensation").get<bool>(), s.at("threaded").get<bool>()};
      plan.scenarios.push_back(p);
    }
    for (const auto& j : json.at("jobs")) {
      CompareJob job{static_cast<int>(plan.jobs.size()), j.at(0).get<int>(), j.at(1).get<int>()};
      if (job.scenario < 0 || job.scenario >= static_cast<int>(plan.scenarios.size()) ||
          job.controller < 0 || job.controller >= static_cast<int>(plan.controllers.size()))
        throw InputError("job " + std::to_string(job.index) + " names no planned run");
      plan.jobs.push_back(job);
    }
    return plan;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(origin + ": not a plan written by agv compare (" + e.what() + ")");
  } catch (const InputError& e) {
    throw InputError(origin + ": " + e.what());
  }
}

}  // namespace agv::pipeline
