#include "pipeline/evaluation/metrics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace agv::pipeline {
namespace {

// Time at which |e| falls back to `band` between samples i and i + 1 (e(i+1) is inside); t(i)
// when e(i) is inside already.
double reentry_time(const std::vector<double>& t, const std::vector<double>& e, size_t i,
                    double band) {
  const double a = std::abs(e[i]), b = std::abs(e[i + 1]);
  if (a <= band) return t[i];
  if (a == b) return t[i + 1];
  const double fraction = std::clamp((a - band) / (a - b), 0.0, 1.0);
  return t[i] + fraction * (t[i + 1] - t[i]);
}

}  // namespace

nlohmann::json optional_json(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::optional<double> settle_time(const std::vector<double>& t, const std::vector<double>& e_d,
                                  const std::vector<double>& e_theta, double band_d,
                                  double band_theta) {
  const size_t n = t.size();
  if (n == 0) return std::nullopt;
  auto outside = [&](size_t i) {
    return std::abs(e_d[i]) > band_d || std::abs(e_theta[i]) > band_theta;
  };
  if (outside(n - 1)) return std::nullopt;
  size_t last_outside = n;
  for (size_t i = n; i-- > 0;) {
    if (outside(i)) {
      last_outside = i;
      break;
    }
  }
  if (last_outside == n) return 0.0;
  return std::max(reentry_time(t, e_d, last_outside, band_d),
                  reentry_time(t, e_theta, last_outside, band_theta));
}

double overshoot(const std::vector<double>& e) {
  if (e.empty() || e.front() == 0.0) return 0.0;
  const double sign = e.front() > 0.0 ? 1.0 : -1.0;
  double worst = 0.0;
  for (double v : e) worst = std::max(worst, -sign * v);
  return worst;
}

std::optional<double> rms_from(const std::vector<double>& values, size_t first) {
  if (first >= values.size()) return std::nullopt;
  double sum = 0.0;
  for (size_t i = first; i < values.size(); ++i) sum += values[i] * values[i];
  return std::sqrt(sum / (values.size() - first));
}

double track_area_m2(const control::Path& path, const std::vector<Eigen::Vector2d>& track) {
  double area_m2 = 0.0;
  std::optional<control::PathProjection> previous;
  for (const Eigen::Vector2d& point : track) {
    const control::PathProjection foot =
        previous ? path.project(point, previous->s_m, 0.5) : path.project(point);
    if (previous) {
      const double ds_m = std::abs(foot.s_m - previous->s_m);
      const double a = previous->lateral_m, b = foot.lateral_m;
      area_m2 += (a * b >= 0.0) ? 0.5 * (std::abs(a) + std::abs(b)) * ds_m
                                : 0.5 * (a * a + b * b) / (std::abs(a) + std::abs(b)) * ds_m;
    }
    previous = foot;
  }
  return area_m2;
}

RunMetrics compute_metrics(const RunResult& run, const Scenario& scenario) {
  RunMetrics m;
  std::vector<Eigen::Vector2d> front_track, rear_track;
  for (const TraceRow& row : run.rows) {
    front_track.push_back(row.front_wheel);
    rear_track.push_back(row.rear_wheel);
  }
  m.coverage_area_m2 =
      track_area_m2(scenario.path, front_track) + track_area_m2(scenario.path, rear_track);
  std::vector<double> t, e_d, e_theta;
  bool acting = false;  // a measurement arrived in an earlier period
  for (const TraceRow& row : run.rows) {
    t.push_back(row.t_s);
    e_d.push_back(row.truth.e_d_m);
    e_theta.push_back(row.truth.e_theta_rad);
    m.max_abs_e_d_m = std::max(m.max_abs_e_d_m, std::abs(row.truth.e_d_m));
    if (acting)
      m.max_abs_e_d_after_first_measurement_m =
          std::max(m.max_abs_e_d_after_first_measurement_m, std::abs(row.truth.e_d_m));
    if (row.measurement_arrived) acting = true;
    m.max_abs_e_theta_rad = std::max(m.max_abs_e_theta_rad, std::abs(row.truth.e_theta_rad));
    if (row.violations != 0) ++m.limit_violations;
  }
  // Lateral speed and acceleration of the reference point as commanded, the same for every
  // drive and law (a Mecanum vehicle moves sideways with vy, a DWA turns with wz): the speed
  // across the path, vx sin(e_theta) + vy cos(e_theta) with the true e_theta (else the one the
  // controller acted on), and the change of the velocity in the floor frame between periods
  // over the period, turning included (the vehicle starts at path speed, straight on, with
  // the heading of the first row).
  const double ts = scenario.controller.ts_s;
  Eigen::Vector2d previous_velocity = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  for (size_t i = 0; i < run.rows.size(); ++i) {
    const TraceRow& row = run.rows[i];
    const BodyTwist& c = row.output.command;
    const double e_theta_rad = row.has_truth             ? row.truth.e_theta_rad
                               : row.output.has_estimate ? row.output.estimate.e_theta_rad
                                                         : 0.0;
    m.max_abs_v_lateral_m_s =
        std::max(m.max_abs_v_lateral_m_s,
                 std::abs(c.vx_m_s * std::sin(e_theta_rad) + c.vy_m_s * std::cos(e_theta_rad)));
    if (i == 0) {
      yaw_rad = row.has_truth ? row.pose.yaw_rad : 0.0;
      previous_velocity =
          scenario.path_speed_m_s * Eigen::Vector2d(std::cos(yaw_rad), std::sin(yaw_rad));
    } else {
      yaw_rad =
          row.has_truth ? row.pose.yaw_rad : yaw_rad + run.rows[i - 1].output.command.wz_rad_s * ts;
    }
    const Eigen::Vector2d velocity =
        Eigen::Rotation2Dd(yaw_rad) * Eigen::Vector2d(c.vx_m_s, c.vy_m_s);
    m.max_abs_accel_m_s2 =
        std::max(m.max_abs_accel_m_s2, (velocity - previous_velocity).norm() / ts);
    previous_velocity = velocity;
  }
  m.settle_time_s = settle_time(t, e_d, e_theta, scenario.metrics.settle_band_e_d_m,
                                scenario.metrics.settle_band_e_theta_rad);
  if (m.settle_time_s) {
    const size_t first =
        static_cast<size_t>(std::lower_bound(t.begin(), t.end(), *m.settle_time_s) - t.begin());
    m.rms_e_d_m = rms_from(e_d, first);
    m.rms_e_theta_rad = rms_from(e_theta, first);
  }
  m.overshoot_e_d_m = overshoot(e_d);

  std::vector<double> perception_d, perception_theta;
  for (const FrameRecord& f : run.frames) {
    ++m.frames;
    if (!f.measurement.line_found) {
      ++m.frames_lost;
      continue;
    }
    if (f.measurement.extrapolated) ++m.frames_extrapolated;
    if (f.measurement.remembered_only) ++m.frames_remembered_only;
    if (!f.truth) continue;
    perception_d.push_back(f.measurement.e_d_m - f.truth->e_d_m);
    perception_theta.push_back(f.measurement.e_theta_rad - f.truth->e_theta_rad);
  }
  m.perception_rms_e_d_m = rms_from(perception_d, 0);
  m.perception_rms_e_theta_rad = rms_from(perception_theta, 0);
  return m;
}

nlohmann::json summary_json(const RunMetrics& m, const RunResult& run, const Scenario& s) {
  nlohmann::json j;
  j["settle_time_s"] = optional_json(m.settle_time_s);
  j["settled"] = m.settle_time_s.has_value();
  j["max_abs_e_d_m"] = m.max_abs_e_d_m;
  j["max_abs_e_theta_rad"] = m.max_abs_e_theta_rad;
  j["max_abs_e_d_after_first_measurement_m"] = m.max_abs_e_d_after_first_measurement_m;
  j["rms_e_d_m"] = optional_json(m.rms_e_d_m);
  j["rms_e_theta_rad"] = optional_json(m.rms_e_theta_rad);
  j["overshoot_e_d_m"] = m.overshoot_e_d_m;
  j["max_abs_v_lateral_m_s"] = m.max_abs_v_lateral_m_s;
  j["max_abs_accel_m_s2"] = m.max_abs_accel_m_s2;
  j["limit_violations"] = m.limit_violations;
  j["frames"] = m.frames;
  j["frames_lost"] = m.frames_lost;
  j["frames_extrapolated"] = m.frames_extrapolated;
  j["frames_remembered_only"] = m.frames_remembered_only;
  j["odometry"] = run.odometry_source;
  j["perception_rms_e_d_m"] = optional_json(m.perception_rms_e_d_m);
  j["perception_rms_e_theta_rad"] = optional_json(m.perception_rms_e_theta_rad);
  j["coverage_area_m2"] = m.coverage_area_m2;

  int saturated = 0, infeasible = 0, stopping = 0, holding = 0, horizon_sum = 0, horizon_count = 0,
      horizon_max = 0;
  double max_age_s = 0.0;
  for (const TraceRow& row : run.rows) {
    if (row.output.flags & control::kSaturated) ++saturated;
    if (row.output.flags & control::kNoFeasibleHorizon) ++infeasible;
    if (row.output.flags & control::kStopping) ++stopping;
    if (row.output.flags & control::kHolding) ++holding;
    if (row.output.horizon_steps > 0) {
      horizon_sum += row.output.horizon_steps;
      ++horizon_count;
      horizon_max = std::max(horizon_max, row.output.horizon_steps);
    }
    if (row.has_measurement) max_age_s = std::max(max_age_s, row.measurement_age_s);
  }
  j["scenario"] = s.source_name;
  j["camera"] = s.camera_name;
  j["controller"] = run.controller_name;
  j["mode"] = word_of(kLoopModeWords, s.loop.mode);
  j["seed"] = s.seed;
  j["ts_s"] = s.controller.ts_s;
  j["duration_s"] = s.duration_s;
  j["latency_frames"] = s.latency_frames;
  j["settle_band_e_d_m"] = s.metrics.settle_band_e_d_m;
  j["settle_band_e_theta_rad"] = s.metrics.settle_band_e_theta_rad;
  j["periods"] = run.rows.size();
  j["periods_saturated"] = saturated;
  j["periods_no_feasible_horizon"] = infeasible;
  j["periods_line_lost_holding"] = holding;
  j["periods_stopping"] = stopping;
  j["horizon_steps_mean"] = horizon_count ? static_cast<double>(horizon_sum) / horizon_count : 0.0;
  j["horizon_steps_max"] = horizon_max;
  j["max_measurement_age_s"] = max_age_s;
  j["queue"] = {{"pushed", run.queue.pushed},     {"popped", run.queue.popped},
                {"dropped", run.queue.dropped},   {"superseded", run.measurements_superseded},
                {"rejected", run.queue.rejected}, {"max_depth", run.queue.max_depth}};
  j["watchdog_stalls"] = nlohmann::json::array();
  for (const WatchdogStall& stall : run.stalls) {
    j["watchdog_stalls"].push_back({{"thread", stall.thread},
                                    {"last_seen_s", stall.last_seen_s},
                                    {"silent_for_s", stall.silent_for_s}});
  }
  const double frames = std::max(1, m.frames);
  const double periods = std::max<size_t>(1, run.rows.size());
  j["timing"] = {{"wall_s", run.wall_s},
                 {"setup_wall_s", run.setup_wall_s},
                 {"render_ms_mean", 1e3 * run.total_times.source_s / frames},
                 {"perceive_ms_mean", 1e3 * run.total_times.perceive_s / frames},
                 {"control_ms_mean", 1e3 * run.total_times.control_s / periods},
                 {"max_tick_lateness_s", run.max_tick_lateness_s}};
  return j;
}

}  // namespace agv::pipeline
