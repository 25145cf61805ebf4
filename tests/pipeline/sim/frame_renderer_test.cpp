#include "pipeline/sim/frame_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "support/test_scenes.h"

namespace agv::pipeline {
namespace {

perception::CameraModel default_camera() {
  return perception::CameraModel(testing::default_intrinsics(), testing::straight_down_mount());
}

TEST(FrameRenderer, DeterministicForASeedAndFrameIndex) {
  const FrameRenderer a(default_camera(), testing::straight_tape_scene(3));
  const FrameRenderer b(default_camera(), testing::straight_tape_scene(3));
  const FrameRenderer c(default_camera(), testing::straight_tape_scene(4));
  const Pose2 pose{0.5, 0.01, 0.02};
  const cv::Mat fa = a.render(pose, {0.3, 0, 0}, 5);
  EXPECT_EQ(cv::norm(fa, b.render(pose, {0.3, 0, 0}, 5), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(fa, c.render(pose, {0.3, 0, 0}, 5), cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(fa, a.render(pose, {0.3, 0, 0}, 6), cv::NORM_L1), 0.0);  // new noise
  EXPECT_EQ(fa.type(), CV_8UC3);
  EXPECT_EQ(fa.cols, 640);
  EXPECT_EQ(fa.rows, 480);
}

// With every effect off, a pixel whose floor point is on the tape's centre line has the tape's
// colour, and one 30 mm to the side has the floor's.
TEST(FrameRenderer, TapeIsWhereTheCameraModelSaysItIs) {
  Scene scene = testing::straight_tape_scene();
  scene.floor.texture_contrast = 0.0;
  scene.tapes[0].texture_contrast = 0.0;
  scene.effects = ImageEffects{0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  const perception::CameraModel camera(testing::default_intrinsics(),
                                       testing::tilted_offset_mount());
  const FrameRenderer renderer(camera, scene);
  const Pose2 pose{0.8, -0.012, deg_to_rad(4.0)};
  const cv::Mat frame = renderer.render(pose, {0.0, 0.0, 0.0}, 0);
  const Pose2 to_vehicle = pose.inverse();
  for (double x_world : {1.1, 1.15, 1.2}) {  // 0.3 to 0.4 m ahead of the vehicle: in view
    for (double y_world : {0.0, 0.03, -0.03}) {
      const Eigen::Vector2d p = to_vehicle.transform({x_world, y_world});
      const auto pixel = camera.floor_to_pixel(p);
      ASSERT_TRUE(pixel);
      ASSERT_TRUE(pixel->x >= 0 && pixel->y >= 0 && pixel->x <= 639 && pixel->y <= 479)
          << x_world << ", " << y_world;
      const cv::Vec3b colour = frame.at<cv::Vec3b>(static_cast<int>(std::lround(pixel->y)),
                                                   static_cast<int>(std::lround(pixel->x)));
      const cv::Vec3d expected = y_world == 0.0 ? scene.tapes[0].color_bgr : scene.floor.color_bgr;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(colour[c], expected[c], 1.0) << x_world << ", " << y_world;
    }
  }
}

// The noise added has the configured standard deviation: on a flat floor with no other effect,
// the frame-to-frame difference of two noise draws has sigma * sqrt(2).
TEST(FrameRenderer, SensorNoiseHasTheConfiguredSigma) {
  Scene scene = testing::straight_tape_scene();
  scene.tapes[0].path = control::Path::starting_at({50, 50, 0}).add_line(1.0);
  scene.floor.texture_contrast = 0.0;
  scene.effects = ImageEffects{4.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  const FrameRenderer renderer(default_camera(), scene);
  cv::Mat a, b;
  renderer.render({0, 0, 0}, {}, 1).convertTo(a, CV_32F);
  renderer.render({0, 0, 0}, {}, 2).convertTo(b, CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(a - b, mean, stddev);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(stddev[c], 4.0 * std::sqrt(2.0), 0.3);  // rounding adds ~0.3
}

// The 8-bit output clips at both ends rather than wrapping: on a near-black floor (level 5) with
// noise of sigma 40 (1.6 x a standard normal times 25, rounded), a level falls below 1 where
// 25 z rounds to -3 or less (z < -0.1: 0.460 of them) and never wraps to a bright value; under
// a glare spot of 700 levels the floor is white (255), never wrapped to a dark one.
TEST(FrameRenderer, ExposureClipsAtBothEndsOfTheEightBitRange) {
  Scene scene = testing::straight_tape_scene();
  scene.tapes[0].path = control::Path::starting_at({50, 50, 0}).add_line(1.0);
  scene.floor.texture_contrast = 0.0;
  scene.floor.color_bgr = cv::Vec3d(5, 5, 5);
  scene.effects = ImageEffects{40.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  scene.effects.specular_strength = 700.0;
  scene.effects.specular_x = 0.5;
  scene.effects.specular_y = 0.5;
  scene.effects.specular_radius = 0.05;  // 32 px
  const FrameRenderer renderer(default_camera(), scene);
  const cv::Mat frame = renderer.render({0, 0, 0}, {}, 1);
  // Dark: the top-left quarter, far from the spot (glare under 1e-5 levels there).
  const cv::Mat dark = frame(cv::Rect(0, 0, 160, 120)).reshape(1);
  const double zeros = static_cast<double>(dark.total() - cv::countNonZero(dark)) / dark.total();
  EXPECT_NEAR(zeros, 0.460, 0.02);
  double darkest = 0.0, brightest = 0.0;
  cv::minMaxLoc(dark, &darkest, &brightest);
  EXPECT_LE(brightest, 5 + 5.5 * 40.0);  // the noise bank is clipped at 5 sigma
  // Bright: within 8 px of the spot's centre the glare exceeds 700 exp(-1/16) - 5 sigma > 255.
  const cv::Mat bright = frame(cv::Rect(320 - 8, 240 - 8, 16, 16)).reshape(1);
  cv::minMaxLoc(bright, &darkest, &brightest);
  EXPECT_EQ(darkest, 255.0);
}

// Motion blur spreads the tape edge along the motion: sideways motion over the exposure widens
// the transition across the tape; motion along the tape does not.
TEST(FrameRenderer, MotionBlurFollowsTheMotion) {
  Scene scene = testing::straight_tape_scene();
  scene.floor.texture_contrast = 0.0;
  scene.tapes[0].texture_contrast = 0.0;
  scene.effects = ImageEffects{0.0, 0.01, 0.0, 0.0, 0.0, 1.0};
  const FrameRenderer renderer(default_camera(), scene);
  auto transition_px = [&](const BodyTwist& twist) {
    const cv::Mat frame = renderer.render({0.0, 0.0, 0.0}, twist, 0);
    int ramp = 0;  // pixels of the middle row neither floor nor tape in the blue channel
    for (int u = 0; u < frame.cols; ++u) {
      const int b = frame.at<cv::Vec3b>(240, u)[0];
      if (b > 137 && b < 161) ++ramp;
    }
    return ramp;
  };
  const int still = transition_px({0.0, 0.0, 0.0});
  const int along = transition_px({0.5, 0.0, 0.0});
  const int across = transition_px({0.0, 0.5, 0.0});  // 5 mm in 10 ms: about 13 px of blur
  EXPECT_LE(still, 4);
  EXPECT_LE(along, 4);
  EXPECT_GE(across, 10);  // two ramps of ~13 px, 57 % of each inside the counted band
}

}  // namespace
}  // namespace agv::pipeline
