#include "pipeline/evaluation/compare_plan.h"

#include <gtest/gtest.h>

#include <set>

#include "common/input_error.h"
#include "pipeline/config/builtin_files.h"

namespace agv::pipeline {
namespace {

// Two controllers on Mecanum, one only for dual steer; two scenarios, one of them dual steer;
// a latency study of 0 and 2 frames without a threaded run.
const char* kSuite = R"(
name: test
seed: 3
controllers:
  - {name: fs, set: {controller.kind: finite_step}}
  - {name: pid, set: {controller.kind: pid}}
  - {name: dwa_dual_only, set: {controller.kind: dwa}, vehicles: [dual_steer]}
scenarios:
  - {name: slow, about: "0.3 m/s", set: {duration_s: 1.0}}
  - {name: dual, set: {duration_s: 1.0, vehicle.kind: dual_steer}}
latency_study:
  scenario: slow
  frames: [0, 2]
monte_carlo:
  scenario: slow
  e_theta_max_rad: 0.1
  e_d_max_m: 0.01
)";

ScenarioText suite_text(const std::string& body, const std::string& name = "suite.yaml") {
  ScenarioText t;
  t.text = body;
  t.name = name;
  t.builtin_files = pipeline::builtin_files();
  return t;
}

CompareSuite suite_of(const std::string& body) {
  return load_suite(suite_text(body),
                    suite_text(pipeline::builtin_files().at("default_scenario.yaml"),
                               "built-in default scenario"));
}

std::string error_of(const std::string& body, bool plan = false) {
  try {
    const CompareSuite suite = suite_of(body);
    if (plan) plan_suite(suite);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ComparePlan, EveryControllerOnEveryScenarioItsVehicleAllows) {
  const ComparePlan plan = plan_suite(suite_of(kSuite));
  std::vector<std::string> names;
  for (const PlannedScenario& s : plan.scenarios) names.push_back(s.entry.name);
  EXPECT_EQ(names, (std::vector<std::string>{"slow", "dual", "latency_0_comp", "latency_0_nocomp",
                                             "latency_2_comp", "latency_2_nocomp"}));
  // Mecanum scenarios: fs and pid (2 each, 5 scenarios); the dual-steer one: all three.
  ASSERT_EQ(plan.jobs.size(), 5u * 2u + 3u);
  for (size_t i = 0; i < plan.jobs.size(); ++i) EXPECT_EQ(plan.jobs[i].index, static_cast<int>(i));
  EXPECT_EQ(plan.jobs[2].scenario, 1);
  EXPECT_EQ(plan.jobs[4].controller, 2);  // dual: fs, pid, dwa_dual_only

  // The last job: latency_2_nocomp with pid; its scenario has every layer applied.
  const Scenario last = job_scenario(plan, plan.jobs.back());
  EXPECT_EQ(last.latency_frames, 2);
  EXPECT_FALSE(last.controller.latency_compensation);
  EXPECT_EQ(last.controller.kind, ControllerKind::kPid);
  EXPECT_DOUBLE_EQ(last.duration_s, 1.0);
  EXPECT_EQ(last.seed, 3u);
  EXPECT_TRUE(plan.scenarios[5].latency_label == "2" && !plan.scenarios[5].compensation);
}

TEST(ComparePlan, ShardsPartitionTheJobs) {
  const ComparePlan plan = plan_suite(suite_of(kSuite));
  for (int n = 1; n <= 5; ++n) {
    std::multiset<int> seen;
    for (int k = 1; k <= n; ++k) {
      for (int j : shard_jobs(plan, k, n)) seen.insert(j);
    }
    ASSERT_EQ(seen.size(), plan.jobs.size()) << n << " shards";
    for (int j = 0; j < static_cast<int>(plan.jobs.size()); ++j) EXPECT_EQ(seen.count(j), 1u);
  }
  EXPECT_THROW(shard_jobs(plan, 0, 2), InputError);
  EXPECT_THROW(shard_jobs(plan, 3, 2), InputError);
}

TEST(ComparePlan, FingerprintNamesThePlanAndJsonRoundTrips) {
  const ComparePlan a = plan_suite(suite_of(kSuite));
  EXPECT_EQ(a.fingerprint, plan_suite(suite_of(kSuite)).fingerprint);
  std::string other = kSuite;
  other.replace(other.find("seed: 3"), 7, "seed: 4");
  EXPECT_NE(a.fingerprint, plan_suite(suite_of(other)).fingerprint);
  EXPECT_NE(a.fingerprint, plan_monte_carlo(suite_of(kSuite), 2).fingerprint);

  const ComparePlan b = plan_from_json(plan_json(a), "plan.json");
  EXPECT_EQ(plan_json(b), plan_json(a));
  EXPECT_EQ(b.scenarios[4].latency_label, "2");
  EXPECT_THROW(plan_from_json(nlohmann::json{{"mode", "suite"}}, "plan.json"), InputError);
}

TEST(ComparePlan, MonteCarloDrawsWithinTheBoundsTheSameForEveryController) {
  const ComparePlan plan = plan_monte_carlo(suite_of(kSuite), 20);
  ASSERT_EQ(plan.jobs.size(), 40u);  // the Monte Carlo scenario is Mecanum: fs and pid
  std::set<std::uint64_t> seeds;
  double largest_theta = 0.0, largest_d = 0.0;
  for (size_t i = 0; i < plan.jobs.size(); i += 2) {
    ASSERT_EQ(plan.jobs[i].scenario, plan.jobs[i + 1].scenario);  // paired: same draw
    const Scenario s = job_scenario(plan, plan.jobs[i]);
    EXPECT_LE(std::abs(s.initial_e_theta_rad), 0.1);
    EXPECT_LE(std::abs(s.initial_e_d_m), 0.01);
    largest_theta = std::max(largest_theta, std::abs(s.initial_e_theta_rad));
    largest_d = std::max(largest_d, std::abs(s.initial_e_d_m));
    seeds.insert(s.seed);
  }
  // 20 uniform draws: the largest is above half the bound unless the draws are broken
  // (probability 2^-20 each).
  EXPECT_GT(largest_theta, 0.05);
  EXPECT_GT(largest_d, 0.005);
  EXPECT_EQ(seeds.size(), 20u);  // a fresh noise seed per run
  // Deterministic: the same plan again.
  EXPECT_EQ(plan_json(plan), plan_json(plan_monte_carlo(suite_of(kSuite), 20)));
  EXPECT_THROW(plan_monte_carlo(suite_of(kSuite), 0), InputError);
}

TEST(ComparePlan, BadSuitesNameTheFileAndKey) {
  EXPECT_NE(error_of("controlers: []\n").find("suite.yaml"), std::string::npos);
  EXPECT_NE(error_of("controllers: []\nscenarios: []\n").find("controllers"), std::string::npos);
  std::string typo = kSuite;
  typo.replace(typo.find("monte_carlo:"), 12, "monte_carlos:");
  EXPECT_NE(error_of(typo).find("monte_carlos"), std::string::npos);
  std::string twice = kSuite;
  twice.replace(twice.find("name: pid"), 9, "name: fs");
  EXPECT_NE(error_of(twice).find("'fs' is used twice"), std::string::npos);
  std::string no_such = kSuite;
  no_such.replace(no_such.find("scenario: slow"), 14, "scenario: fast");
  EXPECT_NE(error_of(no_such).find("no scenario named 'fast'"), std::string::npos);
  std::string bad_name = kSuite;
  bad_name.replace(bad_name.find("name: slow"), 10, "name: a/b");
  EXPECT_NE(error_of(bad_name).find("expected a word"), std::string::npos);
  // A key the scenario does not have is refused when the plan is made, before any run.
  std::string bad_key = kSuite;
  bad_key.replace(bad_key.find("{duration_s: 1.0}"), 17, "{duraton_s: 1.0}");
  EXPECT_NE(error_of(bad_key, true).find("duraton_s"), std::string::npos);
}

}  // namespace
}  // namespace agv::pipeline
