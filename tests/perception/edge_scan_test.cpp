#include "perception/edge_scan.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::perception {
namespace {

constexpr int kWidth = 640, kHeight = 480, kDownsample = 4;
constexpr double kFloor = 50.0, kTape = 210.0;
// A vertical tape whose edges are linear ramps 4 pixels wide: the grey level runs from the floor
// at x = 296 to the tape at x = 300, and back from x = 340 to x = 344, so that the half-way
// level (130) lies at x = 298 and x = 342 exactly (whole grey levels all along the ramps).
constexpr double kFirstEdgePx = 298.0, kSecondEdgePx = 342.0;

// The tape on a floor that is kFloor within `near_px` of the ramps and `far_level` beyond: a
// floor texture blob as wide as the image, except next to the tape.
cv::Mat tape_frame(double far_level, int near_px) {
  cv::Mat frame(kHeight, kWidth, CV_8UC1);
  for (int x = 0; x < kWidth; ++x) {
    double v = far_level;
    if (x >= 296 - near_px && x <= 344 + near_px) v = kFloor;
    if (x > 296 && x < 300) v = kFloor + (kTape - kFloor) * (x - 296) / 4.0;
    if (x >= 300 && x <= 340) v = kTape;
    if (x > 340 && x < 344) v = kFloor + (kTape - kFloor) * (344 - x) / 4.0;
    frame.col(x).setTo(cv::Scalar(std::round(v)));
  }
  return frame;
}

// Contrast 0 on the floor next to the tape, 1 on the tape.
ContrastAxis grey_axis() {
  ContrastAxis axis;
  axis.weights = {static_cast<float>(1.0 / (kTape - kFloor)), 0.0f, 0.0f};
  axis.offset = static_cast<float>(-kFloor / (kTape - kFloor));
  return axis;
}

// A coarse stage that marked only downsampled columns [first_small, last_small] as tape, on
// every row.
TapeRegions coarse_columns(int first_small, int last_small) {
  TapeRegions coarse;
  coarse.downsample = kDownsample;
  coarse.labels_small = cv::Mat::zeros(kHeight / kDownsample, kWidth / kDownsample, CV_32S);
  coarse.labels_small.colRange(first_small, last_small + 1).setTo(1);
  coarse.floor_noise = 0.01f;
  TapeRegion region;
  region.label = 1;
  region.box_small = cv::Rect(first_small, 0, last_small - first_small + 1, kHeight / kDownsample);
  coarse.regions.push_back(region);
  return coarse;
}

// Scans every 8th row of `frame` across the coarse region and expects the tape's two edges on
// each, within tolerance_px of the ramps' half-way points.
void expect_edges_at_half_way(const cv::Mat& frame, const TapeRegions& coarse,
                              double tolerance_px) {
  EdgeScanOptions options;
  options.flank_px = 24;  // 0.6 of the tape's width, as LineEstimator sets it
  options.step = 8;
  const auto edges = scan_tape_edges(frame, grey_axis(), coarse, coarse.regions[0], true, options);
  ASSERT_EQ(edges.size(), static_cast<size_t>(kHeight / 8));
  for (const EdgePair& e : edges) {
    EXPECT_NEAR(e.first_px.x, kFirstEdgePx, tolerance_px);
    EXPECT_NEAR(e.second_px.x, kSecondEdgePx, tolerance_px);
  }
}

// The edges on a plain floor sit at the half-way points of the ramps. Tolerance 0.01 pixel: the
// levels are re-taken around the edge found the round before, and each round leaves about a
// quarter of the error before it (here 0.06 px after the second pass, 0.004 px after two more).
TEST(EdgeScan, EdgesOfLinearRampsAtTheirHalfWayPoints) {
  const cv::Mat frame = tape_frame(kFloor, 0);
  const TapeRegions coarse = coarse_columns(76, 83);
  expect_edges_at_half_way(frame, coarse, 0.01);
}

// Floor texture brighter a few pixels away from the edges than right next to them: the edge
// is where the image changes from the floor it touches to the tape, not half-way to the far
// floor. Taking the far floor (90 grey levels here) as the floor level would move the
// threshold by 20 levels, which on a ramp of 40 levels per pixel is 0.5 pixels.
TEST(EdgeScan, FloorLevelIsTheFloorNextToTheEdge) {
  const cv::Mat frame = tape_frame(90.0, 7);
  const TapeRegions coarse = coarse_columns(76, 83);
  expect_edges_at_half_way(frame, coarse, 0.05);
}

// The coarse stage marked only the tape's leftmost 4 pixels (x 300-303): the scan window
// (24 pixels beyond them) ends on the tape, and the tape's right edge lies outside it. The
// window is widened on that side and both edges are found where they are.
TEST(EdgeScan, WindowEndingOnTheTapeIsWidened) {
  const cv::Mat frame = tape_frame(kFloor, 0);
  const TapeRegions coarse = coarse_columns(75, 75);
  expect_edges_at_half_way(frame, coarse, 0.01);
}

// The tape of tape_frame(kFloor, 0) with a worn spot of floor inside it on every third band of
// 24 rows: x 320-325, between the peak the walks start from (the coarse run's first sample, x 304)
// and the second edge.
cv::Mat tape_frame_with_worn_spots() {
  cv::Mat frame = tape_frame(kFloor, 0);
  for (int y = 0; y < kHeight; ++y)
    if ((y / 24) % 3 == 0) frame.row(y).colRange(320, 326).setTo(cv::Scalar(kFloor));
  return frame;
}

// Scans every 4th row of `frame` across the coarse region of tape_frame's tape, crossing dips
// up to 12 px, on a floor of the given noise (0.05 tape contrasts and more: textured), and
// expects the tape's two edges on each row. Tolerance 0.05 px, as for a floor brighter a few
// pixels out.
void expect_tape_edges_across_dips(const cv::Mat& frame, float floor_noise) {
  TapeRegions coarse = coarse_columns(76, 83);
  coarse.floor_noise = floor_noise;
  EdgeScanOptions options;
  options.flank_px = 24;
  options.max_dip_px = 12;
  options.step = 4;
  const std::vector<EdgePair> edges =
      scan_tape_edges(frame, grey_axis(), coarse, coarse.regions[0], true, options);
  ASSERT_EQ(edges.size(), static_cast<size_t>(kHeight / 4));
  for (const EdgePair& e : edges) {
    EXPECT_NEAR(e.first_px.x, kFirstEdgePx, 0.05) << "row " << e.first_px.y;
    EXPECT_NEAR(e.second_px.x, kSecondEdgePx, 0.05) << "row " << e.first_px.y;
  }
}

// A worn spot inside the tape, shorter than max_dip_px, is crossed: the edge beyond it is where
// the other rows have it (not at the spot, 22 pixels in); on a plain floor and on a textured one,
// where the walk that crosses no dip is tried too (it stops at the spot, which lines up with no
// other row's edge).
TEST(EdgeScan, AWornSpotInsideTheTapeIsCrossed) {
  expect_tape_edges_across_dips(tape_frame_with_worn_spots(), 0.01f);
  expect_tape_edges_across_dips(tape_frame_with_worn_spots(), 0.1f);
}

// On a textured floor, a blob as bright as the tape beside it, 8 pixels of floor between (a dip
// shorter than max_dip_px), on every third band of 24 rows (x 352-379): the tape's edge stays
// where the other rows have it (crossing the dip, it would be the blob's rim, 38 pixels out).
TEST(EdgeScan, ABlobAsBrightAsTheTapeBesideItIsNotTape) {
  cv::Mat frame = tape_frame(kFloor, 0);
  for (int y = 0; y < kHeight; ++y)
    if ((y / 24) % 3 == 0) frame.row(y).colRange(352, 380).setTo(cv::Scalar(kTape));
  expect_tape_edges_across_dips(frame, 0.1f);
}

// A tape running out of the image on the left: tape from the border to a ramp 4 pixels wide
// (x 296-300), floor beyond; the half-way level lies at x = 298 exactly.
cv::Mat tape_from_left_border_frame() {
  cv::Mat frame(kHeight, kWidth, CV_8UC1);
  for (int x = 0; x < kWidth; ++x) {
    double v = kFloor;
    if (x <= 296) v = kTape;
    if (x > 296 && x < 300) v = kTape - (kTape - kFloor) * (x - 296) / 4.0;
    frame.col(x).setTo(cv::Scalar(std::round(v)));
  }
  return frame;
}

// The one edge of a tape that runs out of the image, on every 8th row, at the ramp's half-way
// point (tolerance 0.01 px, as for two edges), the other end of the pair the border pixel,
// flagged; mirrored, the same on the other side; the same where a strip of floor too narrow to
// measure against lies between the tape and the border. The border scan says nothing where the tape
// lies wholly inside the image (two edges: scan_tape_edges' work) or covers a whole row.
TEST(EdgeScan, OneEdgeOfATapeRunningOutOfTheImage) {
  const cv::Mat left = tape_from_left_border_frame();
  const std::vector<EdgePair> pairs = scan_border_edges(left, grey_axis(), true, 8, 0.3f, {});
  ASSERT_EQ(pairs.size(), static_cast<size_t>(kHeight / 8));
  for (const EdgePair& pair : pairs) {
    EXPECT_TRUE(pair.first_at_border);
    EXPECT_FALSE(pair.second_at_border);
    EXPECT_EQ(pair.first_px.x, 0.0f);
    EXPECT_NEAR(pair.second_px.x, 298.0, 0.01);
    EXPECT_NEAR(pair.contrast, 1.0, 0.05);
  }
  cv::Mat right;
  cv::flip(left, right, 1);
  const std::vector<EdgePair> mirrored = scan_border_edges(right, grey_axis(), true, 8, 0.3f, {});
  ASSERT_EQ(mirrored.size(), static_cast<size_t>(kHeight / 8));
  for (const EdgePair& pair : mirrored) {
    EXPECT_TRUE(pair.second_at_border);
    EXPECT_EQ(pair.second_px.x, kWidth - 1.0f);
    EXPECT_NEAR(pair.first_px.x, kWidth - 1 - 298.0, 0.01);
  }
  EXPECT_TRUE(scan_border_edges(tape_frame(kFloor, 0), grey_axis(), true, 8, 0.3f, {}).empty());
  const cv::Mat covered(kHeight, kWidth, CV_8UC1, cv::Scalar(kTape));
  EXPECT_TRUE(scan_border_edges(covered, grey_axis(), true, 8, 0.3f, {}).empty());
  // The tape's far edge just inside the image (a strip of floor 3 pixels wide at the border,
  // too narrow to measure that edge against): the near edge is found all the same.
  cv::Mat strip = left.clone();
  strip.colRange(0, 3).setTo(cv::Scalar(kFloor));
  const std::vector<EdgePair> beside_strip =
      scan_border_edges(strip, grey_axis(), true, 8, 0.3f, {});
  ASSERT_EQ(beside_strip.size(), static_cast<size_t>(kHeight / 8));
  EXPECT_NEAR(beside_strip.front().second_px.x, 298.0, 0.01);
  // Too little contrast for the minimum asked.
  EXPECT_TRUE(scan_border_edges(left, grey_axis(), true, 8, 1.5f, {}).empty());
}

}  // namespace
}  // namespace agv::perception
