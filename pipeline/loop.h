#pragma once

#include <functional>

#include "pipeline/camera_stage.h"
#include "pipeline/control_stage.h"
#include "pipeline/run_result.h"
#include "pipeline/sim/simulated_vehicle.h"

namespace agv::pipeline {

// The two stages of the loop and what the commands drive. The lockstep and threaded schedules
// (lockstep_loop.h, threaded_loop.h) run the same stages; they differ only in when.
struct Loop {
  CameraStage& camera;
  BoundedQueue<StampedMeasurement>& queue;  // from the camera stage to the control stage
  ControlStage& control;
  // The simulated vehicle the commands move (its pose is what the camera sees), or null: the
  // commands go to a real vehicle, or nowhere (replay: what the controller would have done).
  SimulatedVehicle* vehicle = nullptr;
  // Each row as soon as it is made (a command stream to a vehicle computer); may be empty.
  std::function<void(const TraceRow&)> on_period;
};

// The result's parts that both schedules fill the same way: rows and frames, queue figures,
// stage times.
void collect_results(const Loop& loop, RunResult* result);

}  // namespace agv::pipeline
