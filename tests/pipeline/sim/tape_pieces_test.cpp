#include "pipeline/sim/tape_pieces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "control/path.h"

namespace agv::pipeline {
namespace {

// The renderer skips the stretches of a row where a bound on the uncut distance says no tape can
// be: that bound needs the uncut distance never to exceed the cut one and to be 1-Lipschitz in
// the point. Checked on random points around a line and an arc, each cut square at both ends.
TEST(TapePieces, UncutDistanceBoundsTheCutOneAndIsLipschitz) {
  TapeStrip strip;
  strip.path = control::Path::starting_at({0.0, 0.0, 0.3}).add_line(0.4).add_arc(0.25, 1.2);
  const std::vector<WorldPiece> pieces = tape_pieces({strip});
  ASSERT_GE(pieces.size(), 2u);
  cv::RNG rng(4);
  constexpr int kPoints = 400;
  float xs[kPoints], ys[kPoints], cut[kPoints], uncut[kPoints];
  for (int i = 0; i < kPoints; ++i) {
    xs[i] = static_cast<float>(rng.uniform(-0.3, 0.8));
    ys[i] = static_cast<float>(rng.uniform(-0.3, 0.8));
  }
  int arcs = 0;
  for (const WorldPiece& world : pieces) {
    WorldPiece piece = world;
    piece.flat_start = piece.flat_end = true;
    arcs += piece.is_arc ? 1 : 0;
    const LocalPiece local = to_local(piece, Pose2{0.0, 0.0, 0.0});
    piece_distances(local, xs, ys, kPoints, cut, /*cuts=*/true);
    piece_distances(local, xs, ys, kPoints, uncut, /*cuts=*/false);
    for (int i = 0; i < kPoints; ++i) {
      EXPECT_LE(uncut[i], cut[i]) << i;
      for (int j = 0; j < i; j += 7) {
        const float apart = std::hypot(xs[i] - xs[j], ys[i] - ys[j]);
        EXPECT_LE(std::abs(uncut[i] - uncut[j]), apart + 1e-5f) << i << ", " << j;
      }
    }
    // Somewhere the cut matters (points past the square ends), else this checks nothing.
    int beyond = 0;
    for (int i = 0; i < kPoints; ++i) beyond += cut[i] > uncut[i] + 1e-3f ? 1 : 0;
    EXPECT_GT(beyond, 0);
  }
  EXPECT_GT(arcs, 0);
}

}  // namespace
}  // namespace agv::pipeline
