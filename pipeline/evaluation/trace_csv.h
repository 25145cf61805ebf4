#pragma once

#include <ostream>
#include <string>

#include "pipeline/closed_loop.h"

namespace agv::pipeline {

// trace.csv: one row per control period. Columns: time, true pose, true and measured errors,
// what the controller acted on, the command, what it asks of the wheels (Mecanum: four wheel
// speeds; dual steer: steer angle and speed of each wheel), measurement age and flags.
void write_trace_csv(std::ostream& out, const RunResult& run);

// frames.csv: one row per camera frame, perception against ground truth.
void write_frames_csv(std::ostream& out, const RunResult& run);

}  // namespace agv::pipeline
