#include "perception/hough_baseline.h"

#include <gtest/gtest.h>

#include "common/angles.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// The yardstick must itself measure: on rendered frames of a straight 25 mm tape with the
// vehicle up to 20 mm and 6 deg off, within 1 mm and 0.5 deg (segments end on whole pixels,
// 0.4 mm on the floor, and Hough's 1 deg bins snap a segment's angle: measured 0.2 mm and up to
// 0.3 deg). A fit through the end points of both edges leaned 1.2 deg and missed by 5.9 mm.
TEST(HoughBaseline, MeasuresAStraightTape) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const pipeline::FrameRenderer renderer(camera, testing::straight_tape_scene());
  const HoughBaseline baseline(camera, 0.025);
  for (const Pose2& pose : {Pose2{1.0, 0.0, 0.0}, Pose2{1.5, 0.02, deg_to_rad(6.0)},
                            Pose2{2.0, -0.015, deg_to_rad(-4.0)}}) {
    const LineMeasurement m = baseline.estimate(renderer.render(pose, {0.0, 0.0, 0.0}, 1), 0.5);
    ASSERT_TRUE(m.line_found) << pose.y_m;
    EXPECT_NEAR(m.e_d_m, pose.y_m, 0.001);  // tape along world x: e_d = y, e_theta = yaw
    EXPECT_NEAR(rad_to_deg(m.e_theta_rad), rad_to_deg(pose.yaw_rad), 0.5);
    EXPECT_EQ(m.stamp_s, 0.5);
  }
}

// No tape, or only one of its edges in view (the tape half out of the image): no line.
TEST(HoughBaseline, NoLineWithoutBothEdges) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const pipeline::FrameRenderer renderer(camera, testing::straight_tape_scene());
  const HoughBaseline baseline(camera, 0.025);
  // 0.3 m to the side: no tape in view.
  EXPECT_FALSE(baseline.estimate(renderer.render({1.0, 0.3, 0.0}, {}, 1), 0.0).line_found);
  // The view's half-width at the camera is 0.125 m (f 384 px, 0.15 m up; a little more with the
  // barrel distortion): the tape's centre 0.128 m to the side leaves one edge in view.
  EXPECT_FALSE(baseline.estimate(renderer.render({1.0, 0.128, 0.0}, {}, 1), 0.0).line_found);
}

}  // namespace
}  // namespace agv::perception
