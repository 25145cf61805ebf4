#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "perception/camera_model.h"
#include "perception/floor_map.h"
#include "pipeline/sim/floor_texture.h"
#include "pipeline/sim/linear_upsampler.h"
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

  const perception::FloorMap& floor_map() const { return *floor_map_; }
  const Scene& scene() const { return scene_; }

 private:
  perception::CameraModel camera_;
  Scene scene_;
  std::shared_ptr<const perception::FloorMap> floor_map_;  // FloorMap::shared
  FloorTexture texture_;
  cv::Mat floor_x_m_, floor_y_m_;      // the floor map with 0 where no floor is seen
  cv::Mat texture_x_m_, texture_y_m_;  // the same on the half-resolution texture grid
  cv::Mat gain_;   // CV_32F: vignetting x illumination gradient x shadow x brightness
  cv::Mat glare_;  // CV_32F: specular glare added, grey levels
  std::vector<std::pair<int, int>> glare_span_;  // per row: columns [first, last) of glare != 0
  std::vector<float> wear_level_;  // per strip: texture level above which the tape is worn
  cv::Mat noise_bank_;             // CV_8S: standard normal samples x kNoiseScale
  std::vector<WorldPiece> pieces_;
  struct TagPattern {  // a floor tag's cells (0 black, 255 white) and where they lie
    cv::Mat cells;
    double cell_m = 0.0, half_extent_m = 0.0;
    double x_m = 0.0, y_m = 0.0, cos_yaw = 1.0, sin_yaw = 0.0;
  };
  std::vector<TagPattern> tag_patterns_;
  // Per row: the most a pixel's footprint adds to a tag's reach (draw_tags_in_row's test).
  std::vector<double> tag_reach_extra_m_;
  // The floor steps of one pixel at (u, v), vehicle frame, metres: along the row (ux, uy) and
  // down the column (vx, vy), central differences (one-sided at the image's edges).
  struct PixelSteps {
    double ux, uy, vx, vy;
  };
  PixelSteps pixel_steps(int u, int v) const;
  // Tags drawn into one row of colour buffers (no motion blur: tags serve static calibration).
  void draw_tags_in_row(int v, const Pose2& pose, float* blue, float* green, float* red) const;
  std::vector<cv::Mat> inverse_ramp_;  // CV_32F per strip: 1 / edge ramp width at each pixel
  // Per strip and row: beyond this distance from its centre line a pixel shows no tape (half
  // the width plus half the widest edge ramp in the row), metres.
  std::vector<std::vector<float>> tape_reach_m_;
  // The floor points of every kCoarseStep-th pixel of each row and of its last (CV_32F).
  cv::Mat coarse_x_m_, coarse_y_m_;
  // Per row: the largest floor distance between neighbouring pixels, metres.
  std::vector<float> row_step_m_;
  struct Workspace {  // per-frame buffers kept between frames (no allocation per frame)
    cv::Mat texture_small;
  };
  mutable Workspace workspace_;
  // texture_small enlarged to the frame, a row at a time (cv::resize's values).
  mutable std::optional<LinearUpsampler> texture_upsampler_;

  // Built once, in the constructor.
  void make_tag_patterns();
  void make_floor_grids();
  void make_gain_and_glare();
  void make_tape_tables();
  void make_noise_bank();
  void make_tag_reach();

  // One pose within the exposure, with the tape pieces it can see (vehicle frame).
  struct SubPose {
    float c, s, tx, ty;  // vehicle -> world
    std::vector<LocalPiece> pieces;
  };
  // `count` poses spread over the exposure, centred on `pose`.
  std::vector<SubPose> sub_poses(const Pose2& pose, const BodyTwist& twist, int count,
                                 bool with_pieces) const;
  // The floor texture over the exposure, into workspace_.texture_small (half resolution).
  void render_texture(const std::vector<SubPose>& texture_poses) const;
  // What every row of a frame shares, and the buffers one row is drawn in.
  struct RowContext {
    const Pose2* pose = nullptr;
    const std::vector<SubPose>* tape_poses = nullptr;
    float texture_scale = 0.0f;
    int noise_dx = 0, noise_dy = 0;
    float noise_gain = 0.0f;
  };
  struct RowBuffers {
    RowBuffers(int width, int strips)
        : distance(width),
          coverage(width),
          texture(width),
          blue(width),
          green(width),
          red(width),
          wear_x(width),
          wear_y(width),
          wear_level(width),
          alpha(strips, std::vector<float>(width)),
          level{std::vector<unsigned char>(width), std::vector<unsigned char>(width),
                std::vector<unsigned char>(width)} {}
    std::vector<float> distance, coverage, texture, blue, green, red;
    std::vector<float> wear_x, wear_y, wear_level;  // worn tape: its pattern's points, levels
    std::vector<float> coarse_distance;     // at coarse_x_m_, coarse_y_m_
    std::vector<std::vector<float>> alpha;  // per strip: coverage summed over the exposure
    std::vector<unsigned char> level[3];    // the row's 8-bit output, per channel (B, G, R)
  };
  void shade_floor_row(const RowContext& row, RowBuffers* buffers) const;
  void draw_tape_in_row(int v, int strip, const RowContext& row, RowBuffers* buffers) const;
  void wear_tape_in_row(int v, int strip, const Pose2& pose, int first, int last,
                        RowBuffers* buffers) const;
  void expose_row(int v, const RowContext& row, RowBuffers* buffers) const;
};

}  // namespace agv::pipeline
