#include "perception/camera_model.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include <opencv2/calib3d.hpp>

#include "common/angles.h"
#include "perception/camera_file.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// DESIGN.md's worked example: straight down, image top to the front.
TEST(MountPose, DesignWorkedExample) {
  const Eigen::Matrix3d r = testing::straight_down_mount().rotation();
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  EXPECT_TRUE(r.isApprox(expected, 1e-12)) << r;
  EXPECT_NEAR(testing::straight_down_mount().tilt_rad(), 0.0, 1e-12);
}

TEST(MountPose, RollPitchYawRoundTrip) {
  for (const Eigen::Vector3d& rpy :
       {Eigen::Vector3d(3.0, 0.1, -1.5), Eigen::Vector3d(-2.9, -0.3, 0.4),
        Eigen::Vector3d(kPi, 0.05, -kPi / 2 + 0.05)}) {
    MountPose mount;
    mount.rpy_rad = rpy;
    const MountPose back = MountPose::from_rotation(mount.xyz_m, mount.rotation());
    EXPECT_TRUE(back.rotation().isApprox(mount.rotation(), 1e-12));
  }
}

TEST(MountPose, DescribesItselfInWords) {
  const std::string words = testing::straight_down_mount().describe();
  EXPECT_NE(words.find("0.300 m ahead"), std::string::npos) << words;
  EXPECT_NE(words.find("0.150 m up"), std::string::npos) << words;
  EXPECT_NE(words.find("straight down"), std::string::npos) << words;
}

// 640 x 480 px with f = 384 px at 0.15 m: 0.25 m x 0.1875 m at the principal lines; the image
// top is the front, the image left is the vehicle's left.
TEST(CameraModel, DefaultCameraSeesTheFloorAheadOfTheVehicle) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const Eigen::Vector2d centre = *camera.pixel_to_floor({319.5, 239.5});
  EXPECT_NEAR(centre.x(), 0.30, 1e-9);
  EXPECT_NEAR(centre.y(), 0.0, 1e-9);
  // Along the principal row and column distortion only stretches: still symmetric.
  const Eigen::Vector2d top = *camera.pixel_to_floor({319.5, 0.0});
  const Eigen::Vector2d left = *camera.pixel_to_floor({0.0, 239.5});
  EXPECT_GT(top.x(), 0.30 + 0.09);
  EXPECT_NEAR(top.y(), 0.0, 1e-9);
  EXPECT_GT(left.y(), 0.12);
  EXPECT_NEAR(left.x(), 0.30, 1e-9);
  // Barrel distortion (k1 < 0): the edge pixel sees farther out than the pinhole would (0.125 m).
  EXPECT_LT(left.y(), 0.14);
}

TEST(CameraModel, PixelToFloorToPixelRoundTrip) {
  for (const MountPose& mount : {testing::straight_down_mount(), testing::tilted_offset_mount()}) {
    const CameraModel camera(testing::default_intrinsics(), mount);
    for (const cv::Point2d pixel :
         {cv::Point2d(0, 0), cv::Point2d(639, 0), cv::Point2d(320.25, 100.75), cv::Point2d(17, 470),
          cv::Point2d(639, 479)}) {
      const auto floor = camera.pixel_to_floor(pixel);
      ASSERT_TRUE(floor);
      const auto back = camera.floor_to_pixel(*floor);
      ASSERT_TRUE(back);
      EXPECT_NEAR(back->x, pixel.x, 1e-6);
      EXPECT_NEAR(back->y, pixel.y, 1e-6);
    }
  }
}

// A camera 0.15 m up, its optical axis tilted 30 deg forward from vertical: the principal
// point sees the floor 0.15 tan(30 deg) = 0.0866 m ahead of the point below the camera.
TEST(CameraModel, TiltedCameraHandCase) {
  const double tilt = deg_to_rad(30.0);
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(std::sin(tilt), 0.0, -std::cos(tilt));   // optical axis
  r.col(1) = Eigen::Vector3d(-std::cos(tilt), 0.0, -std::sin(tilt));  // image down: backwards
  r.col(0) = r.col(1).cross(r.col(2));                                // image right: vehicle right
  const MountPose mount = MountPose::from_rotation({0.3, 0.0, 0.15}, r);
  EXPECT_NEAR(mount.tilt_rad(), tilt, 1e-12);
  CameraIntrinsics pinhole = testing::default_intrinsics();
  pinhole.distortion.clear();
  const CameraModel camera(pinhole, mount);
  const Eigen::Vector2d p = *camera.pixel_to_floor({319.5, 239.5});
  EXPECT_NEAR(p.x(), 0.3 + 0.15 * std::tan(tilt), 1e-9);
  EXPECT_NEAR(p.y(), 0.0, 1e-9);
  EXPECT_FALSE(camera.floor_to_pixel({0.3, 0.0}) == std::nullopt);  // below the camera: in view
}

TEST(CameraModel, RaysAboveTheHorizonMissTheFloor) {
  const double tilt = deg_to_rad(80.0);
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(std::sin(tilt), 0.0, -std::cos(tilt));
  r.col(1) = Eigen::Vector3d(-std::cos(tilt), 0.0, -std::sin(tilt));
  r.col(0) = r.col(1).cross(r.col(2));
  const CameraModel camera(testing::default_intrinsics(),
                           MountPose::from_rotation({0.3, 0.0, 0.15}, r));
  EXPECT_FALSE(
      camera.pixel_to_floor({319.5, 0.0}).has_value());  // image top looks above the horizon
  EXPECT_TRUE(camera.pixel_to_floor({319.5, 479.0}).has_value());
}

// A fisheye lens (OpenCV's equidistant model): a floor point's pixel is what
// cv::fisheye::distortPoints makes of its pinhole projection (OpenCV's own code, not the
// camera model's), and the pixel reads back to the point. A camera file keeps the model.
TEST(CameraModel, FisheyeLensProjectsAsOpenCvsFisheyeModel) {
  CameraIntrinsics fisheye;
  fisheye.camera_matrix = cv::Matx33d(310, 0, 326, 0, 310, 310, 0, 0, 1);
  fisheye.width_px = fisheye.height_px = 640;
  fisheye.distortion = {0.03, -0.01, 0.004, -0.001};
  fisheye.fisheye = true;
  const CameraModel camera(fisheye, testing::straight_down_mount(0.30, 0.0, 0.20));
  for (const Eigen::Vector2d& floor :
       {Eigen::Vector2d(0.30, 0.0), Eigen::Vector2d(0.45, 0.12), Eigen::Vector2d(0.20, -0.25)}) {
    const auto pixel = camera.floor_to_pixel(floor);
    ASSERT_TRUE(pixel);
    const Eigen::Vector3d p_camera =
        camera.mount().rotation().transpose() *
        (Eigen::Vector3d(floor.x(), floor.y(), 0.0) - camera.mount().xyz_m);
    std::vector<cv::Point2d> normalised{{p_camera.x() / p_camera.z(), p_camera.y() / p_camera.z()}},
        distorted;
    cv::fisheye::distortPoints(normalised, distorted, cv::Mat(fisheye.camera_matrix),
                               cv::Mat(fisheye.distortion));
    EXPECT_NEAR(pixel->x, distorted[0].x, 1e-6);
    EXPECT_NEAR(pixel->y, distorted[0].y, 1e-6);
    const auto back = camera.pixel_to_floor(*pixel);
    ASSERT_TRUE(back);
    EXPECT_NEAR((*back - floor).norm(), 0.0, 1e-7);
  }
  CameraFile file;
  file.intrinsics = fisheye;
  const CameraFile read = parse_camera_text(camera_file_text(file), "fisheye.yaml");
  EXPECT_TRUE(read.intrinsics.fisheye);
  EXPECT_EQ(read.intrinsics.distortion, fisheye.distortion);
}

// The one-point projection (OpenCV's lens models written out) against OpenCV's own
// cv::projectPoints / cv::fisheye::projectPoints, for every length of coefficient vector a
// camera file may hold (4, 5, 8, 12, 14 and the fisheye's 4), strong coefficients, points out to
// wide angles: within 1e-9 px (double rounding; a dropped or swapped term moves pixels by
// whole pixels out there).
TEST(CameraModel, OnePointProjectionIsOpenCvs) {
  const std::vector<std::pair<std::vector<double>, bool>> lenses = {
      {{}, false},
      {{-0.31, 0.12, 0.002, -0.0015}, false},
      {{-0.31, 0.12, 0.002, -0.0015, -0.03}, false},
      {{0.4, -0.2, 0.001, 0.002, 0.05, 0.7, -0.1, 0.03}, false},
      {{0.4, -0.2, 0.001, 0.002, 0.05, 0.7, -0.1, 0.03, 0.004, -0.002, 0.003, 0.001}, false},
      {{0.4, -0.2, 0.001, 0.002, 0.05, 0.7, -0.1, 0.03, 0.004, -0.002, 0.003, 0.001, 0.01, -0.02},
       false},
      {{0.03, -0.01, 0.004, -0.001}, true},
  };
  for (const auto& [distortion, fisheye] : lenses) {
    CameraIntrinsics lens;
    lens.camera_matrix = cv::Matx33d(412.5, 0, 322.25, 0, 409.75, 237.5, 0, 0, 1);
    lens.distortion = distortion;
    lens.fisheye = fisheye;
    const CameraModel camera(lens, testing::straight_down_mount(0.30, 0.0, 0.20));
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(0.3, -0.2, 1.0),
          Eigen::Vector3d(-0.6, 0.45, 0.9), Eigen::Vector3d(1e-10, 0, 1)}) {
      const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
      const cv::Mat t = (cv::Mat_<double>(3, 1) << p.x(), p.y(), p.z());
      std::vector<cv::Point2d> reference;
      if (fisheye) {
        cv::fisheye::projectPoints(std::vector<cv::Point3d>{{0, 0, 0}}, reference, zero, t,
                                   cv::Mat(lens.camera_matrix), cv::Mat(distortion));
      } else {
        cv::projectPoints(std::vector<cv::Point3d>{{0, 0, 0}}, zero, t, cv::Mat(lens.camera_matrix),
                          distortion.empty() ? cv::Mat() : cv::Mat(distortion), reference);
      }
      const cv::Point2d ours = camera.camera_point_to_pixel(p);
      EXPECT_NEAR(ours.x, reference[0].x, 1e-9)
          << distortion.size() << " coefficients, " << p.transpose();
      EXPECT_NEAR(ours.y, reference[0].y, 1e-9)
          << distortion.size() << " coefficients, " << p.transpose();
    }
  }
}

// A strongly distorting lens (barrel, k1 -0.35): every pixel out to the image corners reads
// back to a ray that OpenCV's own projectPoints (not the camera model) puts on that pixel within
// a thousandth of a pixel. OpenCV's default of 5 undistortion iterations leaves the corners
// tenths of a pixel off (millimetres on the floor far ahead).
TEST(CameraModel, UndistortionIsExactOutToTheImageCorners) {
  CameraIntrinsics lens;
  lens.camera_matrix = cv::Matx33d(420, 0, 322, 0, 418, 236, 0, 0, 1);
  lens.distortion = {-0.35, 0.12, 0.0012, -0.0008, -0.015};
  const CameraModel camera(lens, testing::straight_down_mount());
  std::vector<cv::Point2d> pixels;
  for (double x : {0.0, 80.0, 320.0, 560.0, 639.0})
    for (double y : {0.0, 60.0, 240.0, 420.0, 479.0}) pixels.emplace_back(x, y);
  const std::vector<cv::Point2d> normalised = camera.undistort(pixels);
  std::vector<cv::Point3d> rays;
  for (const cv::Point2d& n : normalised) rays.emplace_back(n.x, n.y, 1.0);
  std::vector<cv::Point2d> back;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(lens.camera_matrix),
                    cv::Mat(lens.distortion), back);
  for (size_t i = 0; i < pixels.size(); ++i)
    EXPECT_LT(cv::norm(back[i] - pixels[i]), 1e-3) << pixels[i];
}

}  // namespace
}  // namespace agv::perception
