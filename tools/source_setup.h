#pragma once

#include "perception/camera_model.h"
#include "perception/line_estimator.h"
#include "pipeline/config/scenario.h"
#include "pipeline/open_frame_source.h"
#include "tools/replay_command.h"

namespace agv::tools {

// What replay and track build from their options: the source with its calibration, the
// scenario (controller, limits, perception settings, with the shorthands applied) and the
// perception options (tape hints from the options, else the camera file, else the scenario).
struct SourceSetup {
  pipeline::OpenedSource opened;
  pipeline::Scenario scenario;
  perception::CameraModel camera;
  perception::LineEstimator::Options perception;
};

SourceSetup set_up_source(const SourceArgs& args, bool pass_bad_frames);

}  // namespace agv::tools
