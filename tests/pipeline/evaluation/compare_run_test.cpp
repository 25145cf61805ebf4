#include "pipeline/evaluation/compare_run.h"

#include <gtest/gtest.h>

#include <string>

#include "common/input_error.h"
#include "pipeline/config/builtin_files.h"

namespace agv::pipeline {
namespace {

// The plan of a suite given as text, on the built-in default scenario.
ComparePlan plan_of(const std::string& suite_text) {
  ScenarioText suite;
  suite.name = "suite.yaml";
  suite.text = suite_text;
  ScenarioText base;
  base.text = pipeline::builtin_files().at("default_scenario.yaml");
  base.name = "built-in default scenario";
  base.builtin_files = pipeline::builtin_files();
  return plan_suite(load_suite(suite, base));
}

ComparePlan small_plan() {
  return plan_of(R"(
controllers:
  - {name: fs, set: {controller.kind: finite_step}}
  - {name: pid, set: {controller.kind: pid}}
scenarios:
  - {name: short, set: {duration_s: 0.6}}
  - {name: fast, set: {duration_s: 0.6, path_speed_m_s: 0.5, controller.input: pose}}
)");
}

void expect_same_results(const CompareRun& a, const CompareRun& b) {
  EXPECT_EQ(a.job, b.job);
  EXPECT_EQ(a.scenario, b.scenario);
  EXPECT_EQ(a.controller, b.controller);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.e_d_m, b.e_d_m);
  EXPECT_EQ(a.e_theta_rad, b.e_theta_rad);
  EXPECT_EQ(a.metrics.settle_time_s, b.metrics.settle_time_s);
  EXPECT_EQ(a.metrics.max_abs_e_d_m, b.metrics.max_abs_e_d_m);
  EXPECT_EQ(a.metrics.rms_e_d_m, b.metrics.rms_e_d_m);
  EXPECT_EQ(a.metrics.coverage_area_m2, b.metrics.coverage_area_m2);
}

// Runs on worker threads give the same results as one after another (the plan fixes every seed);
// the results come back in job order whatever order the workers finish in. Two of the four runs
// render and measure frames (renderers and estimators side by side on threads: this test also
// runs under ThreadSanitizer), two take the errors from the pose (fast).
TEST(CompareRunner, ParallelRunsEqualSerialRunsInJobOrder) {
  const ComparePlan plan = small_plan();
  const std::vector<int> all{0, 1, 2, 3};
  int progress_calls = 0;
  const std::vector<CompareRun> parallel =
      run_compare_jobs(plan, all, 3, [&](int done, int total, const CompareRun&) {
        ++progress_calls;
        EXPECT_EQ(total, 4);
        EXPECT_LE(done, 4);
      });
  EXPECT_EQ(progress_calls, 4);
  ASSERT_EQ(parallel.size(), 4u);
  for (int j = 0; j < 4; ++j) {
    EXPECT_EQ(parallel[j].job, j);
    expect_same_results(parallel[j], run_compare_job(plan, plan.jobs[j]));
  }
  EXPECT_EQ(parallel[1].controller, "pid");
  EXPECT_EQ(parallel[2].scenario, "fast");
  EXPECT_EQ(parallel[0].t_s.size(), 7u);  // 0.6 s at 0.1 s: t = 0 .. 0.6
  // A shard's jobs only, in the order asked.
  const std::vector<CompareRun> some = run_compare_jobs(plan, {1, 3}, 2);
  ASSERT_EQ(some.size(), 2u);
  expect_same_results(some[0], parallel[1]);
  expect_same_results(some[1], parallel[3]);
}

// Threaded runs (real time) run after the lockstep ones, several at a time: every run comes back,
// in job order, whether the workers are one or several (under ThreadSanitizer: two threaded
// loops side by side).
TEST(CompareRunner, ThreadedRunsComeBackInJobOrder) {
  const ComparePlan plan = plan_of(R"(
controllers:
  - {name: fs, set: {controller.kind: finite_step}}
  - {name: pid, set: {controller.kind: pid}}
scenarios:
  - {name: short, set: {duration_s: 0.3}}
latency_study:
  scenario: short
  frames: [0]
  threaded: {camera_fps: 30.0, time_scale: 4.0, latency_frames: 1}
)");
  std::vector<int> all;
  int threaded = 0;
  for (const CompareJob& job : plan.jobs) {
    all.push_back(job.index);
    threaded += plan.scenarios[job.scenario].threaded ? 1 : 0;
  }
  ASSERT_GE(threaded, 4);  // two controllers, compensation on and off
  for (int workers : {1, 2}) {
    const std::vector<CompareRun> runs = run_compare_jobs(plan, all, workers);
    ASSERT_EQ(runs.size(), all.size());
    for (size_t j = 0; j < runs.size(); ++j) {
      EXPECT_EQ(runs[j].job, all[j]);
      EXPECT_FALSE(runs[j].t_s.empty());
    }
  }
}

TEST(CompareRunner, JsonRowsReadBackBitForBit) {
  const ComparePlan plan = small_plan();
  const CompareRun run = run_compare_job(plan, plan.jobs[0]);
  const CompareRun back =
      compare_run_from_json(nlohmann::json::parse(compare_run_json(run).dump()), "runs.jsonl");
  expect_same_results(run, back);
  EXPECT_EQ(run.control_us_per_period, back.control_us_per_period);
  EXPECT_EQ(run.metrics.overshoot_e_d_m, back.metrics.overshoot_e_d_m);
  EXPECT_EQ(run.settle_band_e_theta_rad, back.settle_band_e_theta_rad);
  nlohmann::json broken = compare_run_json(run);
  broken["e_d_m"].erase(0);
  EXPECT_THROW(compare_run_from_json(broken, "runs.jsonl line 3"), InputError);
  broken.erase("t_s");
  EXPECT_THROW(compare_run_from_json(broken, "runs.jsonl line 3"), InputError);
}

}  // namespace
}  // namespace agv::pipeline
