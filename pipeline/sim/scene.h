#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/pose2.h"
#include "control/path.h"

namespace agv::pipeline {

// One strip of guide tape laid along a path.
struct TapeStrip {
  control::Path path;
  double width_m = 0.025;
  cv::Vec3d color_bgr = {170.0, 90.0, 25.0};      // blue tape
  double edge_softness_m = 0.0003;                // width of the soft edge (paper fibres, glue)
  double texture_contrast = 0.03;                 // relative brightness variation of the tape
  double wear = 0.0;                              // fraction of the tape worn through to the floor
  std::vector<std::pair<double, double>> gaps_m;  // [from, to] arc lengths with no tape
};

struct FloorStyle {
  cv::Vec3d color_bgr = {128.0, 132.0, 135.0};  // grey concrete
  double texture_contrast = 0.10;               // relative brightness variation (1 sigma)
  double texture_feature_m = 0.002;             // smallest texture feature
};

// Image effects of the camera; each can be switched off by setting it to 0.
struct ImageEffects {
  double noise_sigma = 2.0;                 // Gaussian sensor noise, grey levels (of 255)
  double exposure_s = 0.002;                // motion blur: poses integrated over this exposure
  double vignetting = 0.20;                 // fraction of brightness lost at the image corners
  double illumination_gradient = 0.15;      // brightness change across the image, fraction
  double illumination_direction_rad = 0.6;  // direction of that change in the image
  double brightness = 1.0;                  // overall exposure gain
  // The vehicle's own shadow, fixed in the image: a half-plane darkened by `shadow_darkness`,
  // its edge `shadow_offset` (-1..1, image half-sizes) from the centre along
  // `shadow_direction_rad`, blurred over `shadow_softness` (fraction of the image width).
  double shadow_darkness = 0.0;
  double shadow_direction_rad = 0.0;
  double shadow_offset = 0.5;
  double shadow_softness = 0.05;
  // A specular glare of a light on a glossy floor, fixed in the image: adds up to
  // `specular_strength` grey levels in a Gaussian spot at (specular_x, specular_y) (fractions of
  // the image size) of radius `specular_radius` (fraction of the image width).
  double specular_strength = 0.0;
  double specular_x = 0.6;
  double specular_y = 0.4;
  double specular_radius = 0.08;
};

// An AprilTag printed on paper lying on the floor: its pattern (white margin included), centred
// at `pose` (world), its x axis along the pose's heading. size_m is AprilTag's size (the black
// border square for tag36h11).
struct FloorTag {
  std::string family = "tag36h11";
  int id = 0;
  double size_m = 0.10;
  Pose2 pose;
};

struct Scene {
  std::vector<TapeStrip> tapes;
  std::vector<FloorTag> tags;
  FloorStyle floor;
  ImageEffects effects;
  std::uint64_t seed = 1;
};

}  // namespace agv::pipeline
