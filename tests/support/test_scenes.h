#pragma once

// Shared helpers for tests that render frames: cameras and scenes with stated parameters.

#include <numbers>

#include "common/angles.h"
#include "control/path.h"
#include "perception/camera_model.h"
#include "perception/line_estimator.h"
#include "pipeline/sim/scene.h"

namespace agv::testing {

// Line estimator options told the scene's first tape's width and colour.
inline perception::LineEstimator::Options hinted(const pipeline::Scene& scene) {
  perception::LineEstimator::Options options;
  options.tape.width_m = scene.tapes.front().width_m;
  options.tape.color_bgr = scene.tapes.front().color_bgr;
  return options;
}

// The project's default camera (pipeline/config/default_camera.yaml), written out here so that a
// change to the shipped file does not silently change what tests check.
inline perception::CameraIntrinsics default_intrinsics() {
  perception::CameraIntrinsics in;
  in.width_px = 640;
  in.height_px = 480;
  in.camera_matrix = cv::Matx33d(384, 0, 319.5, 0, 384, 239.5, 0, 0, 1);
  in.distortion = {-0.08, 0.02, 0.0, 0.0, 0.0};
  return in;
}

inline perception::MountPose straight_down_mount(double x_m = 0.30, double y_m = 0.0,
                                                 double z_m = 0.15) {
  perception::MountPose mount;
  mount.xyz_m = {x_m, y_m, z_m};
  mount.rpy_rad = {std::numbers::pi, 0.0, -std::numbers::pi / 2};
  return mount;
}

// Another mount: higher, off-centre, tilted 5 deg and turned 3 deg.
inline perception::MountPose tilted_offset_mount() {
  perception::MountPose mount = straight_down_mount(0.35, 0.02, 0.20);
  mount.rpy_rad.y() = deg_to_rad(5.0);
  mount.rpy_rad.z() += deg_to_rad(3.0);
  return mount;
}

// A scene with one straight tape along the world x axis from x = -2 m to x = 8 m.
inline pipeline::Scene straight_tape_scene(std::uint64_t seed = 7) {
  pipeline::Scene scene;
  pipeline::TapeStrip tape;
  tape.path = control::Path::starting_at({-2.0, 0.0, 0.0}).add_line(10.0);
  scene.tapes.push_back(tape);
  scene.seed = seed;
  return scene;
}

}  // namespace agv::testing
