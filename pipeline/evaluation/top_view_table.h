#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/pose2.h"
#include "perception/line_estimator.h"
#include "pipeline/sim/scene.h"

namespace agv::pipeline {

// Points of a top view around the vehicle within this distance of its origin.
constexpr double kTopViewReach_m = 0.6;

// A table for a top view of one frame (agv evaluate plots one for each failed sequence frame it
// saves): CSV `kind,x_m,y_m` in the vehicle frame of `pose` (x forward, y left, metres; DESIGN.md),
// one row per point within kTopViewReach_m of the origin: the centre lines of the tapes laid
// ("tape_laid", every 2 mm along them), the path memory's centre points (`remembered`, already in
// the vehicle frame), and the chord centres of the line followed ("followed") and of the other
// lines in view ("other_line"). Throws std::runtime_error when the file cannot be written.
void write_top_view_table(const std::string& file, const Pose2& pose,
                          const std::vector<Eigen::Vector2d>& remembered,
                          const perception::LineDetection& detection,
                          const std::vector<TapeStrip>& tapes);

}  // namespace agv::pipeline
