#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/config/scenario.h"
#include "pipeline/config/scenario_loader.h"

namespace agv::pipeline {

using Settings = std::vector<std::pair<std::string, std::string>>;  // --set key=value pairs

// One controller or one scenario of a comparison suite: what `agv simulate --set` would apply.
struct SuiteEntry {
  std::string name;  // a word: letters, digits, '_' and '-' (it names files)
  std::string about;
  Settings settings;
  std::vector<control::VehicleKind> vehicles;  // controllers: vehicle kinds it runs on (empty: all)
};

// How latency degrades each controller: `scenario` with each latency in `frames` and a threaded
// run, each with latency compensation on and off.
struct LatencyStudy {
  std::string scenario;
  std::vector<int> frames;
  bool threaded = true;
  double camera_fps = 30.0;
  double time_scale = 4.0;
  int threaded_latency_frames = 1;
};

struct MonteCarloSettings {
  std::string scenario;
  double e_theta_max_rad = 0.13962634015954636;  // 8 deg: seed 000's model validity
  double e_d_max_m = 0.020;
};

// A suite file of `agv compare` (pipeline/config/default_suite.yaml shows every key).
struct CompareSuite {
  std::string source_name;
  std::string text;  // the file's text, part of the plan's fingerprint
  std::string name;
  std::uint64_t seed = 1;
  ScenarioText base;  // the scenario every run starts from
  std::vector<SuiteEntry> controllers;
  std::vector<SuiteEntry> scenarios;
  std::optional<LatencyStudy> latency;
  MonteCarloSettings monte_carlo;
};

// Reads a suite; `base_default` is the scenario used when the suite names none. Throws
// InputError naming the file and key.
CompareSuite load_suite(const ScenarioText& source, const ScenarioText& base_default);

// A scenario of the plan, with its place in the latency study if it has one.
struct PlannedScenario {
  SuiteEntry entry;
  std::string latency_label;  // "" | "0", "1", ... (frames) | "threaded"
  bool compensation = true;   // latency study: controller.latency_compensation
  bool threaded = false;      // loop.mode threaded: runs alone, varies from run to run
};

// One run: a scenario of the plan with a controller of the plan.
struct CompareJob {
  int index = 0;
  int scenario = 0;
  int controller = 0;
};

// Every run of a comparison, in a fixed order: the same suite, mode and seed give the same plan
// on every machine, so that shards of it can run anywhere and be merged.
struct ComparePlan {
  std::string mode = "suite";  // suite | monte_carlo
  std::string suite_name;
  std::uint64_t seed = 1;
  int monte_carlo_runs = 0;
  ScenarioText base;
  std::vector<SuiteEntry> controllers;
  std::vector<PlannedScenario> scenarios;
  std::vector<CompareJob> jobs;
  std::string fingerprint;  // equal for equal plans (suite text, base scenario, mode, seed, K)
};

// The suite's controllers on its scenarios (and its latency study), skipping a controller on a
// vehicle kind it does not list. Loads every scenario once to check it.
ComparePlan plan_suite(const CompareSuite& suite);

// `runs` runs per controller of the suite's Monte Carlo scenario, each with initial errors drawn
// uniformly within the suite's bounds and its own noise seed (the same draws for every
// controller: the comparison is paired).
ComparePlan plan_monte_carlo(const CompareSuite& suite, int runs);

// The jobs of shard k of n (1 <= k <= n): every n-th job, starting at job k - 1.
std::vector<int> shard_jobs(const ComparePlan& plan, int k, int n);

// The scenario of a job: the base, the scenario's settings, then the controller's.
Scenario job_scenario(const ComparePlan& plan, const CompareJob& job);

// plan.json: everything but the base scenario text, enough to report and to merge.
nlohmann::json plan_json(const ComparePlan& plan);
ComparePlan plan_from_json(const nlohmann::json& json, const std::string& origin);

}  // namespace agv::pipeline
