#include "pipeline/sim/frame_renderer.h"

#include "perception/apriltag_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <opencv2/core/hal/hal.hpp>
#include <opencv2/imgproc.hpp>

#include "common/twist_motion.h"
#include "common/vector_clones.h"
#include "pipeline/sim/tape_pieces.h"

namespace agv::pipeline {
namespace {

constexpr int kNoiseMargin = 64;      // random offsets into the noise bank per frame
constexpr float kNoiseScale = 25.0f;  // int8 noise bank: standard normal x 25, clipped at 5 sigma
constexpr double kTexel_m = 0.0005;
constexpr int kMaxBlurSamples = 12;
// Tape coverage is first bounded on every 16th pixel of a row; only the stretches that the tape
// can reach are drawn pixel by pixel.
constexpr int kCoarseStep = 16;

}  // namespace

FrameRenderer::FrameRenderer(const perception::CameraModel& camera, const Scene& scene)
    : camera_(camera),
      scene_(scene),
      floor_map_(perception::FloorMap::shared(camera)),
      texture_(kTexel_m, scene.floor.texture_feature_m, scene.seed),
      pieces_(tape_pieces(scene.tapes)) {
  make_tag_patterns();
  make_floor_grids();
  make_gain_and_glare();
  make_tape_tables();
  make_noise_bank();
  make_tag_reach();
}

void FrameRenderer::make_tag_patterns() {
  for (const FloorTag& tag : scene_.tags) {
    perception::AprilTagDetector::Options options;
    options.family = tag.family;
    options.max_hamming = 0;  // only the pattern is needed
    const perception::AprilTagDetector family(options);
    TagPattern p;
    p.cells = family.tag_image(tag.id);
    p.cell_m = tag.size_m / family.size_cells();
    p.half_extent_m = 0.5 * p.cells.cols * p.cell_m;
    p.x_m = tag.pose.x_m;
    p.y_m = tag.pose.y_m;
    p.cos_yaw = std::cos(tag.pose.yaw_rad);
    p.sin_yaw = std::sin(tag.pose.yaw_rad);
    tag_patterns_.push_back(p);
  }
}

void FrameRenderer::make_floor_grids() {
  const int w = camera_.intrinsics().width_px, h = camera_.intrinsics().height_px;
  // Pixels that see no floor get floor point (0, 0) and zero gain: black plus noise.
  cv::patchNaNs(floor_x_m_ = floor_map_->x_m().clone(), 0.0);
  cv::patchNaNs(floor_y_m_ = floor_map_->y_m().clone(), 0.0);
  // The floor texture is sampled on a half-resolution grid and interpolated: its finest
  // features span several pixels, so this loses nothing visible and saves 3/4 of the lookups.
  const cv::Size texture_grid((w + 1) / 2, (h + 1) / 2);
  cv::resize(floor_x_m_, texture_x_m_, texture_grid, 0, 0, cv::INTER_AREA);
  cv::resize(floor_y_m_, texture_y_m_, texture_grid, 0, 0, cv::INTER_AREA);
  texture_upsampler_.emplace(texture_grid, cv::Size(w, h));
}

void FrameRenderer::make_gain_and_glare() {
  const int w = camera_.intrinsics().width_px, h = camera_.intrinsics().height_px;
  const ImageEffects& fx = scene_.effects;
  gain_.create(h, w, CV_32F);
  glare_.create(h, w, CV_32F);
  const double cx = (w - 1) / 2.0, cy = (h - 1) / 2.0;
  const double corner_sq = cx * cx + cy * cy;
  const double gx = std::cos(fx.illumination_direction_rad),
               gy = std::sin(fx.illumination_direction_rad);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double du = u - cx, dv = v - cy;
      const double vignette = 1.0 - fx.vignetting * (du * du + dv * dv) / corner_sq;
      const double gradient = 1.0 + fx.illumination_gradient * (du / w * gx + dv / h * gy);
      // The vehicle's shadow: a soft half-plane across the image.
      const double across =
          (du * std::cos(fx.shadow_direction_rad) + dv * std::sin(fx.shadow_direction_rad)) /
          (0.5 * std::max(w, h));
      const double softness = std::max(1e-3, fx.shadow_softness * w / (0.5 * std::max(w, h)));
      const double shadowed = 0.5 * (1.0 + std::tanh((across - fx.shadow_offset) / softness));
      const double shadow = 1.0 - fx.shadow_darkness * shadowed;
      const bool sees_floor = std::isfinite(floor_map_->x_m().at<float>(v, u));
      gain_.at<float>(v, u) =
          sees_floor ? static_cast<float>(fx.brightness * vignette * gradient * shadow) : 0.0f;
      // A specular glare: a Gaussian spot of added light.
      const double gu = u - fx.specular_x * (w - 1), gv = v - fx.specular_y * (h - 1);
      const double radius_px = std::max(1.0, fx.specular_radius * w);
      glare_.at<float>(v, u) = static_cast<float>(
          fx.specular_strength * std::exp(-(gu * gu + gv * gv) / (2.0 * radius_px * radius_px)));
    }
  }
  // Where a row's glare is exactly 0 adding it changes nothing: expose_row skips it there (most
  // rows of most scenes have none; reading it cost a tenth of a frame).
  glare_span_.assign(h, {0, 0});
  for (int v = 0; v < h; ++v) {
    const float* glare = glare_.ptr<float>(v);
    int first = 0, last = w;
    while (first < w && glare[first] == 0.0f) ++first;
    while (last > first && glare[last - 1] == 0.0f) --last;
    glare_span_[v] = {first, last};
  }
}

void FrameRenderer::make_tape_tables() {
  const int w = camera_.intrinsics().width_px, h = camera_.intrinsics().height_px;
  // Worn tape: where a second, finer floor-texture field exceeds the level that a fraction
  // `wear` of it exceeds (the standard normal quantile, by bisection on erfc).
  for (const TapeStrip& strip : scene_.tapes) {
    double lo = -6.0, hi = 6.0;
    const double fraction = std::clamp(strip.wear, 1e-9, 1.0 - 1e-9);
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (0.5 * std::erfc(mid / std::sqrt(2.0)) > fraction ? lo : hi) = mid;
    }
    wear_level_.push_back(static_cast<float>(0.5 * (lo + hi)));
  }
  // Anti-aliasing: a pixel's coverage of the tape ramps over its footprint and the tape's soft
  // edge.
  for (const TapeStrip& strip : scene_.tapes) {
    cv::Mat inverse_ramp(h, w, CV_32F);
    const float softness_sq = static_cast<float>(strip.edge_softness_m * strip.edge_softness_m);
    for (int v = 0; v < h; ++v) {
      const float* footprint = floor_map_->footprint_m().ptr<float>(v);
      float* out = inverse_ramp.ptr<float>(v);
      for (int u = 0; u < w; ++u) {
        const float f = std::isfinite(footprint[u]) ? footprint[u] : 1.0f;
        out[u] = 1.0f / std::sqrt(f * f + softness_sq);
      }
    }
    inverse_ramp_.push_back(inverse_ramp);
    // Coverage 0.5 + (w/2 - d) / ramp is 0 from d = w/2 + ramp/2 on.
    std::vector<float> reach(h);
    for (int v = 0; v < h; ++v) {
      double smallest_inverse = 0.0;
      cv::minMaxLoc(inverse_ramp.row(v), &smallest_inverse);
      reach[v] = static_cast<float>(strip.width_m / 2.0 + 0.5 / smallest_inverse);
    }
    tape_reach_m_.push_back(reach);
  }
  // Every kCoarseStep-th pixel of each row, and its last (read for every row of every frame: a
  // gather from the full grids missed the cache at every sample).
  const int coarse = (w - 1 + kCoarseStep - 1) / kCoarseStep + 1;
  coarse_x_m_.create(h, coarse, CV_32F);
  coarse_y_m_.create(h, coarse, CV_32F);
  for (int v = 0; v < h; ++v) {
    for (int k = 0; k < coarse; ++k) {
      const int u = std::min(k * kCoarseStep, w - 1);
      coarse_x_m_.at<float>(v, k) = floor_x_m_.at<float>(v, u);
      coarse_y_m_.at<float>(v, k) = floor_y_m_.at<float>(v, u);
    }
  }
  row_step_m_.assign(h, 0.0f);
  for (int v = 0; v < h; ++v) {
    const float* xs = floor_x_m_.ptr<float>(v);
    const float* ys = floor_y_m_.ptr<float>(v);
    for (int u = 0; u + 1 < w; ++u)
      row_step_m_[v] = std::max(row_step_m_[v], std::hypot(xs[u + 1] - xs[u], ys[u + 1] - ys[u]));
  }
}

void FrameRenderer::make_noise_bank() {
  const int w = camera_.intrinsics().width_px, h = camera_.intrinsics().height_px;
  noise_bank_.create(h + kNoiseMargin, 3 * w + kNoiseMargin, CV_8S);
  cv::RNG rng(scene_.seed * 0x9E3779B97F4A7C15ull + 17);
  for (int r = 0; r < noise_bank_.rows; ++r) {
    auto* row = noise_bank_.ptr<signed char>(r);
    for (int c = 0; c < noise_bank_.cols; ++c) {
      const double z = std::clamp(rng.gaussian(1.0), -5.0, 5.0);
      row[c] = static_cast<signed char>(std::lround(z * kNoiseScale));
    }
  }
}

cv::Mat FrameRenderer::render(const Pose2& pose, const BodyTwist& twist,
                              std::uint64_t frame_index) const {
  cv::Mat frame;
  render_into(pose, twist, frame_index, &frame);
  return frame;
}

std::vector<FrameRenderer::SubPose> FrameRenderer::sub_poses(const Pose2& pose,
                                                             const BodyTwist& twist, int count,
                                                             bool with_pieces) const {
  const double exposure_s = scene_.effects.exposure_s;
  std::vector<SubPose> poses(count);
  for (int k = 0; k < count; ++k) {
    const double offset_s = count == 1 ? 0.0 : exposure_s * ((k + 0.5) / count - 0.5);
    const Pose2 p = integrate_twist(pose, twist, offset_s);
    poses[k].c = static_cast<float>(std::cos(p.yaw_rad));
    poses[k].s = static_cast<float>(std::sin(p.yaw_rad));
    poses[k].tx = static_cast<float>(p.x_m);
    poses[k].ty = static_cast<float>(p.y_m);
    if (!with_pieces) continue;
    const Eigen::Vector2d view_world = p.transform(floor_map_->view_centre_m());
    const Pose2 inverse = p.inverse();
    for (const WorldPiece& piece : pieces_) {
      const double reach_m =
          floor_map_->view_radius_m() + piece.bound_radius_m + scene_.tapes[piece.strip].width_m;
      if ((piece.bound_centre - view_world).norm() > reach_m) continue;
      poses[k].pieces.push_back(to_local(piece, inverse));
    }
  }
  return poses;
}

void FrameRenderer::render_texture(const std::vector<SubPose>& texture_poses) const {
  cv::Mat& texture_small = workspace_.texture_small;
  texture_small.create(texture_x_m_.size(), CV_32F);
  texture_small.setTo(0.0f);
  for (const SubPose& sp : texture_poses) {
    for (int v = 0; v < texture_small.rows; ++v) {
      const float* xs = texture_x_m_.ptr<float>(v);
      const float* ys = texture_y_m_.ptr<float>(v);
      texture_.add_samples(xs, ys, texture_small.cols, sp.c, sp.s, sp.tx, sp.ty,
                           texture_small.ptr<float>(v));
    }
  }
  texture_upsampler_->forget();
}

void FrameRenderer::render_into(const Pose2& pose, const BodyTwist& twist,
                                std::uint64_t frame_index, cv::Mat* frame) const {
  const int w = camera_.intrinsics().width_px, h = camera_.intrinsics().height_px;
  frame->create(h, w, CV_8UC3);
  const ImageEffects& fx = scene_.effects;

  // Sub-exposure poses centred on `pose`. The tape edges (what perception measures) are
  // integrated with poses at most 1 px of image motion apart; the floor texture, whose finest
  // features span several pixels, with poses at most 3 px apart.
  const double speed_m_s =
      std::hypot(twist.vx_m_s, twist.vy_m_s) +
      std::abs(twist.wz_rad_s) * (floor_map_->view_centre_m().norm() + floor_map_->view_radius_m());
  const double blur_px =
      speed_m_s * fx.exposure_s / std::max(1e-6, floor_map_->typical_footprint_m());
  const int tape_samples = std::clamp(static_cast<int>(std::ceil(blur_px)), 1, kMaxBlurSamples);
  const int texture_samples =
      std::clamp(static_cast<int>(std::ceil(blur_px / 3.0)), 1, tape_samples);
  const std::vector<SubPose> tape_poses = sub_poses(pose, twist, tape_samples, true);
  // A floor without texture contrast shows none, on the tape either (its contrast is relative to
  // the floor's): the texture is left at 0, which is what it then adds.
  const bool textured = scene_.floor.texture_contrast != 0.0;
  if (textured) render_texture(sub_poses(pose, twist, texture_samples, false));

  RowContext row;
  row.pose = &pose;
  row.tape_poses = &tape_poses;
  row.texture_scale = static_cast<float>(scene_.floor.texture_contrast) / texture_samples;
  cv::RNG frame_rng(scene_.seed * 1000003ull + frame_index * 7919ull + 1);
  row.noise_dx = frame_rng.uniform(0, kNoiseMargin);
  row.noise_dy = frame_rng.uniform(0, kNoiseMargin);
  row.noise_gain = static_cast<float>(fx.noise_sigma) / kNoiseScale;
  RowBuffers buffers(w, static_cast<int>(scene_.tapes.size()));
  for (int v = 0; v < h; ++v) {
    if (textured) texture_upsampler_->row(workspace_.texture_small, v, buffers.texture.data());
    shade_floor_row(row, &buffers);
    for (int i = 0; i < static_cast<int>(scene_.tapes.size()); ++i)
      draw_tape_in_row(v, i, row, &buffers);
    if (!tag_patterns_.empty())
      draw_tags_in_row(v, pose, buffers.blue.data(), buffers.green.data(), buffers.red.data());
    expose_row(v, row, &buffers);
    const uchar* planes[3] = {buffers.level[0].data(), buffers.level[1].data(),
                              buffers.level[2].data()};
    cv::hal::merge8u(planes, frame->ptr<uchar>(v), w, 3);
  }
}

// The floor's colour along the row, with its texture (b->texture).
AGV_VECTOR_CLONES
void FrameRenderer::shade_floor_row(const RowContext& row, RowBuffers* b) const {
  const float floor_b = static_cast<float>(scene_.floor.color_bgr[0]);
  const float floor_g = static_cast<float>(scene_.floor.color_bgr[1]);
  const float floor_r = static_cast<float>(scene_.floor.color_bgr[2]);
  const float* texture = b->texture.data();
  for (int u = 0; u < static_cast<int>(b->blue.size()); ++u) {
    const float t = 1.0f + row.texture_scale * texture[u];
    b->blue[u] = floor_b * t;
    b->green[u] = floor_g * t;
    b->red[u] = floor_r * t;
  }
}

// Tape strip i over row v: each pixel's coverage averaged over the exposure, worn patches, the
// tape's colour blended over the floor by that coverage.
AGV_VECTOR_CLONES
void FrameRenderer::draw_tape_in_row(int v, int i, const RowContext& row, RowBuffers* b) const {
  const int w = static_cast<int>(b->blue.size());
  const float* xs = floor_x_m_.ptr<float>(v);
  const float* ys = floor_y_m_.ptr<float>(v);
  const float* texture = b->texture.data();
  std::vector<float>& alpha = b->alpha[i];  // 0 everywhere between rows (cleared after use)
  bool strip_in_row = false;
  const float* inverse_ramp = inverse_ramp_[i].ptr<float>(v);
  const TapeStrip& tape = scene_.tapes[i];
  const float half_width = static_cast<float>(tape.width_m / 2.0);
  // Every kCoarseStep-th pixel of the row (and its last): between two of them the distance to a
  // piece can fall by at most half their floor separation below the mean of theirs (distance is
  // 1-Lipschitz), so a stretch whose bound exceeds the tape's reach shows none of it. The image
  // is the same as drawing every pixel; the margin covers float rounding.
  const int coarse = coarse_x_m_.cols;
  b->coarse_distance.resize(coarse);
  const float reach_m = tape_reach_m_[i][v] + 1e-4f;
  const float half_span_m = 0.5f * kCoarseStep * row_step_m_[v];
  // Columns [drawn_first, drawn_last] hold all the tape of this row (alpha is 0 outside);
  // b->coverage is 0 everywhere between sub-poses (each clears what it drew), as alpha is between
  // rows.
  int drawn_first = w, drawn_last = -1;
  for (const SubPose& sp : *row.tape_poses) {
    int pose_first = w, pose_last = -1;
    bool any = false;
    for (const LocalPiece& piece : sp.pieces) {
      if (piece.strip != i) continue;
      any = true;
      piece_distances(piece, coarse_x_m_.ptr<float>(v), coarse_y_m_.ptr<float>(v), coarse,
                      b->coarse_distance.data(), /*cuts=*/false);
      for (int k = 0; k + 1 < coarse;) {
        // The longest run of stretches that the tape may reach, drawn in one go.
        int end = k;
        while (end + 1 < coarse &&
               0.5f * (b->coarse_distance[end] + b->coarse_distance[end + 1]) - half_span_m <=
                   reach_m)
          ++end;
        if (end == k) {
          ++k;
          continue;
        }
        const int first = k * kCoarseStep, last = std::min(end * kCoarseStep, w - 1);
        const int count = last - first + 1;
        pose_first = std::min(pose_first, first);
        pose_last = std::max(pose_last, last);
        piece_distances(piece, xs + first, ys + first, count, b->distance.data());
        // __restrict (row buffers that could alias keep loops scalar); min/max rather than
        // std::clamp: the latter's branches keep this from vectorising.
        float* __restrict coverage = b->coverage.data() + first;
        const float* __restrict ramp = inverse_ramp + first;
        const float* __restrict distance = b->distance.data();
        for (int u = 0; u < count; ++u) {
          const float a =
              std::min(std::max(0.5f + (half_width - distance[u]) * ramp[u], 0.0f), 1.0f);
          coverage[u] = std::max(coverage[u], a);
        }
        k = end;
      }
    }
    if (!any) continue;
    strip_in_row = true;
    float* __restrict summed = alpha.data();
    float* __restrict coverage = b->coverage.data();
    for (int u = pose_first; u <= pose_last; ++u) {
      summed[u] += coverage[u];
      coverage[u] = 0.0f;
    }
    drawn_first = std::min(drawn_first, pose_first);
    drawn_last = std::max(drawn_last, pose_last);
  }
  if (!strip_in_row) return;
  if (tape.wear > 0.0) wear_tape_in_row(v, i, *row.pose, drawn_first, drawn_last, b);
  const float tape_b = static_cast<float>(tape.color_bgr[0]);
  const float tape_g = static_cast<float>(tape.color_bgr[1]);
  const float tape_r = static_cast<float>(tape.color_bgr[2]);
  const float tape_contrast =
      static_cast<float>(tape.texture_contrast) /
      static_cast<float>(scene_.floor.texture_contrast > 0.0 ? scene_.floor.texture_contrast : 1.0);
  const float inverse_samples = 1.0f / static_cast<int>(row.tape_poses->size());
  const float texture_scale = tape_contrast * row.texture_scale;
  float* __restrict summed = alpha.data();
  const float* __restrict pattern = texture;
  float* __restrict blue = b->blue.data();
  float* __restrict green = b->green.data();
  float* __restrict red = b->red.data();
  for (int u = drawn_first; u <= drawn_last; ++u) {
    const float a = summed[u] * inverse_samples;
    summed[u] = 0.0f;
    // The tape shares the floor's texture pattern, at its own (weaker) contrast.
    const float t = 1.0f + texture_scale * pattern[u];
    blue[u] += a * (tape_b * t - blue[u]);
    green[u] += a * (tape_g * t - green[u]);
    red[u] += a * (tape_r * t - red[u]);
  }
}

// Worn patches of strip i show the floor through the tape (world-fixed, 1-20 mm across), over
// columns [first, last] (the tape's coverage is 0 elsewhere, and stays 0 under any factor).
AGV_VECTOR_CLONES
void FrameRenderer::wear_tape_in_row(int v, int i, const Pose2& pose, int first, int last,
                                     RowBuffers* b) const {
  const int count = last - first + 1;
  const float* __restrict xs = floor_x_m_.ptr<float>(v) + first;
  const float* __restrict ys = floor_y_m_.ptr<float>(v) + first;
  const float centre_c = static_cast<float>(std::cos(pose.yaw_rad)),
              centre_s = static_cast<float>(std::sin(pose.yaw_rad));
  const float centre_tx = static_cast<float>(pose.x_m), centre_ty = static_cast<float>(pose.y_m);
  // The wear pattern: a second, finer field of the floor texture, at world points scaled and
  // shifted (computed apart so that the texture lookups run as one batch).
  float* __restrict pattern_x = b->wear_x.data();
  float* __restrict pattern_y = b->wear_y.data();
  for (int k = 0; k < count; ++k) {
    const float wx = centre_c * xs[k] - centre_s * ys[k] + centre_tx;
    const float wy = centre_s * xs[k] + centre_c * ys[k] + centre_ty;
    pattern_x[k] = 2.3f * wx + 13.1f;
    pattern_y[k] = 2.3f * wy - 7.3f;
  }
  float* __restrict level = b->wear_level.data();
  texture_.samples(pattern_x, pattern_y, count, level);
  float* __restrict alpha = b->alpha[i].data() + first;
  const float wear_level = wear_level_[i];
  for (int k = 0; k < count; ++k)
    alpha[k] *= std::min(std::max(1.0f - (level[k] - wear_level) / 0.4f, 0.0f), 1.0f);
}

// The camera over row v: vignetting and illumination gain, glare, sensor noise, 8-bit output
// into b->level (one row per channel, so that the loops vectorise; interleaved into BGR after).
AGV_VECTOR_CLONES
void FrameRenderer::expose_row(int v, const RowContext& row, RowBuffers* b) const {
  const int w = static_cast<int>(b->blue.size());
  const float* __restrict gain = gain_.ptr<float>(v);
  const float* __restrict glare = glare_.ptr<float>(v);
  const auto [glare_first, glare_last] = glare_span_[v];
  const float* colour[3] = {b->blue.data(), b->green.data(), b->red.data()};
  for (int ch = 0; ch < 3; ++ch) {
    const signed char* __restrict noise =
        noise_bank_.ptr<signed char>(v + row.noise_dy) + row.noise_dx + ch * w;
    // __restrict: the 8-bit output may otherwise alias the inputs, which keeps the loop scalar.
    unsigned char* __restrict out = b->level[ch].data();
    const float* __restrict c = colour[ch];
    // Rounded (+ 0.5, truncated), then clamped to 0-255: clamping the integer is the same as
    // clamping the float before it (the values are far inside int's range), and unlike float
    // min/max (NaN rules) it maps onto vector instructions. Outside the glare's span its 0 is not
    // added (x + 0 is x).
    const auto level = [](float value) {
      return static_cast<unsigned char>(std::min(std::max(static_cast<int>(value), 0), 255));
    };
    for (int u = 0; u < glare_first; ++u)
      out[u] = level(c[u] * gain[u] + row.noise_gain * noise[u] + 0.5f);
    for (int u = glare_first; u < glare_last; ++u)
      out[u] = level(c[u] * gain[u] + glare[u] + row.noise_gain * noise[u] + 0.5f);
    for (int u = glare_last; u < w; ++u)
      out[u] = level(c[u] * gain[u] + row.noise_gain * noise[u] + 0.5f);
  }
}

FrameRenderer::PixelSteps FrameRenderer::pixel_steps(int u, int v) const {
  const int w = floor_x_m_.cols, h = floor_x_m_.rows;
  const int left = std::max(0, u - 1), right = std::min(w - 1, u + 1);
  const int up = std::max(0, v - 1), down = std::min(h - 1, v + 1);
  const double col_span = right - left == 2 ? 0.5 : 1.0, row_span = down - up == 2 ? 0.5 : 1.0;
  const auto x = [&](int row, int col) { return floor_x_m_.at<float>(row, col); };
  const auto y = [&](int row, int col) { return floor_y_m_.at<float>(row, col); };
  return {(x(v, right) - x(v, left)) * col_span, (y(v, right) - y(v, left)) * col_span,
          (x(down, u) - x(up, u)) * row_span, (y(down, u) - y(up, u)) * row_span};
}

void FrameRenderer::make_tag_reach() {
  if (tag_patterns_.empty()) return;
  const int w = floor_x_m_.cols, h = floor_x_m_.rows;
  tag_reach_extra_m_.assign(h, 0.0);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const PixelSteps p = pixel_steps(u, v);
      tag_reach_extra_m_[v] = std::max(
          tag_reach_extra_m_[v], std::abs(p.ux) + std::abs(p.uy) + std::abs(p.vx) + std::abs(p.vy));
    }
  }
}

void FrameRenderer::draw_tags_in_row(int v, const Pose2& pose, float* blue, float* green,
                                     float* red) const {
  // Printed paper: black ink and white paper levels (before the camera's gain).
  constexpr float kBlack = 20.0f, kWhite = 230.0f;
  constexpr int kSub = 4;  // 4 x 4 samples per pixel: edges land at sub-pixel accuracy
  const int w = floor_x_m_.cols;
  const float* xs = floor_x_m_.ptr<float>(v);
  const float* ys = floor_y_m_.ptr<float>(v);
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  // Columns that a tag may reach: a pixel whose floor point lies further than reach * sqrt(2)
  // from a tag's centre fails the test below. Between two coarse points the distance to a centre
  // falls by at most half their floor separation below the mean of theirs (it is 1-Lipschitz),
  // as for the tape; the margin covers rounding. The same image as testing every pixel.
  std::vector<char> near_tag(w, 0);
  const float* coarse_x = coarse_x_m_.ptr<float>(v);
  const float* coarse_y = coarse_y_m_.ptr<float>(v);
  const int coarse = coarse_x_m_.cols;
  const double half_span_m = 0.5 * kCoarseStep * row_step_m_[v];
  for (const TagPattern& tag : tag_patterns_) {
    const Eigen::Vector2d centre = pose.inverse().transform({tag.x_m, tag.y_m});
    const double far_m = std::sqrt(2.0) * (tag.half_extent_m + tag_reach_extra_m_[v]) + 1e-6;
    const auto distance = [&](int k) {
      return std::hypot(coarse_x[k] - centre.x(), coarse_y[k] - centre.y());
    };
    for (int k = 0; k + 1 < coarse; ++k) {
      if (0.5 * (distance(k) + distance(k + 1)) - half_span_m > far_m) continue;
      const int first = k * kCoarseStep, last = std::min((k + 1) * kCoarseStep, w - 1);
      std::fill(near_tag.begin() + first, near_tag.begin() + last + 1, 1);
    }
  }
  for (int u = 0; u < w; ++u) {
    if (!near_tag[u]) continue;
    if (xs[u] == 0.0f && ys[u] == 0.0f) continue;  // no floor seen
    // The pixel's footprint on the floor (vehicle frame): centre and the steps of one pixel.
    const double px = xs[u], py = ys[u];
    const auto [ux, uy, vx, vy] = pixel_steps(u, v);
    for (const TagPattern& tag : tag_patterns_) {
      // Pixel centre in the tag's frame; skip pixels clearly off the tag.
      const double wx = c * px - s * py + pose.x_m - tag.x_m;
      const double wy = s * px + c * py + pose.y_m - tag.y_m;
      const double lx = tag.cos_yaw * wx + tag.sin_yaw * wy;
      const double ly = -tag.sin_yaw * wx + tag.cos_yaw * wy;
      const double reach =
          tag.half_extent_m + std::abs(ux) + std::abs(uy) + std::abs(vx) + std::abs(vy);
      if (std::abs(lx) > reach || std::abs(ly) > reach) continue;
      float sum = 0.0f;
      int inside = 0;
      for (int a = 0; a < kSub; ++a) {
        for (int b = 0; b < kSub; ++b) {
          const double fu = (a + 0.5) / kSub - 0.5, fv = (b + 0.5) / kSub - 0.5;
          const double qx = px + fu * ux + fv * vx, qy = py + fu * uy + fv * vy;
          const double tx = c * qx - s * qy + pose.x_m - tag.x_m;
          const double ty = s * qx + c * qy + pose.y_m - tag.y_m;
          const double tag_x = tag.cos_yaw * tx + tag.sin_yaw * ty;
          const double tag_y = -tag.sin_yaw * tx + tag.cos_yaw * ty;
          // The tag image's columns run along the tag's x, its rows against its y (seen from
          // above, the printed tag is not mirrored).
          const int col = static_cast<int>(std::floor((tag_x + tag.half_extent_m) / tag.cell_m));
          const int row = static_cast<int>(std::floor((tag.half_extent_m - tag_y) / tag.cell_m));
          if (col < 0 || row < 0 || col >= tag.cells.cols || row >= tag.cells.rows) continue;
          ++inside;
          sum += tag.cells.at<unsigned char>(row, col) ? kWhite : kBlack;
        }
      }
      if (inside == 0) continue;
      const float a = static_cast<float>(inside) / (kSub * kSub);
      const float level = sum / inside;
      blue[u] += a * (level - blue[u]);
      green[u] += a * (level - green[u]);
      red[u] += a * (level - red[u]);
    }
  }
}

}  // namespace agv::pipeline
