#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/evaluation/compare_plan.h"
#include "pipeline/evaluation/metrics.h"

namespace agv::pipeline {

// What `agv compare` keeps of one run: its metrics and its true error trace.
struct CompareRun {
  int job = 0;
  std::string scenario, controller;  // names in the plan
  std::string controller_name;       // as the controller names itself
  RunMetrics metrics;
  double settle_band_e_d_m = 0.0, settle_band_e_theta_rad = 0.0;
  double initial_e_d_m = 0.0, initial_e_theta_rad = 0.0;
  double control_us_per_period = 0.0;  // mean compute time of the controller (measured)
  double max_measurement_age_s = 0.0;
  std::vector<double> t_s, e_d_m, e_theta_rad;  // true errors, one per control period
};

// One line of runs.jsonl. Doubles are written so that reading gives the same bits.
nlohmann::json compare_run_json(const CompareRun& run);
CompareRun compare_run_from_json(const nlohmann::json& json, const std::string& origin);

// Runs one job of the plan.
CompareRun run_compare_job(const ComparePlan& plan, const CompareJob& job);

// Called after each finished run with the number done and the total.
using CompareProgress = std::function<void(int done, int total, const CompareRun& last)>;

// Runs the given jobs of the plan on `threads` worker threads; threaded-loop jobs (real time:
// they must not share the processors with lockstep runs to keep their clocks) run afterwards,
// up to `threads` and the processors at a time. Returns the runs in job order. The first error in any run is rethrown here after every worker has stopped.
std::vector<CompareRun> run_compare_jobs(const ComparePlan& plan, const std::vector<int>& jobs,
                                         int threads, const CompareProgress& progress = {});

}  // namespace agv::pipeline
