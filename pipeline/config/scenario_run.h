#pragma once

#include "pipeline/camera_stage.h"
#include "pipeline/config/scenario.h"
#include "pipeline/run_result.h"

namespace agv::pipeline {

// Runs a scenario in closed loop: frames rendered at the simulated vehicle's pose (or, with
// controller.input pose, its pose alone), perception, the queue with the scenario's latency,
// the controller, the plant; scheduled lockstep (deterministic) or threaded, as loop.mode says.
// `sink` receives every frame (a dataset recorder); frames are rendered for it also with pose
// input.
RunResult run_scenario(const Scenario& scenario, const Progress& progress = {},
                       const FrameSink& sink = {});

}  // namespace agv::pipeline
