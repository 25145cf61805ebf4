#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "control/line_tracker.h"
#include "perception/line_estimator.h"
#include "pipeline/config/scenario.h"
#include "pipeline/control_stage.h"
#include "pipeline/sim/frame_renderer.h"
#include "pipeline/sim/plant.h"
#include "pipeline/sim/scene.h"

namespace agv::pipeline {

// The one place that turns a scenario into the loop's parts; no stage reads a scenario itself.
// Used by simulate, record, replay, track, bench and compare.

// The vehicle's pose at the start: at arc length start_s_m, offset and turned by the initial
// errors; and its twist: path speed along the path's curvature there.
Pose2 start_pose(const Scenario& scenario);
BodyTwist start_twist(const Scenario& scenario);

// The scenario's controller, told what it needs of the vehicle and the planned path (DWA looks
// ahead along it when the input is the pose).
std::unique_ptr<control::PathController> make_controller(const Scenario& scenario);
// That controller inside a LineTracker (limits, line-loss hold) running every ts_s.
control::LineTracker make_tracker(const Scenario& scenario, double ts_s);
// What the control stage needs to know of the vehicle.
ControlStage::Options control_stage_options(const Scenario& scenario, double ts_s);

Plant make_plant(const Scenario& scenario);

// What the user should know before trusting the run, one sentence each (empty: nothing): a law
// that commands a sideways speed (finite_step, pid, seed004_ff_p) on a dual steer drive form
// whose reference point cannot move sideways (rear_drive, front_drive).
std::vector<std::string> scenario_warnings(const Scenario& scenario);
// The camera that takes the frames: the camera file's, or its intrinsics with the true mount.
perception::CameraModel render_camera(const Scenario& scenario);
// The scene the renderer draws: the tape, extra tapes, floor marks and tags, floor, effects.
Scene render_scene(const Scenario& scenario);
std::unique_ptr<FrameRenderer> make_renderer(const Scenario& scenario);
// Seconds between frames: 1 / loop.camera_fps, or one frame per control period.
double camera_period_s(const Scenario& scenario);

// The perception options of a simulation: the scenario's tape width and, if enabled, colour.
perception::LineEstimator::Options perception_options(const Scenario& scenario);
// The perception options for recorded or live frames: the tape hints of the camera file (the
// scenario's tape describes a simulated floor, not this one), tracking as the scenario says.
perception::LineEstimator::Options recorded_perception_options(
    const Scenario& scenario, const perception::CameraFile& camera);

}  // namespace agv::pipeline
