#include "pipeline/sim/floor_texture.h"

#include <cmath>
#include <opencv2/core.hpp>
#include <tuple>

#include "common/recent_cache.h"
#include "common/vector_clones.h"

namespace agv::pipeline {

namespace {

// The tile for one (texel, feature size, seed): two 1024 x 1024 DFTs (about 0.1 s).
cv::Mat make_tile(double texel_m, double feature_size_m, std::uint64_t seed) {
  const int n = FloorTexture::kTileTexels;
  cv::RNG rng(seed ^ 0x5eed7e47u);
  cv::Mat white(n, n, CV_32F);
  rng.fill(white, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat spectrum;
  cv::dft(white, spectrum, cv::DFT_COMPLEX_OUTPUT);
  // Shape the spectrum: amplitude ~ 1/f between the feature size and 4 cm, rolled off outside.
  // Filtering in the frequency domain keeps the tile periodic, so it wraps without seams.
  const double tile_m = n * texel_m;
  const double f_high = 1.0 / std::max(feature_size_m, 2.0 * texel_m);  // cycles per metre
  const double f_low = 1.0 / 0.04;
  for (int y = 0; y < n; ++y) {
    const int ky = y <= n / 2 ? y : y - n;
    for (int x = 0; x < n; ++x) {
      const int kx = x <= n / 2 ? x : x - n;
      const double f = std::hypot(kx, ky) / tile_m;
      double gain = 0.0;
      if (f > 0.0) {
        gain = 1.0 / std::max(f, f_low) * std::exp(-(f * f) / (2.0 * f_high * f_high));
      }
      cv::Vec2f& c = spectrum.at<cv::Vec2f>(y, x);
      c *= static_cast<float>(gain);
    }
  }
  cv::Mat tile;
  cv::dft(spectrum, tile, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  cv::Scalar mean, stddev;
  cv::meanStdDev(tile, mean, stddev);
  return (tile - mean[0]) / std::max(stddev[0], 1e-12);
}

// The tile's texels in blocks of `block` x `block` with a one-texel apron (FloorTexture::index's
// order): block after block along the tile's rows, each (block + 1) x (block + 1), row-major.
cv::Mat blocked(const cv::Mat& tile, int block) {
  const int pitch = block + 1;
  cv::Mat out(1, (tile.rows / block) * (tile.cols / block) * pitch * pitch, CV_32F);
  float* next = out.ptr<float>();
  for (int by = 0; by < tile.rows; by += block)
    for (int bx = 0; bx < tile.cols; bx += block)
      for (int y = by; y < by + pitch; ++y)
        for (int x = bx; x < bx + pitch; ++x)
          *next++ = tile.at<float>(y % tile.rows, x % tile.cols);
  return out;
}

}  // namespace

FloorTexture::FloorTexture(double texel_m, double feature_size_m, std::uint64_t seed)
    : texel_m_(texel_m), inverse_texel_m_(static_cast<float>(1.0 / texel_m)) {
  // Made once per process for each (texel, feature size, seed) and shared read-only (every run
  // of a comparison suite has the same floor); the last 8 are kept.
  static RecentCache<std::tuple<double, double, std::uint64_t>, cv::Mat> tiles(8);
  blocked_ = tiles.get({texel_m, feature_size_m, seed},
                       [&] { return blocked(make_tile(texel_m, feature_size_m, seed), kBlock); });
  blocks_ = blocked_.ptr<float>();
}

AGV_VECTOR_CLONES
void FloorTexture::add_samples(const float* __restrict xs, const float* __restrict ys, int count,
                               float c, float s, float tx, float ty, float* __restrict out) const {
  const float* __restrict blocks = blocks_;
  const float inverse_texel_m = inverse_texel_m_;
  for (int k = 0; k < count; ++k) {
    out[k] += bilinear(blocks, (c * xs[k] - s * ys[k] + tx) * inverse_texel_m,
                       (s * xs[k] + c * ys[k] + ty) * inverse_texel_m);
  }
}

AGV_VECTOR_CLONES
void FloorTexture::samples(const float* __restrict xs, const float* __restrict ys, int count,
                           float* __restrict out) const {
  const float* __restrict blocks = blocks_;
  const float inverse_texel_m = inverse_texel_m_;
  for (int k = 0; k < count; ++k)
    out[k] = bilinear(blocks, xs[k] * inverse_texel_m, ys[k] * inverse_texel_m);
}

}  // namespace agv::pipeline
