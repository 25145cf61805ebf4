#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose2.h"
#include "control/path.h"
#include "perception/line_estimator.h"

namespace agv::pipeline {

struct PerceptionBenchmarkOptions {
  int conditions = 60;  // random (camera, floor, tape, light, path) draws
  int frames_per_condition = 10;
  int empty_conditions = 20;  // conditions without tape (frames must give no line)
  std::uint64_t seed = 1;
  // Where to write annotated frames that were missed or off by more than 1 mm / 0.5 deg, or a
  // line reported without tape ("": none); at most max_saved of them.
  std::string save_failures_dir;
  int max_saved = 60;
};

// One rendered frame of the benchmark and what perception made of it.
struct BenchmarkFrame {
  int condition = 0;
  bool has_tape = true;
  bool curved = false;
  double visible_fraction = 0.0;  // length of tape in view / the longest it could be
  bool line_found = false;
  double error_e_d_m = 0.0, error_e_theta_rad = 0.0;
  // The same errors where the evidence nearest the vehicle lies, before any extrapolation to
  // the vehicle's origin: the estimated line's offset from the true path and its heading error
  // at its point nearest the nearest end of the evidence.
  double near_error_offset_m = 0.0, near_error_heading_rad = 0.0;
  double perceive_ms = 0.0;
  // The Canny + HoughLinesP baseline (perception::HoughBaseline) on the same frame.
  bool baseline_found = false;
  double baseline_error_e_d_m = 0.0, baseline_error_e_theta_rad = 0.0;
  double baseline_ms = 0.0;
  std::string conditions_text;  // the draw, for a reader of the CSV
};

struct PerceptionBenchmarkResult {
  std::vector<BenchmarkFrame> frames;
  nlohmann::json summary;  // the figures, for humans and scripts
};

// How far the followed line of `detection` lies from the true `path` where its evidence begins
// nearest the vehicle at `pose`, and how its direction differs there: what perception measured,
// before the curve is carried back to the vehicle's origin. offset_m is the signed distance of
// the line's point nearest that end of the evidence from the path (positive left of it),
// heading_rad the line's yaw there minus the path's. `s_hint_m`: arc length of the path near
// the vehicle.
struct NearEvidenceError {
  double offset_m = 0.0, heading_rad = 0.0;
};
NearEvidenceError error_at_nearest_evidence(const perception::LineDetection& detection,
                                            const control::Path& path, const Pose2& pose,
                                            double s_hint_m);

// Renders frames over randomised conditions (tape colours and polarities, widths 10-50 mm,
// floors, lighting, shadow, glare, noise, motion blur, camera height 0.12-0.25 m, tilt up to
// 10 deg, yaw, lens distortion, straight tape and arcs of 0.3-3 m radius), measures each with
// perception, and compares with the ground truth. Arcs are laid so that the vehicle and its view
// lie on the same arc. Deterministic for the seed.
PerceptionBenchmarkResult run_perception_benchmark(
    const PerceptionBenchmarkOptions& options, const std::function<void(double)>& progress = {});

}  // namespace agv::pipeline
