#pragma once

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/config/scenario.h"
#include "pipeline/run_result.h"

namespace agv::pipeline {

// The metrics of shared/DESIGN.md (summary.json keys). Optional values are absent (JSON null)
// when they are undefined, e.g. RMS after settling for a run that never settles.
struct RunMetrics {
  std::optional<double> settle_time_s;
  double max_abs_e_d_m = 0.0;
  double max_abs_e_theta_rad = 0.0;
  // Largest |e_d| in the periods after the one in which the first measurement arrived: what the
  // controller's commands made of the error (before, the vehicle drifts on its initial command
  // for the camera's latency whatever the controller).
  double max_abs_e_d_after_first_measurement_m = 0.0;
  std::optional<double> rms_e_d_m;        // after settling
  std::optional<double> rms_e_theta_rad;  // after settling
  double overshoot_e_d_m = 0.0;
  double max_abs_v_lateral_m_s = 0.0;
  double max_abs_accel_m_s2 = 0.0;
  int limit_violations = 0;
  int frames = 0;
  int frames_lost = 0;
  int frames_extrapolated = 0;     // lines carried back from the view: no remembered tape under
                                   //   the vehicle yet
  int frames_remembered_only = 0;  // no tape in view: the remembered tape under the vehicle
  std::optional<double> perception_rms_e_d_m;
  std::optional<double> perception_rms_e_theta_rad;
  double coverage_area_m2 = 0.0;  // seed 002: front and rear wheel tracks against the path
};

// First time after which |e_d| <= band_d and |e_theta| <= band_theta hold to the end of the
// samples, with the re-entry into the band interpolated linearly between samples; 0 when the
// samples never leave the bands; nullopt when the last sample is outside them.
std::optional<double> settle_time(const std::vector<double>& t_s, const std::vector<double>& e_d_m,
                                  const std::vector<double>& e_theta_rad, double band_d_m,
                                  double band_theta_rad);

// Largest excursion of e past zero on the side opposite its first sample (0 when none, or
// when the first sample is exactly 0).
double overshoot(const std::vector<double>& e);

// Root mean square of values[first..].
std::optional<double> rms_from(const std::vector<double>& values, size_t first);

// Area between a track (points in time order) and the path: the integral of |lateral offset|
// over the foot points' arc length, by the trapezoid rule, an interval whose ends lie on
// opposite sides split at the crossing (two triangles). Seed 002's coverage area of one wheel.
double track_area_m2(const control::Path& path, const std::vector<Eigen::Vector2d>& track);

RunMetrics compute_metrics(const RunResult& run, const Scenario& scenario);

// A value for summary.json and runs.jsonl: JSON null when there is none.
nlohmann::json optional_json(const std::optional<double>& value);

// summary.json: the metric keys of DESIGN.md plus what the run was and how it went.
nlohmann::json summary_json(const RunMetrics& metrics, const RunResult& run,
                            const Scenario& scenario);

}  // namespace agv::pipeline
