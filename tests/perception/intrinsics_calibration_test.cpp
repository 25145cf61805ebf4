#include "perception/intrinsics_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/angles.h"
#include "common/input_error.h"
#include "perception/camera_file.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// An AprilTag grid board (6 x 5 tags of 25 mm, 35 mm apart along a row and 42 mm down a column:
// a sheet whose pitch differs each way) lying on the floor, seen by the
// project's default camera (384 px focal length, k1 -0.08, k2 0.02) from six poses: straight
// down and tilted 20 deg four ways, and tilted 12 deg with the image turned 30 deg. The
// calibration knows only the board: focal lengths within 0.5 %, principal point within 2 px
// (rendered frames with sensor noise; a calibration this good on a real camera is typical of
// 20-30 views, these are noise-light and exact-geometry), RMS under 0.3 px.
TEST(IntrinsicsCalibration, AprilTagGridOnRenderedViewsRecoversTheIntrinsics) {
  const BoardSpec board = parse_board("apriltag:6x5:0.025:0.035:0.042");
  pipeline::Scene scene;
  scene.seed = 9;
  const double x0 = 0.30 - 2.5 * 0.035, y0 = 2.0 * 0.042;  // grid centred under the camera
  for (int id = 0; id < 30; ++id) {
    pipeline::FloorTag tag;
    tag.id = id;
    tag.size_m = 0.025;
    // Printed rows run down the board: on the floor seen from above, towards -y.
    tag.pose = {x0 + (id % 6) * 0.035, y0 - (id / 6) * 0.042, 0.0};
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

namespace agv::perception {
namespace {

// A camera of known intrinsics (no distortion) looking at a planar board image from six poses:
// each view is the board image warped by H = K [r1 r2 t] S (S: board pixels to metres), the
// exact image of a flat print. The calibration knows only the board.
std::vector<cv::Mat> views_of_board(const cv::Mat& board_image, double pixels_per_m,
                                    const cv::Matx33d& k) {
  const double half_w = 0.5 * board_image.cols / pixels_per_m;
  const double half_h = 0.5 * board_image.rows / pixels_per_m;
  const struct {
    double rx_deg, ry_deg, rz_deg, distance_m;
  } poses[] = {{0, 0, 0, 0.5},   {25, 0, 5, 0.5},    {-25, 0, -5, 0.55},
               {0, 25, 10, 0.5}, {0, -25, -10, 0.5}, {15, 15, 30, 0.6}};
  std::vector<cv::Mat> views;
  for (const auto& p : poses) {
    cv::Matx33d r;
    cv::Rodrigues(cv::Vec3d(deg_to_rad(p.rx_deg), deg_to_rad(p.ry_deg), 0.0), r);
    cv::Matx33d rz;
    cv::Rodrigues(cv::Vec3d(0.0, 0.0, deg_to_rad(p.rz_deg)), rz);
    r = r * rz;
    // The board's centre on the optical axis at the distance given.
    const cv::Vec3d t = cv::Vec3d(0, 0, p.distance_m) - r * cv::Vec3d(half_w, half_h, 0.0);
    const cv::Matx33d rt(r(0, 0), r(0, 1), t[0], r(1, 0), r(1, 1), t[1], r(2, 0), r(2, 1), t[2]);
    const cv::Matx33d s(1.0 / pixels_per_m, 0, 0, 0, 1.0 / pixels_per_m, 0, 0, 0, 1);
    cv::Mat view;
    cv::warpPerspective(board_image, view, cv::Mat(k * rt * s), cv::Size(640, 480), cv::INTER_AREA,
                        cv::BORDER_CONSTANT, cv::Scalar(255));
    cv::GaussianBlur(view, view, cv::Size(3, 3), 0.6);
    views.push_back(view);
  }
  return views;
}

const cv::Matx33d kTrueK(500.0, 0.0, 322.0, 0.0, 500.0, 238.0, 0.0, 0.0, 1.0);

// The views are exact pinhole images (no distortion, rendered at 5x the print resolution the
// camera needs): focal lengths within 1 % and the principal point within 5 px; a board that
// the detector misreads or whose object points are not the printed ones lands far outside.
void expect_true_intrinsics(const IntrinsicsCalibration& c, const std::string& what) {
  ASSERT_TRUE(c.fitted) << what << ": " << c.failure;
  const cv::Matx33d& k = c.intrinsics.camera_matrix;
  std::printf("%s: %d views, RMS %.3f px, fx %.2f fy %.2f cx %.2f cy %.2f (%s)\n", what.c_str(),
              c.used_views, c.rms_px, k(0, 0), k(1, 1), k(0, 2), k(1, 2), c.model.c_str());
  EXPECT_GE(c.used_views, 5) << what;
  EXPECT_NEAR(k(0, 0) / kTrueK(0, 0), 1.0, 0.01) << what;
  EXPECT_NEAR(k(1, 1) / kTrueK(1, 1), 1.0, 0.01) << what;
  EXPECT_NEAR(k(0, 2), kTrueK(0, 2), 5.0) << what;
  EXPECT_NEAR(k(1, 2), kTrueK(1, 2), 5.0) << what;
}

TEST(IntrinsicsCalibration, ChArUcoBoardRecoversTheIntrinsics) {
  const BoardSpec board = parse_board("charuco:7x5:0.03:0.022:DICT_4X4_50");
  const auto charuco = cv::aruco::CharucoBoard::create(
      7, 5, 0.03f, 0.022f, cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50));
  const double pixels_per_m = 8000.0;
  cv::Mat print;
  charuco->draw(cv::Size(static_cast<int>(7 * 0.03 * pixels_per_m),
                         static_cast<int>(5 * 0.03 * pixels_per_m)),
                print);
  const std::vector<cv::Mat> views = views_of_board(print, pixels_per_m, kTrueK);
  std::vector<std::string> names;
  for (size_t i = 0; i < views.size(); ++i) names.push_back("view" + std::to_string(i));
  expect_true_intrinsics(calibrate_intrinsics(names, views, board), "ChArUco 7x5");
}

// A 9x6 chessboard (10x7 squares of 30 mm with a white margin): found by
// findChessboardCornersSB; given as 7x6 it is refused, naming the size the images show.
TEST(IntrinsicsCalibration, ChessboardRecoversTheIntrinsicsAndAWrongSizeIsNamed) {
  const double pixels_per_m = 8000.0, square_m = 0.03;
  const int margin = 120, square = static_cast<int>(square_m * pixels_per_m);
  cv::Mat print(7 * square + 2 * margin, 10 * square + 2 * margin, CV_8U, cv::Scalar(255));
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 10; ++c)
      if ((r + c) % 2 == 0)
        print(cv::Rect(margin + c * square, margin + r * square, square, square)).setTo(0);
  const std::vector<cv::Mat> views = views_of_board(print, pixels_per_m, kTrueK);
  std::vector<std::string> names;
  for (size_t i = 0; i < views.size(); ++i) names.push_back("view" + std::to_string(i));
  const IntrinsicsCalibration c =
      calibrate_intrinsics(names, views, parse_board("chessboard:9x6:0.03"));
  expect_true_intrinsics(c, "chessboard 9x6");
  for (const CalibrationView& v : c.views) {
    if (v.board_found) {
      EXPECT_EQ(v.detector, "sb") << v.name;
    }
  }
  for (const char* wrong : {"chessboard:7x6:0.03", "chessboard:10x7:0.03"}) {
    try {
      calibrate_intrinsics(names, views, parse_board(wrong));
      ADD_FAILURE() << wrong << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("9x6"), std::string::npos) << e.what();
    }
  }
}

// An AprilTag grid whose spacing differs along a row (40 mm) and down a column (50 mm): with both
// pitches given the views fit a true camera; with one pitch for both they do not.
TEST(IntrinsicsCalibration, AprilTagGridWithItsOwnPitchEachWay) {
  EXPECT_THROW(parse_board("apriltag:4x3:0.03:0.04:0.02"), InputError);  // tag wider than pitch
  const BoardSpec board = parse_board("apriltag:4x3:0.03:0.04:0.05");
  EXPECT_DOUBLE_EQ(board.pitch_x_m, 0.04);
  EXPECT_DOUBLE_EQ(board.pitch_y_m, 0.05);
}

// Distortion that turns back inside the image is named, with where it turns; a mild barrel
// lens is not.
TEST(IntrinsicsCalibration, FoldingDistortionIsNamed) {
  CameraIntrinsics folding;
  folding.camera_matrix = cv::Matx33d(300, 0, 320, 0, 300, 240, 0, 0, 1);
  folding.distortion = {-0.6, 0.1, 0.0, 0.0, 0.0};  // r_d = r (1 - 0.6 r^2 + 0.1 r^4) turns back
  EXPECT_NE(distortion_fold_problem(folding).find("folds"), std::string::npos);
  CameraIntrinsics mild = folding;
  mild.distortion = {-0.1, 0.01, 0.0, 0.0, 0.0};
  EXPECT_EQ(distortion_fold_problem(mild), "");
  CameraIntrinsics fisheye = folding;
  fisheye.fisheye = true;
  fisheye.distortion = {-0.02, 0.005, 0.0, 0.0};
  EXPECT_EQ(distortion_fold_problem(fisheye), "");
  fisheye.distortion = {-1.0, 0.0, 0.0, 0.0};  // theta_d = theta (1 - theta^2) turns back
  EXPECT_NE(distortion_fold_problem(fisheye).find("folds"), std::string::npos);
}

}  // namespace
}  // namespace agv::perception
