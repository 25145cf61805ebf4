#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/evaluation/compare_plan.h"
#include "pipeline/evaluation/compare_run.h"

namespace agv::tools {

// Writes the report of a complete comparison into `dir`: table.md, table.csv, series/*.csv,
// plots/*.png and index.html (suite), or monte_carlo.csv, table.md, histogram PNGs and
// index.html (Monte Carlo). `runs` holds every job of the plan, in job order. Returns the
// warnings (plots that could not be drawn); the tables are written regardless.
std::vector<std::string> write_compare_report(const std::filesystem::path& dir,
                                              const pipeline::ComparePlan& plan,
                                              const std::vector<pipeline::CompareRun>& runs);

// The Monte Carlo distribution of one controller, for the report and the terminal.
struct MonteCarloSummary {
  std::string controller;
  int runs = 0, settled = 0, limit_violations = 0;
  // Settle time: runs that never settle count as infinitely slow (quantiles may be infinite).
  double settle_median_s = 0.0, settle_p95_s = 0.0, settle_worst_s = 0.0;
  // Max |e_d| after the first measurement arrived (RunMetrics): what the controller made of it.
  double max_e_d_median_m = 0.0, max_e_d_p95_m = 0.0, max_e_d_worst_m = 0.0;
  double max_e_theta_median_rad = 0.0, max_e_theta_p95_rad = 0.0, max_e_theta_worst_rad = 0.0;
};
std::vector<MonteCarloSummary> summarise_monte_carlo(const pipeline::ComparePlan& plan,
                                                     const std::vector<pipeline::CompareRun>& runs);

}  // namespace agv::tools
