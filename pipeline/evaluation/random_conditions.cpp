#include "pipeline/evaluation/random_conditions.h"

#include <algorithm>
#include <numbers>

#include "common/angles.h"

namespace agv::pipeline {

RandomCamera draw_camera(cv::RNG& rng) {
  perception::CameraIntrinsics in;
  in.distortion = {rng.uniform(-0.15, 0.0), rng.uniform(0.0, 0.05), 0.0, 0.0, 0.0};
  const double height = rng.uniform(0.12, 0.25);
  const double tilt = deg_to_rad(rng.uniform(0.0, 10.0)), tilt_direction = rng.uniform(-kPi, kPi);
  perception::MountPose mount;
  mount.xyz_m = {rng.uniform(0.25, 0.35), rng.uniform(-0.03, 0.03), height};
  mount.rpy_rad = {kPi + tilt * std::sin(tilt_direction), tilt * std::cos(tilt_direction),
                   -kPi / 2 + deg_to_rad(rng.uniform(-10.0, 10.0))};
  return {perception::CameraModel(in, mount), height, tilt};
}

bool draw_floor_and_light(cv::RNG& rng, Scene* scene) {
  const bool light_floor = rng.uniform(0.0, 1.0) < 0.5;
  const double grey = light_floor ? rng.uniform(150.0, 215.0) : rng.uniform(60.0, 140.0);
  scene->floor.color_bgr = cv::Vec3d(grey * rng.uniform(0.9, 1.1), grey * rng.uniform(0.9, 1.1),
                                     grey * rng.uniform(0.9, 1.1));
  scene->floor.texture_contrast = rng.uniform(0.02, 0.15);
  scene->floor.texture_feature_m = rng.uniform(0.001, 0.004);
  ImageEffects& fx = scene->effects;
  fx.noise_sigma = rng.uniform(0.0, 6.0);
  fx.exposure_s = rng.uniform(0.0, 0.008);
  fx.vignetting = rng.uniform(0.0, 0.35);
  fx.illumination_gradient = rng.uniform(0.0, 0.4);
  fx.illumination_direction_rad = rng.uniform(-kPi, kPi);
  fx.brightness = rng.uniform(0.6, 1.3);
  if (rng.uniform(0.0, 1.0) < 0.3) {
    fx.shadow_darkness = rng.uniform(0.2, 0.5);
    fx.shadow_direction_rad = rng.uniform(-kPi, kPi);
    fx.shadow_offset = rng.uniform(-0.3, 0.6);
    fx.shadow_softness = rng.uniform(0.01, 0.1);
  }
  if (rng.uniform(0.0, 1.0) < 0.2) {
    fx.specular_strength = rng.uniform(30.0, 90.0);
    fx.specular_x = rng.uniform(0.1, 0.9);
    fx.specular_y = rng.uniform(0.1, 0.9);
  }
  return light_floor;
}

cv::Vec3d draw_tape_colour(cv::RNG& rng, const cv::Vec3d& floor_bgr) {
  const cv::Vec3d palette[] = {{170, 90, 25}, {40, 200, 230},  {40, 40, 200},   {60, 170, 60},
                               {30, 30, 32},  {235, 235, 235}, {200, 120, 200}, {20, 140, 250}};
  for (int attempt = 0; attempt < 20; ++attempt) {
    cv::Vec3d c = palette[rng.uniform(0, 8)] * rng.uniform(0.8, 1.1);
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], 0.0, 255.0);
    if (cv::norm(c - floor_bgr) >= 70.0) return c;
  }
  return floor_bgr[0] > 128 ? cv::Vec3d(30, 30, 32) : cv::Vec3d(235, 235, 235);
}

}  // namespace agv::pipeline
