#include "pipeline/perceiver.h"

#include <gtest/gtest.h>

#include <string>

#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::pipeline {
namespace {

// Perception with the path memory on rendered frames of straight tape, 1 cm a frame on exact
// wheel odometry from 1 m along it (the camera sees it 0.2-0.4 m ahead): frames 0-5 show it,
// 6-13 show a floor without tape (8 cm blind, over PathMemoryOptions::confirm_after_blind_m),
// 14 and 15 show it again before the vehicle reaches the tape it saw first. The frame after the
// blind stretch, only carried back from the view, gives no line and says why; the next agrees
// with it and gives the line. With the reason dropped on its way out, the detection says
// nothing.
TEST(ImagePerceiver, ALineFoundAgainAfterABlindStretchSaysWhyItWaits) {
  const perception::CameraModel camera(testing::default_intrinsics(),
                                       testing::straight_down_mount());
  const Scene scene = testing::straight_tape_scene();
  Scene bare = scene;
  bare.tapes.clear();
  const FrameRenderer with_tape(camera, scene), without_tape(camera, bare);
  ImagePerceiver perceiver(camera, testing::hinted(scene), /*path_memory=*/true);
  for (int k = 0; k <= 15; ++k) {
    SourceFrame frame;
    frame.index = static_cast<std::uint64_t>(k);
    frame.t_s = 0.05 * k;
    const Pose2 pose{-1.0 + 0.01 * k, 0.0, 0.0};
    frame.pose = pose;
    frame.odometry = pose;
    const bool blind = k >= 6 && k <= 13;
    frame.image = (blind ? without_tape : with_tape).render(pose, {0.2, 0.0, 0.0}, frame.index);
    perception::LineDetection seen;
    const LineMeasurement m = perceiver.measure(frame, &seen);
    if (k <= 5) {
      EXPECT_TRUE(m.line_found) << k << ": " << seen.rejected_because;
    } else if (blind) {
      EXPECT_FALSE(m.line_found) << k;
    } else if (k == 14) {
      EXPECT_FALSE(m.line_found);
      EXPECT_NE(seen.rejected_because.find("not yet confirmed by the next frame"),
                std::string::npos)
          << seen.rejected_because;
    } else {
      ASSERT_TRUE(m.line_found) << seen.rejected_because;
      EXPECT_TRUE(m.extrapolated);
      EXPECT_NEAR(m.e_d_m, 0.0, 0.001);
    }
  }
}

}  // namespace
}  // namespace agv::pipeline
