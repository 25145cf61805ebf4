#include "perception/floor_map.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// The map agrees with the camera model at sub-pixel positions it interpolates (1 um: the
// contract says far below a micrometre for usual lenses), under two mounts.
TEST(FloorMap, InterpolatesTheCameraModel) {
  for (const MountPose& mount : {testing::straight_down_mount(), testing::tilted_offset_mount()}) {
    const CameraModel camera(testing::default_intrinsics(), mount);
    const FloorMap map(camera);
    cv::RNG rng(5);
    for (int i = 0; i < 200; ++i) {
      const double u = rng.uniform(0.0, 639.0), v = rng.uniform(0.0, 479.0);
      const auto mapped = map.at(u, v);
      const auto exact = camera.pixel_to_floor({u, v});
      ASSERT_TRUE(mapped && exact);
      EXPECT_LT((*mapped - *exact).norm(), 1e-6) << u << ", " << v;
      // Every point in view lies in the view circle.
      EXPECT_LE((*mapped - map.view_centre_m()).norm(), map.view_radius_m() + 1e-9);
    }
    EXPECT_FALSE(map.at(-1.0, 10.0));
    EXPECT_FALSE(map.at(10.0, 480.0));
  }
}

// Straight down 0.15 m up with f = 384 px: a pixel covers 0.15 / 384 = 0.39 mm at the principal
// point (barrel distortion makes it larger towards the edges: the median is not smaller).
TEST(FloorMap, FootprintIsHeightOverFocalLength) {
  const FloorMap map(CameraModel(testing::default_intrinsics(), testing::straight_down_mount()));
  EXPECT_NEAR(map.footprint_m().at<float>(240, 320), 0.15 / 384.0, 0.01 * 0.15 / 384.0);
  EXPECT_GE(map.typical_footprint_m(), 0.15 / 384.0 * 0.999);
  EXPECT_LT(map.typical_footprint_m(), 0.15 / 384.0 * 1.2);
}

// A camera tilted 80 deg from straight down sees the horizon: the image's top rows see no
// floor (NaN in the map, nullopt from at).
TEST(FloorMap, PixelsAboveTheHorizonSeeNoFloor) {
  const double tilt = 80.0 * CV_PI / 180.0;
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(std::sin(tilt), 0.0, -std::cos(tilt));
  r.col(1) = Eigen::Vector3d(-std::cos(tilt), 0.0, -std::sin(tilt));
  r.col(0) = r.col(1).cross(r.col(2));
  const FloorMap map(
      CameraModel(testing::default_intrinsics(), MountPose::from_rotation({0.3, 0.0, 0.15}, r)));
  EXPECT_TRUE(std::isnan(map.x_m().at<float>(0, 320)));
  EXPECT_FALSE(map.at(320.0, 0.0));
  EXPECT_TRUE(map.at(320.0, 479.0));
}

// One map per camera: the same intrinsics and mount share it (the renderer and estimators of
// every run), another mount has its own, equal to one made directly.
TEST(FloorMap, SharedOncePerCamera) {
  const CameraModel a(testing::default_intrinsics(), testing::straight_down_mount());
  const CameraModel same(testing::default_intrinsics(), testing::straight_down_mount());
  const CameraModel moved(testing::default_intrinsics(), testing::straight_down_mount(0.31));
  const auto first = FloorMap::shared(a);
  EXPECT_EQ(FloorMap::shared(same).get(), first.get());
  const auto other = FloorMap::shared(moved);
  EXPECT_NE(other.get(), first.get());
  const FloorMap direct(moved);
  EXPECT_EQ(cv::norm(other->x_m(), direct.x_m(), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(other->y_m(), direct.y_m(), cv::NORM_INF), 0.0);
  EXPECT_NEAR(other->at(319.5, 239.5)->x(), 0.31, 1e-6);  // the principal point: below it
}

}  // namespace
}  // namespace agv::perception
