#pragma once

#include <ostream>
#include <string>

#include "pipeline/run_result.h"

namespace agv::pipeline {

// trace.csv: one row per control period. Columns: time, true pose, true and measured errors,
// what the controller acted on, the command, what it asks of the wheels (Mecanum: four wheel
// speeds; dual steer: steer angle and speed of each wheel), measurement age and flags.
void write_trace_csv(std::ostream& out, const RunResult& run);

// frames.csv: one row per camera frame, perception against ground truth.
void write_frames_csv(std::ostream& out, const RunResult& run);

// measurements.csv of replay and track (shared/DESIGN.md): one row per frame, index,t_s,
// line_found,e_theta_rad,e_d_m,curvature_1_m,confidence,tape_width_m,no_line_reason, then
// points_used,lines_seen,junction_ahead,bad,source,perceive_ms,extrapolated,curvature_change_m,
// curvature_ahead_1_m and, with ground truth, true_e_theta_rad,true_e_d_m. Free text (the reason,
// the source) has its commas replaced.
void write_measurements_csv(std::ostream& out, const std::vector<FrameRecord>& frames,
                            bool with_truth);

}  // namespace agv::pipeline
