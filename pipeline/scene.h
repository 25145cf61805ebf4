#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "control/path.h"

namespace agv::pipeline {

// One strip of guide tape laid along a path.
struct TapeStrip {
  control::Path path;
  double width_m = 0.025;
  cv::Vec3d color_bgr = {170.0, 90.0, 25.0};  // blue tape
  double edge_softness_m = 0.0003;            // width of the soft edge (paper fibres, glue)
  double texture_contrast = 0.03;             // relative brightness variation of the tape
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
};

struct Scene {
  std::vector<TapeStrip> tapes;
  FloorStyle floor;
  ImageEffects effects;
  std::uint64_t seed = 1;
};

}  // namespace agv::pipeline
