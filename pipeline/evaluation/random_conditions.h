#pragma once

#include <opencv2/core.hpp>

#include "perception/camera_model.h"
#include "pipeline/sim/scene.h"

namespace agv::pipeline {

// Random draws of what a perception evaluation varies, shared by the single-frame benchmark and
// the sequences (each draws from the caller's generator, in a fixed order: same seed, same draw).

// A camera: height 0.12-0.25 m, tilt up to 10 deg in any direction, the image turned up to
// 10 deg, 0.25-0.35 m ahead and up to 30 mm aside, mild barrel distortion.
struct RandomCamera {
  perception::CameraModel camera;
  double height_m = 0.0;
  double tilt_rad = 0.0;
};
RandomCamera draw_camera(cv::RNG& rng);

// The floor (light or dark grey, texture) and the light and image effects (noise, exposure,
// vignetting, illumination gradient, brightness; a shadow 30 % and glare 20 % of the time),
// drawn into `scene`. Returns whether the floor is light.
bool draw_floor_and_light(cv::RNG& rng, Scene* scene);

// A tape colour from a palette of real tapes, at least 70 (BGR distance) from the floor's.
cv::Vec3d draw_tape_colour(cv::RNG& rng, const cv::Vec3d& floor_bgr);

}  // namespace agv::pipeline
