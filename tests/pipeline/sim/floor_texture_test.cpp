#include "pipeline/sim/floor_texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace agv::pipeline {
namespace {

constexpr double kTexel_m = 0.0005;
constexpr double kTile_m = FloorTexture::kTileTexels * kTexel_m;

// Bilinear interpolation is continuous: across every texel boundary of one row and one column of
// the tile, and across the tile's wrap, the texture changes by no more than its slope allows over
// the step (the texels are unit-variance noise, so neighbours differ by a few units at most). A
// texel read from the wrong place (the tile is stored in blocks, and the neighbour across a
// block's edge or the wrap lies elsewhere in memory) jumps by about one unit there.
TEST(FloorTexture, IsContinuousAcrossEveryTexelBlockAndTheWrap) {
  const FloorTexture texture(kTexel_m, 0.002, 7);
  // 1e-3 texels (several float steps at half a metre) either side; the texture's slope is at
  // most a few units per texel, so it changes by under 0.01 across.
  const double step_m = 1e-3 * kTexel_m;
  const double tolerance = 0.02;
  for (int along_x = 0; along_x < 2; ++along_x) {
    for (int i = 0; i <= FloorTexture::kTileTexels; ++i) {
      // Boundary i along one axis, at a fixed position between texels on the other.
      const double at_m = i * kTexel_m, across_m = 37.3 * kTexel_m;
      const double x0 = along_x ? at_m - step_m : across_m, y0 = along_x ? across_m : at_m - step_m;
      const double x1 = along_x ? at_m + step_m : across_m, y1 = along_x ? across_m : at_m + step_m;
      const float before = texture.sample(static_cast<float>(x0), static_cast<float>(y0));
      const float after = texture.sample(static_cast<float>(x1), static_cast<float>(y1));
      ASSERT_NEAR(before, after, tolerance) << (along_x ? "x" : "y") << " boundary " << i;
    }
  }
}

TEST(FloorTexture, RepeatsEveryTileAndGivesTheSameSamplesInABatch) {
  const FloorTexture texture(kTexel_m, 0.002, 3);
  std::vector<float> xs, ys;
  for (int k = 0; k < 300; ++k) {
    xs.push_back(static_cast<float>(-0.05 + 0.00037 * k));
    ys.push_back(static_cast<float>(0.02 - 0.00023 * k));
  }
  // A rigid placement (rotation c, s and translation), as the renderer turns the view's floor
  // points into the world.
  const float c = std::cos(0.4f), s = std::sin(0.4f), tx = 1.3f, ty = -0.7f;
  std::vector<float> batch(xs.size(), 1.0f);
  texture.add_samples(xs.data(), ys.data(), static_cast<int>(xs.size()), c, s, tx, ty,
                      batch.data());
  std::vector<float> plain(xs.size());
  texture.samples(xs.data(), ys.data(), static_cast<int>(xs.size()), plain.data());
  for (size_t k = 0; k < xs.size(); ++k) {
    const float wx = c * xs[k] - s * ys[k] + tx, wy = s * xs[k] + c * ys[k] + ty;
    // Bit for bit: the renderer's frames must not depend on which of the two it calls.
    EXPECT_EQ(batch[k], 1.0f + texture.sample(wx, wy)) << k;
    EXPECT_EQ(plain[k], texture.sample(xs[k], ys[k])) << k;
    // One tile further along either axis: the same texels (exact where the shifted position
    // rounds to the same fraction of a texel; within float rounding of a metre otherwise).
    EXPECT_NEAR(texture.sample(wx + static_cast<float>(kTile_m), wy), texture.sample(wx, wy), 1e-3);
    EXPECT_NEAR(texture.sample(wx, wy - static_cast<float>(kTile_m)), texture.sample(wx, wy), 1e-3);
  }
}

}  // namespace
}  // namespace agv::pipeline
