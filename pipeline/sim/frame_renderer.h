#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "perception/camera_model.h"
#include "perception/floor_map.h"
#include "pipeline/sim/floor_texture.h"
#include "pipeline/sim/scene.h"
#include "pipeline/sim/tape_pieces.h"

namespace agv::pipeline {

// Draws the colour frame (8-bit BGR, the camera's size) that the camera on a vehicle sees:
// textured floor, tape with anti-aliased soft edges (worn, interrupted), motion blur over the
// exposure, lens distortion (each pixel samples the floor along its own distorted ray),
// vignetting, an illumination gradient, the vehicle's shadow, a specular glare and Gaussian
// sensor noise; AprilTags lying on the floor (area-sampled, for calibration). Headless,
// single-threaded, deterministic for the scene's seed and the frame index. One renderer per thread:
// rendering reuses buffers.
class FrameRenderer {
 public:
  FrameRenderer(const perception::CameraModel& camera, const Scene& scene);

  // The frame whose exposure is centred on the vehicle pose `pose`, moving with `twist`.
  cv::Mat render(const Pose2& pose, const BodyTwist& twist, std::uint64_t frame_index) const;
  void render_into(const Pose2& pose, const BodyTwist& twist, std::uint64_t frame_index,
                   cv::Mat* frame) const;

  const perception::FloorMap& floor_map() const { return floor_map_; }
  const Scene& scene() const { return scene_; }

 private:
  perception::CameraModel camera_;
  Scene scene_;
  perception::FloorMap floor_map_;
  FloorTexture texture_;
  cv::Mat floor_x_m_, floor_y_m_;      // the floor map with 0 where no floor is seen
  cv::Mat texture_x_m_, texture_y_m_;  // the same on the half-resolution texture grid
  cv::Mat gain_;   // CV_32F: vignetting x illumination gradient x shadow x brightness
  cv::Mat glare_;  // CV_32F: specular glare added, grey levels
  std::vector<float> wear_level_;  // per strip: texture level above which the tape is worn
  cv::Mat noise_bank_;             // CV_8S: standard normal samples x kNoiseScale
  std::vector<WorldPiece> pieces_;
  struct TagPattern {  // a floor tag's cells (0 black, 255 white) and where they lie
    cv::Mat cells;
    double cell_m = 0.0, half_extent_m = 0.0;
    double x_m = 0.0, y_m = 0.0, cos_yaw = 1.0, sin_yaw = 0.0;
  };
  std::vector<TagPattern> tag_patterns_;
  // Tags drawn into one row of colour buffers (no motion blur: tags serve static calibration).
  void draw_tags_in_row(int v, const Pose2& pose, float* blue, float* green, float* red) const;
  std::vector<cv::Mat> inverse_ramp_;
  struct Workspace {  // per-frame buffers kept between frames (no allocation per frame)
    cv::Mat texture_small, texture_image, planes[3];
  };
  mutable Workspace workspace_;  // CV_32F per strip: 1 / edge ramp width at each pixel
};

}  // namespace agv::pipeline
