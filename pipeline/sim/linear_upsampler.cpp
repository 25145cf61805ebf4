#include "pipeline/sim/linear_upsampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace agv::pipeline {

LinearUpsampler::LinearUpsampler(cv::Size from, cv::Size to) : from_(from), to_(to) {
  if (from.width < 1 || from.height < 1 || to.width < from.width || to.height < from.height)
    throw std::invalid_argument("LinearUpsampler: cannot enlarge " + std::to_string(from.width) +
                                "x" + std::to_string(from.height) + " to " +
                                std::to_string(to.width) + "x" + std::to_string(to.height));
  // OpenCV's resize (imgproc/src/resize.cpp): the source position of output pixel d is
  // (d + 0.5) * scale - 0.5 in float; its floor and fraction give the taps (1 - f, f). A column
  // left of the first source column takes that column alone; the first column whose right tap
  // would fall off the image, and every one after it, copy their clamped source column. Rows
  // keep their weights and clamp the two source rows instead.
  const double scale_x = 1.0 / (static_cast<double>(to.width) / from.width);
  const double scale_y = 1.0 / (static_cast<double>(to.height) / from.height);
  x_interpolated_end_ = to.width;
  for (int dx = 0; dx < to.width; ++dx) {
    float fx = static_cast<float>((dx + 0.5) * scale_x - 0.5);
    int sx = static_cast<int>(std::floor(fx));
    fx -= static_cast<float>(sx);
    if (sx < 0) fx = 0.0f, sx = 0;
    if (sx + 1 >= from.width) {
      x_interpolated_end_ = std::min(x_interpolated_end_, dx);
      if (sx >= from.width - 1) fx = 0.0f, sx = from.width - 1;
    }
    x_source_.push_back(sx);
    x_weights_.push_back(1.0f - fx);
    x_weights_.push_back(fx);
  }
  // Exact doubling (the renderer's case): inner columns 2m and 2m + 1 take source columns
  // (m - 1, m) with weights (0.25, 0.75) and (m, m + 1) with (0.75, 0.25); checked against the
  // tables just built, so that the fast path computes exactly what they say.
  doubling_ = to.width == 2 * from.width && from.width >= 2;
  for (int dx = 1; doubling_ && dx + 1 < to.width; ++dx) {
    const bool even = dx % 2 == 0;
    doubling_ = x_source_[dx] == (even ? dx / 2 - 1 : dx / 2) &&
                x_weights_[2 * dx] == (even ? 0.25f : 0.75f) &&
                x_weights_[2 * dx + 1] == (even ? 0.75f : 0.25f) && dx < x_interpolated_end_;
  }
  for (int dy = 0; dy < to.height; ++dy) {
    float fy = static_cast<float>((dy + 0.5) * scale_y - 0.5);
    const int sy = static_cast<int>(std::floor(fy));
    fy -= static_cast<float>(sy);
    y_source_.push_back(sy);
    y_weights_.push_back(1.0f - fy);
    y_weights_.push_back(fy);
  }
  for (std::vector<float>& kept : kept_) kept.resize(to.width);
}

void LinearUpsampler::forget() { kept_row_[0] = kept_row_[1] = -1; }

const std::vector<float>& LinearUpsampler::resized_source_row(const cv::Mat& src, int source_row) {
  for (int slot = 0; slot < 2; ++slot)
    if (kept_row_[slot] == source_row) return kept_[slot];
  const int slot = next_slot_;
  next_slot_ = 1 - next_slot_;
  kept_row_[slot] = source_row;
  const float* __restrict s = src.ptr<float>(source_row);
  float* __restrict out = kept_[slot].data();
  int dx = 0;
  if (doubling_) {
    // The loop below for columns 1 .. to.width - 2 in pairs, in a form that vectorises (the
    // same products and sums in the same order).
    out[0] = s[x_source_[0]] * x_weights_[0] + s[x_source_[0] + 1] * x_weights_[1];
    for (int m = 1; m < from_.width; ++m) {
      out[2 * m] = s[m - 1] * 0.25f + s[m] * 0.75f;
      out[2 * m - 1] = s[m - 1] * 0.75f + s[m] * 0.25f;
    }
    dx = to_.width - 1;
  }
  for (; dx < x_interpolated_end_; ++dx) {
    const int sx = x_source_[dx];
    out[dx] = s[sx] * x_weights_[2 * dx] + s[sx + 1] * x_weights_[2 * dx + 1];
  }
  for (; dx < to_.width; ++dx) out[dx] = s[x_source_[dx]];
  return kept_[slot];
}

void LinearUpsampler::row(const cv::Mat& src, int y, float* __restrict out) {
  const int upper = std::clamp(y_source_[y], 0, from_.height - 1);
  const int lower = std::clamp(y_source_[y] + 1, 0, from_.height - 1);
  const float* __restrict a = resized_source_row(src, upper).data();
  const float* __restrict b = resized_source_row(src, lower).data();
  const float wa = y_weights_[2 * y], wb = y_weights_[2 * y + 1];
  for (int x = 0; x < to_.width; ++x) out[x] = a[x] * wa + b[x] * wb;
}

}  // namespace agv::pipeline
