#include "pipeline/evaluation/compare_run.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "common/input_error.h"
#include "pipeline/config/scenario_run.h"

namespace agv::pipeline {
namespace {

std::optional<double> optional_from(const nlohmann::json& value) {
  if (value.is_null()) return std::nullopt;
  return value.get<double>();
}

}  // namespace

nlohmann::json compare_run_json(const CompareRun& run) {
  const RunMetrics& m = run.metrics;
  return {
      {"job", run.job},
      {"scenario", run.scenario},
      {"controller", run.controller},
      {"controller_name", run.controller_name},
      {"settle_time_s", optional_json(m.settle_time_s)},
      {"max_abs_e_d_m", m.max_abs_e_d_m},
      {"max_abs_e_theta_rad", m.max_abs_e_theta_rad},
      {"max_abs_e_d_after_first_measurement_m", m.max_abs_e_d_after_first_measurement_m},
      {"rms_e_d_m", optional_json(m.rms_e_d_m)},
      {"rms_e_theta_rad", optional_json(m.rms_e_theta_rad)},
      {"overshoot_e_d_m", m.overshoot_e_d_m},
      {"max_abs_v_lateral_m_s", m.max_abs_v_lateral_m_s},
      {"max_abs_accel_m_s2", m.max_abs_accel_m_s2},
      {"limit_violations", m.limit_violations},
      {"frames", m.frames},
      {"frames_lost", m.frames_lost},
      {"perception_rms_e_d_m", optional_json(m.perception_rms_e_d_m)},
      {"perception_rms_e_theta_rad", optional_json(m.perception_rms_e_theta_rad)},
      {"coverage_area_m2", m.coverage_area_m2},
      {"settle_band_e_d_m", run.settle_band_e_d_m},
      {"settle_band_e_theta_rad", run.settle_band_e_theta_rad},
      {"initial_e_d_m", run.initial_e_d_m},
      {"initial_e_theta_rad", run.initial_e_theta_rad},
      {"control_us_per_period", run.control_us_per_period},
      {"max_measurement_age_s", run.max_measurement_age_s},
      {"t_s", run.t_s},
      {"e_d_m", run.e_d_m},
      {"e_theta_rad", run.e_theta_rad},
  };
}

CompareRun compare_run_from_json(const nlohmann::json& j, const std::string& origin) {
  try {
    CompareRun run;
    run.job = j.at("job").get<int>();
    run.scenario = j.at("scenario").get<std::string>();
    run.controller = j.at("controller").get<std::string>();
    run.controller_name = j.at("controller_name").get<std::string>();
    RunMetrics& m = run.metrics;
    m.settle_time_s = optional_from(j.at("settle_time_s"));
    m.max_abs_e_d_m = j.at("max_abs_e_d_m").get<double>();
    m.max_abs_e_theta_rad = j.at("max_abs_e_theta_rad").get<double>();
    m.max_abs_e_d_after_first_measurement_m =
        j.at("max_abs_e_d_after_first_measurement_m").get<double>();
    m.rms_e_d_m = optional_from(j.at("rms_e_d_m"));
    m.rms_e_theta_rad = optional_from(j.at("rms_e_theta_rad"));
    m.overshoot_e_d_m = j.at("overshoot_e_d_m").get<double>();
    m.max_abs_v_lateral_m_s = j.at("max_abs_v_lateral_m_s").get<double>();
    m.max_abs_accel_m_s2 = j.at("max_abs_accel_m_s2").get<double>();
    m.limit_violations = j.at("limit_violations").get<int>();
    m.frames = j.at("frames").get<int>();
    m.frames_lost = j.at("frames_lost").get<int>();
    m.perception_rms_e_d_m = optional_from(j.at("perception_rms_e_d_m"));
    m.perception_rms_e_theta_rad = optional_from(j.at("perception_rms_e_theta_rad"));
    m.coverage_area_m2 = j.at("coverage_area_m2").get<double>();
    run.settle_band_e_d_m = j.at("settle_band_e_d_m").get<double>();
    run.settle_band_e_theta_rad = j.at("settle_band_e_theta_rad").get<double>();
    run.initial_e_d_m = j.at("initial_e_d_m").get<double>();
    run.initial_e_theta_rad = j.at("initial_e_theta_rad").get<double>();
    run.control_us_per_period = j.at("control_us_per_period").get<double>();
    run.max_measurement_age_s = j.at("max_measurement_age_s").get<double>();
    run.t_s = j.at("t_s").get<std::vector<double>>();
    run.e_d_m = j.at("e_d_m").get<std::vector<double>>();
    run.e_theta_rad = j.at("e_theta_rad").get<std::vector<double>>();
    if (run.e_d_m.size() != run.t_s.size() || run.e_theta_rad.size() != run.t_s.size())
      throw InputError("the error traces differ in length");
    return run;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(origin + ": not a run written by agv compare (" + e.what() + ")");
  } catch (const InputError& e) {
    throw InputError(origin + ": " + e.what());
  }
}

CompareRun run_compare_job(const ComparePlan& plan, const CompareJob& job) {
  const Scenario scenario = job_scenario(plan, job);
  const RunResult result = run_scenario(scenario);
  CompareRun run;
  run.job = job.index;
  run.scenario = plan.scenarios.at(job.scenario).entry.name;
  run.controller = plan.controllers.at(job.controller).name;
  run.controller_name = result.controller_name;
  run.metrics = compute_metrics(result, scenario);
  run.settle_band_e_d_m = scenario.metrics.settle_band_e_d_m;
  run.settle_band_e_theta_rad = scenario.metrics.settle_band_e_theta_rad;
  run.initial_e_d_m = scenario.initial_e_d_m;
  run.initial_e_theta_rad = scenario.initial_e_theta_rad;
  if (!result.rows.empty())
    run.control_us_per_period = 1e6 * result.total_times.control_s / result.rows.size();
  for (const TraceRow& row : result.rows) {
    run.t_s.push_back(row.t_s);
    run.e_d_m.push_back(row.truth.e_d_m);
    run.e_theta_rad.push_back(row.truth.e_theta_rad);
    if (row.has_measurement)
      run.max_measurement_age_s = std::max(run.max_measurement_age_s, row.measurement_age_s);
  }
  return run;
}

std::vector<CompareRun> run_compare_jobs(const ComparePlan& plan, const std::vector<int>& jobs,
                                         int threads, const CompareProgress& progress) {
  std::vector<int> parallel, alone;
  for (int j : jobs) {
    const CompareJob& job = plan.jobs.at(j);
    (plan.scenarios.at(job.scenario).threaded ? alone : parallel).push_back(j);
  }
  std::vector<std::optional<CompareRun>> runs(plan.jobs.size());
  std::mutex mutex;  // guards runs, done, failure and progress calls
  int done = 0;
  std::optional<std::string> failure;
  bool failure_is_input = false;
  std::atomic<size_t> next{0};

  // Each worker takes the next job of `list` until none is left or a run has failed. Errors are
  // kept as messages and thrown again on the calling thread.
  auto work = [&](const std::vector<int>& list) {
    for (size_t i = next.fetch_add(1); i < list.size(); i = next.fetch_add(1)) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (failure) return;
      }
      const CompareJob& job = plan.jobs[list[i]];
      try {
        CompareRun run = run_compare_job(plan, job);
        std::lock_guard<std::mutex> lock(mutex);
        runs[job.index] = std::move(run);
        ++done;
        if (progress) progress(done, static_cast<int>(jobs.size()), *runs[job.index]);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) {
          failure = plan.scenarios[job.scenario].entry.name + " with " +
                    plan.controllers[job.controller].name + ": " + e.what();
          failure_is_input = dynamic_cast<const InputError*>(&e) != nullptr;
        }
      }
    }
  };
  // Lockstep runs keep a processor busy each; threaded runs mostly wait for their clocks (about a
  // third of a processor each at the default rates) and run after them, never beside them, 1.5
  // per worker and per processor at a time (two per processor lengthened the measurements'
  // largest age from one or two camera frames to three or four in half of the default suites).
  auto run_pool = [&](const std::vector<int>& list, int workers) {
    next = 0;
    std::vector<std::thread> pool;
    for (int w = 0; w < std::min<int>(workers, static_cast<int>(list.size())); ++w)
      pool.emplace_back(work, std::cref(list));
    for (std::thread& t : pool) t.join();
  };
  const int processors = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  run_pool(parallel, std::max(1, threads));
  run_pool(alone, std::clamp(threads, 1, processors) * 3 / 2);
  if (failure) {
    if (failure_is_input) throw InputError(*failure);
    throw std::runtime_error(*failure);
  }
  std::vector<CompareRun> ordered;
  for (int j : jobs) ordered.push_back(std::move(*runs[j]));
  return ordered;
}

}  // namespace agv::pipeline
