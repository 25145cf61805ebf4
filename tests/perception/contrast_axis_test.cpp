#include "perception/contrast_axis.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace agv::perception {
namespace {

// A 160 x 120 floor with a vertical band of tape 8 px wide (7 % of the pixels).
cv::Mat band_frame(const cv::Scalar& floor_bgr, const cv::Scalar& tape_bgr) {
  cv::Mat frame(120, 160, CV_8UC3, floor_bgr);
  cv::rectangle(frame, cv::Rect(76, 0, 8, 120), tape_bgr, cv::FILLED);
  return frame;
}

cv::Vec3b bgr(const cv::Scalar& s) {
  return cv::Vec3b(static_cast<uchar>(s[0]), static_cast<uchar>(s[1]), static_cast<uchar>(s[2]));
}

// The axis's contract: about 0 on the floor, about 1 on the tape (0.1: the tape's estimated
// colour is the mean of the pixels that differ most, which on a clean two-colour frame are the
// tape's), for dark tape on a light floor, light on dark, and colour on colour.
TEST(ContrastAxis, FloorReadsZeroAndTapeOne) {
  const std::vector<std::pair<cv::Scalar, cv::Scalar>> cases = {
      {cv::Scalar(150, 160, 170), cv::Scalar(30, 30, 30)},   // black tape, light floor
      {cv::Scalar(60, 60, 60), cv::Scalar(230, 230, 230)},   // white tape, dark floor
      {cv::Scalar(120, 125, 130), cv::Scalar(200, 90, 40)},  // blue tape, grey floor
      {cv::Scalar(90, 110, 140), cv::Scalar(20, 200, 230)},  // yellow tape, brown floor
  };
  for (const auto& [floor, tape] : cases) {
    const auto axis = estimate_contrast_axis(band_frame(floor, tape), std::nullopt);
    ASSERT_TRUE(axis) << tape;
    EXPECT_NEAR(axis->apply(bgr(floor)), 0.0, 0.1) << tape;
    EXPECT_NEAR(axis->apply(bgr(tape)), 1.0, 0.1) << tape;
    EXPECT_FALSE(axis->from_hint);
  }
}

TEST(ContrastAxis, GreyFramesUseTheFirstWeight) {
  cv::Mat grey(120, 160, CV_8UC1, cv::Scalar(180));
  cv::rectangle(grey, cv::Rect(76, 0, 8, 120), cv::Scalar(40), cv::FILLED);
  const auto axis = estimate_contrast_axis(grey, std::nullopt);
  ASSERT_TRUE(axis);
  EXPECT_NEAR(axis->apply(static_cast<unsigned char>(180)), 0.0, 0.1);
  EXPECT_NEAR(axis->apply(static_cast<unsigned char>(40)), 1.0, 0.1);
}

// A hint distinct from the floor is taken as the tape colour.
TEST(ContrastAxis, AHintGivesTheTapeColour) {
  const cv::Scalar floor(150, 160, 170), tape(30, 30, 30);
  const auto axis = estimate_contrast_axis(band_frame(floor, tape), cv::Vec3d(30, 30, 30));
  ASSERT_TRUE(axis);
  EXPECT_TRUE(axis->from_hint);
  EXPECT_NEAR(axis->apply(bgr(floor)), 0.0, 0.05);
  EXPECT_NEAR(axis->apply(bgr(tape)), 1.0, 0.05);
}

TEST(ContrastAxis, AFlatFrameHasNoAxis) {
  const cv::Mat flat(120, 160, CV_8UC3, cv::Scalar(100, 110, 120));
  EXPECT_FALSE(estimate_contrast_axis(flat, std::nullopt));
  EXPECT_FALSE(choose_contrast_axis(flat, std::nullopt, {8.0}));
}

// A broad dark shadow differs from the floor more than blue tape does (in grey level), but it is
// no bar 8 px wide: the axis chosen is the tape's, on which the shadow reads well under the
// half-way threshold (0.5) and the tape about 1.
TEST(ContrastAxis, TheBarNotTheShadowChoosesTheAxis) {
  const cv::Scalar floor(150, 155, 160), tape(200, 90, 40), shadow(60, 62, 64);
  cv::Mat frame = band_frame(floor, tape);
  cv::rectangle(frame, cv::Rect(0, 0, 50, 120), shadow, cv::FILLED);
  const auto axis = choose_contrast_axis(frame, std::nullopt, {8.0});
  ASSERT_TRUE(axis);
  EXPECT_NEAR(axis->apply(bgr(tape)), 1.0, 0.15);
  EXPECT_NEAR(axis->apply(bgr(floor)), 0.0, 0.15);
  EXPECT_LT(axis->apply(bgr(shadow)), 0.5);
}

// Wide green tape filling the left of the view, grey floor with a lighter strip on the right:
// along the lighter-grey axis the strip stands out as a bar and the tape reads below the floor.
// Without a hint that axis is offered (the search tries it where the best gives no line); with
// the tape's colour given every axis offered reads the tape above the floor, by at least half
// the tape's contrast (the axis scales the tape to about 1).
TEST(ContrastAxis, WithAHintEveryAxisReadsTheTapeAboveTheFloor) {
  const cv::Scalar floor(120, 120, 120), tape(60, 170, 60), strip(170, 170, 170);
  cv::Mat frame(120, 160, CV_8UC3, floor);
  cv::rectangle(frame, cv::Rect(0, 0, 70, 120), tape, cv::FILLED);
  cv::rectangle(frame, cv::Rect(120, 0, 8, 120), strip, cv::FILLED);
  const auto reads_tape_above_floor = [&](const ContrastAxis& axis) {
    return axis.apply(bgr(tape)) - axis.apply(bgr(floor)) > 0.5f;
  };
  const std::vector<ContrastAxis> unhinted = choose_contrast_axes(frame, std::nullopt, {8.0}, 2);
  EXPECT_TRUE(std::any_of(unhinted.begin(), unhinted.end(),
                          [&](const ContrastAxis& axis) { return !reads_tape_above_floor(axis); }));
  const std::vector<ContrastAxis> hinted =
      choose_contrast_axes(frame, cv::Vec3d(60, 170, 60), {8.0}, 2);
  ASSERT_FALSE(hinted.empty());
  for (const ContrastAxis& axis : hinted) EXPECT_TRUE(reads_tape_above_floor(axis));
}

// A row at once gives what each pixel gives alone (the scan's and the regions' contrast come
// from it), bit for bit: colour and grey rows, of lengths that leave a vector loop's tail.
TEST(ContrastAxis, ARowAtOnceIsEachPixelAlone) {
  ContrastAxis axis;
  axis.weights = cv::Vec3f(0.013f, -0.021f, 0.0047f);
  axis.offset = -0.37f;
  cv::RNG rng(7);
  for (int n : {1, 7, 33, 160}) {
    cv::Mat colour(1, n, CV_8UC3), grey(1, n, CV_8UC1);
    rng.fill(colour, cv::RNG::UNIFORM, 0, 256);
    rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
    std::vector<float> from_colour(n), from_grey(n);
    axis.apply_to_row(colour.ptr<unsigned char>(), n, 3, from_colour.data());
    axis.apply_to_row(grey.ptr<unsigned char>(), n, 1, from_grey.data());
    for (int x = 0; x < n; ++x) {
      EXPECT_EQ(from_colour[x], axis.apply(colour.at<cv::Vec3b>(0, x))) << "colour, x " << x;
      EXPECT_EQ(from_grey[x], axis.apply(grey.at<unsigned char>(0, x))) << "grey, x " << x;
    }
  }
}

}  // namespace
}  // namespace agv::perception
