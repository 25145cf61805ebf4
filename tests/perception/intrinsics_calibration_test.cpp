#include "perception/intrinsics_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/angles.h"
#include "common/input_error.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// An AprilTag grid board (6 x 5 tags of 25 mm, 35 mm apart) lying on the floor, seen by the
// project's default camera (384 px focal length, k1 -0.08, k2 0.02) from six poses: straight
// down and tilted 20 deg four ways, and tilted 12 deg with the image turned 30 deg. The
// calibration knows only the board: focal lengths within 0.5 %, principal point within 2 px
// (rendered frames with sensor noise; a calibration this good on a real camera is typical of
// 20-30 views, these are noise-light and exact-geometry), RMS under 0.3 px.
TEST(IntrinsicsCalibration, AprilTagGridOnRenderedViewsRecoversTheIntrinsics) {
  const BoardSpec board = parse_board("apriltag:6x5:0.025:0.035");
  pipeline::Scene scene;
  scene.seed = 9;
  const double x0 = 0.30 - 2.5 * 0.035, y0 = 2.0 * 0.035;  // grid centred under the camera
  for (int id = 0; id < 30; ++id) {
    pipeline::FloorTag tag;
    tag.id = id;
    tag.size_m = 0.025;
    // Printed rows run down the board: on the floor seen from above, towards -y.
    tag.pose = {x0 + (id % 6) * 0.035, y0 - (id / 6) * 0.035, 0.0};
    scene.tags.push_back(tag);
  }
  const struct {
    double roll_deg, pitch_deg, yaw_extra_deg;
  } poses[] = {{0, 0, 0}, {20, 0, 0}, {-20, 0, 0}, {0, 20, 0}, {0, -20, 0}, {12, 8, 30}};
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  for (const auto& p : poses) {
    MountPose mount = testing::straight_down_mount(0.30, 0.0, 0.20);
    mount.rpy_rad.x() += deg_to_rad(p.roll_deg);
    mount.rpy_rad.y() += deg_to_rad(p.pitch_deg);
    mount.rpy_rad.z() += deg_to_rad(p.yaw_extra_deg);
    // Keep the board in view: aim at the grid's centre by moving the camera back over it.
    const Eigen::Vector3d axis = mount.rotation().col(2);
    const double t = mount.xyz_m.z() / -axis.z();
    mount.xyz_m.head<2>() -= (mount.xyz_m + t * axis).head<2>() - Eigen::Vector2d(0.30, 0.0);
    const CameraModel camera(testing::default_intrinsics(), mount);
    const pipeline::FrameRenderer renderer(camera, scene);
    images.push_back(renderer.render({0, 0, 0}, {}, images.size()));
    names.push_back("view" + std::to_string(images.size()));
  }
  const IntrinsicsCalibration c = calibrate_intrinsics(names, images, board);
  const cv::Matx33d& k = c.intrinsics.camera_matrix;
  const cv::Matx33d& truth = testing::default_intrinsics().camera_matrix;
  std::printf(
      "AprilTag grid: %d views, RMS %.3f px, fx %.2f fy %.2f cx %.2f cy %.2f (true %.1f %.1f "
      "%.1f %.1f), k1 %.4f k2 %.4f\n",
      c.used_views, c.rms_px, k(0, 0), k(1, 1), k(0, 2), k(1, 2), truth(0, 0), truth(1, 1),
      truth(0, 2), truth(1, 2), c.intrinsics.distortion[0], c.intrinsics.distortion[1]);
  EXPECT_EQ(c.used_views, 6);
  EXPECT_LT(c.rms_px, 0.3);
  EXPECT_NEAR(k(0, 0) / truth(0, 0), 1.0, 0.005);
  EXPECT_NEAR(k(1, 1) / truth(1, 1), 1.0, 0.005);
  EXPECT_NEAR(k(0, 2), truth(0, 2), 2.0);
  EXPECT_NEAR(k(1, 2), truth(1, 2), 2.0);
}

TEST(IntrinsicsCalibration, BoardTextsAreCheckedByName) {
  for (const char* bad : {"chessboard:9x6", "chessboard:2x6:0.025", "apriltag:6x5:0.04:0.03",
                          "apriltag:1x2:0.02:0.03", "circles:4x11:0.02"}) {
    try {
      parse_board(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--board"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace agv::perception
