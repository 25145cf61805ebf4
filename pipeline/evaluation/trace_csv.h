#pragma once

#include <ostream>
#include <string>

#include "pipeline/closed_loop.h"

namespace agv::pipeline {

// trace.csv: one row per control period. Columns: time, true pose, true and measured errors,
// what the controller acted on, the command, wheel speeds, measurement age and flags.
void write_trace_csv(std::ostream& out, const RunResult& run);

// frames.csv: one row per camera frame, perception against ground truth.
void write_frames_csv(std::ostream& out, const RunResult& run);

}  // namespace agv::pipeline
