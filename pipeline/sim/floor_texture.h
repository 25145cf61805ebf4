#pragma once

#include <cmath>
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
    return bilinear(blocks_, x_m * inverse_texel_m_, y_m * inverse_texel_m_);
  }

  // out[k] += sample(c xs[k] - s ys[k] + tx, s xs[k] + c ys[k] + ty) for k < count: the texture
  // under points given in a frame that the rotation (c, s) and translation (tx, ty) place on the
  // floor (the same values as `sample`, bit for bit, in one loop the compiler can vectorise).
  void add_samples(const float* xs, const float* ys, int count, float c, float s, float tx,
                   float ty, float* out) const;

  // out[k] = sample(xs[k], ys[k]) for k < count (bit for bit, in a loop the compiler can
  // vectorise).
  void samples(const float* xs, const float* ys, int count, float* out) const;

  double texel_m() const { return texel_m_; }

 private:
  static constexpr int kMask = kTileTexels - 1;
  // The tile is stored in blocks of kBlock x kBlock texels, block after block along the tile's
  // rows, each row-major with an apron: the next block's first column and row (wrapping at the
  // tile's edges) repeated, so that a texel's right, lower and diagonal neighbours lie at fixed
  // offsets (+1, +kPitch, +kPitch + 1). A view crossing the tile's rows at any angle reads a few
  // cache lines per block (stored row after row, a view across its 4 KiB rows missed the cache
  // at every sample).
  static constexpr int kBlockBits = 3, kBlock = 1 << kBlockBits, kBlockMask = kBlock - 1;
  static constexpr int kPitch = kBlock + 1, kBlockFloats = kPitch * kPitch;
  static constexpr int kBlocksPerRowBits = 10 - kBlockBits;
  static_assert(kTileTexels == 1 << 10);

  // The tile interpolated at texel coordinates (u, v), wrapping around.
  // Always inlined: a call keeps add_samples' loop from vectorising.
  [[gnu::always_inline]] static float bilinear(const float* blocks, float u, float v) {
    const float fu = std::floor(u), fv = std::floor(v);
    const float au = u - fu, av = v - fv;
    // Indices into `blocks` (not a pointer per sample): the form GCC turns into vector gathers.
    const int i = index(static_cast<int>(fu) & kMask, static_cast<int>(fv) & kMask);
    const float t00 = blocks[i], t10 = blocks[i + 1];
    const float t01 = blocks[i + kPitch], t11 = blocks[i + kPitch + 1];
    const float top = t00 + au * (t10 - t00);
    const float bottom = t01 + au * (t11 - t01);
    return top + av * (bottom - top);
  }
  [[gnu::always_inline]] static int index(int iu, int iv) {
    const int block = ((iv >> kBlockBits) << kBlocksPerRowBits) | (iu >> kBlockBits);
    return block * kBlockFloats + (iv & kBlockMask) * kPitch + (iu & kBlockMask);
  }

  double texel_m_;
  float inverse_texel_m_;
  cv::Mat blocked_;                // CV_32F, the blocks above, one row
  const float* blocks_ = nullptr;  // blocked_'s data
};

}  // namespace agv::pipeline
