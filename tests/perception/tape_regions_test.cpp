#include "perception/tape_regions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace agv::perception {
namespace {

// Grey frames, dark on light: an axis with tape (40) at 1 and floor (180) at 0.
ContrastAxis dark_tape_axis() {
  ContrastAxis axis;
  axis.weights = {-1.0f / 140.0f, 0.0f, 0.0f};
  axis.offset = 180.0f / 140.0f;
  return axis;
}

// A downsampled (4x) 160 x 120 frame with a band 6 px wide at 30 deg from the image's vertical,
// and a broad dark patch 50 px wide at the left. The band is one region along its direction,
// the ridge of the bar response: no wider than the band (6 px, 24 px at full size), its spread
// across that of a band, not a blob; the patch, no bar of that width, gives no region of its
// own interior (at most thin ones along its edge).
TEST(TapeRegions, FindsTheBandNotTheBroadPatch) {
  cv::Mat small(120, 160, CV_8UC1, cv::Scalar(180));
  const double angle = 30.0 * CV_PI / 180.0;
  const cv::Point2d centre(110, 60), along(std::sin(angle), std::cos(angle));
  cv::line(small, centre - 80 * along, centre + 80 * along, cv::Scalar(40), 6, cv::LINE_AA);
  cv::rectangle(small, cv::Rect(0, 0, 50, 120), cv::Scalar(40), cv::FILLED);
  const TapeRegions found = find_tape_regions(small, dark_tape_axis(), 4, {6.0}, 12);
  ASSERT_FALSE(found.regions.empty());
  const TapeRegion& band = found.regions.front();  // largest first
  EXPECT_NEAR(band.centroid_px.x, 4 * centre.x, 4 * 6.0);
  EXPECT_NEAR(band.centroid_px.y, 4 * centre.y, 4 * 6.0);
  // Direction within 3 deg of the band's (either sense).
  EXPECT_GT(std::abs(band.direction.dot(along)), std::cos(3.0 * CV_PI / 180.0));
  EXPECT_GT(band.width_px, 0.0);
  EXPECT_LE(band.width_px, 4 * 6.0);
  EXPECT_LT(band.spread_px, 4 * 2 * 6.0);
  EXPECT_GT(band.length_px, 4 * 100.0);
  for (const TapeRegion& r : found.regions) {
    // Nothing found inside the patch, away from its edge at x = 50.
    EXPECT_FALSE(r.centroid_px.x < 4 * 40.0) << r.centroid_px;
  }
  // Levels: the floor reads about 0, the threshold lies between floor and tape.
  EXPECT_NEAR(found.floor_level, 0.0, 0.1);
  EXPECT_GT(found.threshold, found.floor_level);
  EXPECT_LT(found.threshold, found.tape_level);
}

// The band of the test above on a floor of coarse blotches (blurred noise, features about the
// band's width) whose darkest reach the tape's level. The region of the band must be the band,
// not the band and the blotches it touches: its direction within 3 deg, its spread across no
// more than twice the band's width, its area at most 1.5 times the band's (6 x 160 px). With
// the threshold of ISODATA alone (0.25 here), whose two classes are then the floor's smooth and
// blotchy parts, the blotches join the band: spread 210 px, area 1136.
TEST(TapeRegions, AFloorTextureAsStrongAsTheTapeDoesNotJoinTheBand) {
  cv::Mat texture(120, 160, CV_32F);
  cv::RNG rng(5);
  rng.fill(texture, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 2.0);
  cv::Scalar mean, sigma;
  cv::meanStdDev(texture, mean, sigma);
  cv::Mat small;  // grey 180, blotches of 70 grey levels (1 sigma)
  texture.convertTo(small, CV_8U, 70.0 / sigma[0], 180.0 - 70.0 * mean[0] / sigma[0]);
  const double angle = 30.0 * CV_PI / 180.0;
  const cv::Point2d centre(90, 60), along(std::sin(angle), std::cos(angle));
  cv::line(small, centre - 80 * along, centre + 80 * along, cv::Scalar(40), 6, cv::LINE_AA);
  const TapeRegions found = find_tape_regions(small, dark_tape_axis(), 4, {3.0, 6.0, 12.0}, 12);
  ASSERT_FALSE(found.regions.empty());
  const TapeRegion& band = found.regions.front();
  EXPECT_GT(std::abs(band.direction.dot(along)), std::cos(3.0 * CV_PI / 180.0));
  EXPECT_LE(band.spread_px, 4 * 2 * 6.0);
  EXPECT_LE(band.area_small_px, 1.5 * 6 * 160);
}

TEST(TapeRegions, AnEmptyFloorHasNoRegions) {
  cv::Mat small(120, 160, CV_8UC1, cv::Scalar(180));
  cv::RNG rng(3);
  cv::Mat noise(small.size(), CV_8UC1);
  rng.fill(noise, cv::RNG::NORMAL, 0, 3);
  small -= noise;
  EXPECT_TRUE(find_tape_regions(small, dark_tape_axis(), 4, {6.0}, 12).regions.empty());
}

}  // namespace
}  // namespace agv::perception
