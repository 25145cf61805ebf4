#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace agv::pipeline {

// A seamless square tile of floor texture: zero-mean, unit-variance noise with a 1/f spectrum
// band-limited to features between `feature_size_m` and a few centimetres, like concrete or
// epoxy seen close up. Deterministic for a seed. Sampled with wrap-around by world position.
class FloorTexture {
 public:
  static constexpr int kTileTexels = 1024;  // power of two: wrap-around is a bit mask

  FloorTexture(double texel_m, double feature_size_m, std::uint64_t seed);

  // Bilinear sample at a world position (metres); the tile repeats every kTileTexels texels.
  float sample(float x_m, float y_m) const {
    const float u = x_m * inverse_texel_m_, v = y_m * inverse_texel_m_;
    const float fu = std::floor(u), fv = std::floor(v);
    const float au = u - fu, av = v - fv;
    const int iu = static_cast<int>(fu) & kMask, iv = static_cast<int>(fv) & kMask;
    const int iu1 = (iu + 1) & kMask, iv1 = (iv + 1) & kMask;
    const float* r0 = texels_.ptr<float>(iv);
    const float* r1 = texels_.ptr<float>(iv1);
    const float top = r0[iu] + au * (r0[iu1] - r0[iu]);
    const float bottom = r1[iu] + au * (r1[iu1] - r1[iu]);
    return top + av * (bottom - top);
  }

  double texel_m() const { return texel_m_; }

 private:
  static constexpr int kMask = kTileTexels - 1;
  double texel_m_;
  float inverse_texel_m_;
  cv::Mat texels_;  // CV_32F, kTileTexels x kTileTexels
};

}  // namespace agv::pipeline
