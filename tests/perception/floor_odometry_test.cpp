#include "perception/floor_odometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/angles.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// Frames of a vehicle driving a known path over a textured concrete floor (the default
// renderer's: 2 mm features, 10 % contrast, sensor noise, vignetting, motion blur), 30 mm and up
// to 2 deg a frame; the motion FloorOdometry reads from consecutive frames against the true
// one. Bounds: 0.5 mm and 0.1 deg a frame (the bird's-eye view has 1 mm pixels; LK tracks to a
// tenth of one, and the many corners' RANSAC fit averages); the motion itself is 30 mm.
TEST(FloorOdometry, ReadsTheVehiclesMotionFromTheFloorTexture) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const pipeline::FrameRenderer renderer(camera, testing::straight_tape_scene());
  FloorOdometry odometry(camera);
  Pose2 last;
  int measured = 0;
  for (int k = 0; k < 12; ++k) {
    const Pose2 pose{0.03 * k, 0.004 * std::sin(0.5 * k), deg_to_rad(2.0) * std::sin(0.4 * k)};
    const std::optional<Pose2> motion =
        odometry.motion(renderer.render(pose, {0.3, 0.0, 0.0}, static_cast<std::uint64_t>(k)));
    if (k == 0) {
      EXPECT_FALSE(motion);  // nothing to compare with yet
    } else {
      ASSERT_TRUE(motion) << k;
      const Pose2 truth = last.inverse().compose(pose);
      EXPECT_NEAR(motion->x_m, truth.x_m, 5e-4) << k;
      EXPECT_NEAR(motion->y_m, truth.y_m, 5e-4) << k;
      EXPECT_NEAR(rad_to_deg(wrap_angle_rad(motion->yaw_rad - truth.yaw_rad)), 0.0, 0.1) << k;
      ++measured;
    }
    last = pose;
  }
  EXPECT_EQ(measured, 11);
}

// A floor with no texture (only sensor noise, which does not move with the floor): no motion is
// reported rather than a wrong one.
TEST(FloorOdometry, FeaturelessFloorGivesNoMotion) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.floor.texture_contrast = 0.0;
  const pipeline::FrameRenderer renderer(camera, scene);
  FloorOdometry odometry(camera);
  int reported = 0;
  for (int k = 0; k < 6; ++k) {
    const Pose2 pose{0.03 * k, 0.0, 0.0};
    const std::optional<Pose2> motion =
        odometry.motion(renderer.render(pose, {0.3, 0.0, 0.0}, static_cast<std::uint64_t>(k)));
    if (motion && (std::abs(motion->x_m - 0.03) > 0.002 || std::abs(motion->y_m) > 0.002))
      ++reported;
  }
  EXPECT_EQ(reported, 0);
}

}  // namespace
}  // namespace agv::perception
