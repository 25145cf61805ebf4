#include "tools/compare_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "common/input_error.h"
#include "pipeline/config/builtin_files.h"
#include "pipeline/config/scenario_loader.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/evaluation/compare_plan.h"
#include "pipeline/evaluation/compare_run.h"
#include "pipeline/evaluation/output_folder.h"
#include "tools/build_info.h"
#include "tools/compare_report.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"

namespace agv::tools {
namespace {

namespace fs = std::filesystem;
using pipeline::ComparePlan;
using pipeline::CompareRun;

constexpr const char* kPlanFile = "plan.json";
constexpr const char* kRunsFile = "runs.jsonl";

ComparePlan make_plan(const CompareArgs& args) {
  const pipeline::ScenarioText source = pipeline::scenario_text_for_command(
      args.suite_file, "default_suite.yaml", "built-in default suite");
  const pipeline::ScenarioText base =
      pipeline::scenario_text_for_command("", "default_scenario.yaml", "built-in default scenario");
  pipeline::CompareSuite suite = pipeline::load_suite(source, base);
  suite.base.builtin_files =
      pipeline::builtin_files();  // a suite's base_scenario file may name them
  if (args.seed >= 0) {
    suite.seed = static_cast<std::uint64_t>(args.seed);
    suite.text += "\n# --seed " + std::to_string(args.seed);  // part of the fingerprint
  }
  return args.monte_carlo_runs > 0 ? pipeline::plan_monte_carlo(suite, args.monte_carlo_runs)
                                   : pipeline::plan_suite(suite);
}

std::pair<int, int> parse_shard(const std::string& text) {
  int k = 0, n = 0;
  char end = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &k, &n, &end) != 2 || k < 1 || n < 1 || k > n)
    throw InputError("--shard " + text + ": expected K/N with 1 <= K <= N, e.g. --shard 2/4");
  return {k, n};
}

void write_runs(const pipeline::OutputFolder& folder, const ComparePlan& plan, int k, int n,
                const std::vector<CompareRun>& runs) {
  nlohmann::json plan_file = pipeline::plan_json(plan);
  plan_file["shard"] = {k, n};
  std::ofstream out_plan(folder.file(kPlanFile));
  out_plan << plan_file.dump(1) << '\n';
  std::ofstream out_runs(folder.file(kRunsFile));
  for (const CompareRun& r : runs) out_runs << pipeline::compare_run_json(r).dump() << '\n';
  if (!out_plan || !out_runs) throw InputError(folder.target().string() + ": cannot write");
}

nlohmann::json read_json_file(const fs::path& file) {
  std::ifstream in(file);
  if (!in)
    throw InputError(file.string() + ": cannot open (is this an agv compare output folder?)");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not valid JSON (" + e.what() + ")");
  }
}

// Reads shard folders written by `agv compare --shard K/N` (or whole runs) of one plan: every
// job once, from shards of the same plan.
std::pair<ComparePlan, std::vector<CompareRun>> read_shards(const std::vector<std::string>& dirs) {
  std::optional<ComparePlan> plan;
  std::optional<int> shard_count;
  std::set<int> shards_seen;
  std::vector<std::optional<CompareRun>> runs;
  for (const std::string& dir : dirs) {
    const fs::path plan_path = fs::path(dir) / kPlanFile;
    const nlohmann::json plan_file = read_json_file(plan_path);
    ComparePlan this_plan = pipeline::plan_from_json(plan_file, plan_path.string());
    int k = 1, n = 1;
    try {
      k = plan_file.at("shard").at(0).get<int>();
      n = plan_file.at("shard").at(1).get<int>();
    } catch (const nlohmann::json::exception&) {
      throw InputError(plan_path.string() + ": key 'shard': expected [K, N]");
    }
    if (!plan) {
      plan = this_plan;
      shard_count = n;
      runs.resize(plan->jobs.size());
    } else if (this_plan.fingerprint != plan->fingerprint) {
      throw InputError(plan_path.string() + ": is a shard of another plan (fingerprint " +
                       this_plan.fingerprint + ", expected " + plan->fingerprint + " as in " +
                       dirs.front() + "): same suite, seed and mode needed");
    } else if (n != *shard_count) {
      throw InputError(plan_path.string() + ": shard " + std::to_string(k) + "/" +
                       std::to_string(n) + " does not match the " + std::to_string(*shard_count) +
                       " shards of " + dirs.front());
    }
    if (!shards_seen.insert(k).second)
      throw InputError(plan_path.string() + ": shard " + std::to_string(k) + " is given twice");
    const fs::path runs_path = fs::path(dir) / kRunsFile;
    std::ifstream in(runs_path);
    if (!in) throw InputError(runs_path.string() + ": cannot open");
    std::string line;
    for (int row = 1; std::getline(in, line); ++row) {
      if (line.empty()) continue;
      const std::string origin = runs_path.string() + " line " + std::to_string(row);
      nlohmann::json json;
      try {
        json = nlohmann::json::parse(line);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(origin + ": not valid JSON (" + e.what() + ")");
      }
      CompareRun run = pipeline::compare_run_from_json(json, origin);
      if (run.job < 0 || run.job >= static_cast<int>(runs.size()))
        throw InputError(origin + ": job " + std::to_string(run.job) + " is not in the plan");
      if (runs[run.job])
        throw InputError(origin + ": job " + std::to_string(run.job) + " appears twice");
      runs[run.job] = std::move(run);
    }
  }
  std::vector<CompareRun> all;
  std::string missing;
  int missing_count = 0;
  for (size_t j = 0; j < runs.size(); ++j) {
    if (runs[j]) {
      all.push_back(std::move(*runs[j]));
    } else if (++missing_count <= 5) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(j);
    }
  }
  if (missing_count > 0) {
    std::string absent;
    for (int k = 1; k <= *shard_count; ++k)
      if (!shards_seen.count(k)) absent += (absent.empty() ? "" : ", ") + std::to_string(k);
    throw InputError(
        "--merge: " + std::to_string(missing_count) + " of " + std::to_string(runs.size()) +
        " runs are missing (jobs " + missing + (missing_count > 5 ? ", ..." : "") + ")" +
        (absent.empty() ? ""
                        : "; shards not given: " + absent + " of " + std::to_string(*shard_count)));
  }
  return {*plan, all};
}

void print_summary(const ComparePlan& plan, const std::vector<CompareRun>& runs) {
  if (plan.mode == "monte_carlo") {
    for (const MonteCarloSummary& s : summarise_monte_carlo(plan, runs)) {
      auto seconds = [](double t) {
        char text[32];
        if (std::isinf(t)) return std::string("never");
        std::snprintf(text, sizeof(text), "%.2f s", t);
        return std::string(text);
      };
      std::printf(
          "%-22s settled %d/%d | settle median %s, p95 %s | max |e_d| after the 1st measurement "
          "median "
          "%.2f mm, p95 %.2f mm, worst %.2f mm\n",
          s.controller.c_str(), s.settled, s.runs, seconds(s.settle_median_s).c_str(),
          seconds(s.settle_p95_s).c_str(), 1e3 * s.max_e_d_median_m, 1e3 * s.max_e_d_p95_m,
          1e3 * s.max_e_d_worst_m);
    }
    return;
  }
  // One line per controller: its settle time in each scenario, in the plan's order.
  for (const pipeline::SuiteEntry& c : plan.controllers) {
    std::string line = c.name + ": settle";
    for (const CompareRun& r : runs) {
      if (r.controller != c.name) continue;
      char cell[96];
      if (r.metrics.settle_time_s)
        std::snprintf(cell, sizeof(cell), " %s %.2f s,", r.scenario.c_str(),
                      *r.metrics.settle_time_s);
      else
        std::snprintf(cell, sizeof(cell), " %s never,", r.scenario.c_str());
      line += cell;
    }
    line.pop_back();
    std::printf("%s\n", line.c_str());
  }
}

}  // namespace

void add_compare_command(CLI::App& app, CompareArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Runs every controller of a suite on every scenario of it (closed loop from camera "
      "images) and writes table.md, table.csv, one plot per scenario and index.html. The "
      "built-in default suite (pipeline/config/default_suite.yaml) covers seed 000's Tables 1 and "
      "2, a larger initial error, a curve, heavy noise and blur, and a latency study (0-3 "
      "frames and a threaded run, compensation on and off). Deterministic for a given seed "
      "except the measured compute times and the threaded runs.");
  sub->add_option("--suite", args.suite_file, "Suite YAML (default: the built-in default suite)");
  sub->add_option("--out", args.out_dir, "Output folder (default: runs/<date-time>)");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
  sub->add_option("--jobs", args.jobs,
                  "Runs in parallel (default: one per processor; threaded runs, which mostly "
                  "wait for their clocks, 1.5 times as many, at most 1.5 per processor)")
      ->check(CLI::Range(1, 256));
  sub->add_option("--seed", args.seed,
                  "Seed of every run's noise and texture (default: the suite's)")
      ->check(CLI::Range(0LL, 2147483647LL));
  sub->add_option("--monte-carlo", args.monte_carlo_runs,
                  "K runs per controller of the suite's monte_carlo scenario with random initial "
                  "errors and noise seeds; reports median, p95 and worst (default: no Monte Carlo, "
                  "the suite)")
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--shard", args.shard,
                  "Run only slice K of N of the runs (every N-th run from the K-th) and write "
                  "their rows, for a batch engine (GNU parallel, a Slurm job array); join the "
                  "slices with --merge")
      ->type_name("K/N");
  sub->add_option("--merge", args.merge_dirs,
                  "Join the output folders of all N shards into one report, the same as a single "
                  "run's (runs nothing)")
      ->type_name("DIR...")
      ->excludes("--shard")
      ->excludes("--suite")
      ->excludes("--seed")
      ->excludes("--monte-carlo");  // the shards' plan says what was run
  sub->add_flag("--quiet", args.quiet, "No progress bar");
  sub->add_flag("--json", args.json,
                "Print the result as JSON (every run's settle time, max |e_d|, limit violations; "
                "null settle: never within the bands) instead of the text summary");
}

int run_compare(const CompareArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  // The output folder first: a folder that may not be replaced is refused before the runs.
  pipeline::OutputFolder folder(args.out_dir, kPlanFile, args.force);
  ComparePlan plan;
  std::vector<CompareRun> runs;
  int k = 1, n = 1;
  if (!args.merge_dirs.empty()) {
    std::tie(plan, runs) = read_shards(args.merge_dirs);
  } else {
    if (!args.shard.empty()) std::tie(k, n) = parse_shard(args.shard);
    plan = make_plan(args);
    const std::vector<int> jobs = pipeline::shard_jobs(plan, k, n);
    const int threads = args.jobs > 0
                            ? args.jobs
                            : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    ProgressBar bar("compare: " + std::to_string(jobs.size()) + " runs" +
                        (n > 1 ? " (shard " + args.shard + ")" : "") + " on " +
                        std::to_string(threads) + " threads",
                    !args.quiet);
    runs = pipeline::run_compare_jobs(plan, jobs, threads,
                                      [&](int done, int total, const CompareRun&) {
                                        bar.update(static_cast<double>(done) / total);
                                      });
  }
  write_runs(folder, plan, k, n, runs);
  std::vector<std::string> warnings;
  if (n == 1) warnings = write_compare_report(folder.file(""), plan, runs);
  folder.commit();
  for (const std::string& w : warnings) std::cerr << "agv compare: warning: " << w << '\n';

  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.json) {
    nlohmann::json j;
    j["runs"] = runs.size();
    j["mode"] = plan.mode;
    j["suite"] = plan.suite_name;
    j["seed"] = plan.seed;
    j["wall_s"] = wall_s;
    j["output"] = folder.target().string();
    j["agv"] = build_json();
    j["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
    for (const CompareRun& r : runs) {
      j["per_run"].push_back(
          {{"controller", r.controller},
           {"scenario", r.scenario},
           {"settle_s", r.metrics.settle_time_s ? nlohmann::json(*r.metrics.settle_time_s)
                                                : nlohmann::json(nullptr)},
           {"max_abs_e_d_m", r.metrics.max_abs_e_d_m},
           {"limit_violations", r.metrics.limit_violations}});
    }
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  if (n == 1) print_summary(plan, runs);
  std::printf(
      "compare: %zu runs (%s, suite '%s', seed %llu%s) in %.1f s\noutput: %s%s\n", runs.size(),
      plan.mode.c_str(), plan.suite_name.c_str(), static_cast<unsigned long long>(plan.seed),
      n > 1 ? (", shard " + args.shard).c_str() : "", wall_s, folder.target().string().c_str(),
      n > 1 ? " (rows only: join all shards with agv compare --merge)" : "/index.html");
  return 0;
}

}  // namespace agv::tools
