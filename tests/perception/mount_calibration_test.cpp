#include "perception/mount_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/angles.h"
#include "common/input_error.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// Where the optical axis meets the floor (vehicle frame).
Eigen::Vector2d view_centre(const MountPose& mount) {
  const Eigen::Vector3d axis = mount.rotation().col(2);
  const double t = -mount.xyz_m.z() / axis.z();
  return (mount.xyz_m + t * axis).head<2>();
}

// Four 40 mm tags around the view centre, turned differently, on a textured floor.
FloorTagsFile tags_around(const MountPose& mount) {
  FloorTagsFile file;
  const Eigen::Vector2d c = view_centre(mount);
  const double dx[4] = {-0.055, 0.055, -0.055, 0.055}, dy[4] = {-0.04, -0.04, 0.04, 0.04};
  for (int i = 0; i < 4; ++i)
    file.tags.push_back({10 + i, 0.04, c.x() + dx[i], c.y() + dy[i], 0.4 * i});
  return file;
}

pipeline::Scene scene_with(const FloorTagsFile& file) {
  pipeline::Scene scene;
  scene.seed = 5;
  scene.effects.noise_sigma = 2.0;
  for (const FloorTagPose& t : file.tags) {
    pipeline::FloorTag tag;
    tag.id = t.id;
    tag.size_m = t.size_m;
    tag.pose = {t.x_m, t.y_m, t.yaw_rad};
    scene.tags.push_back(tag);
  }
  return scene;
}

// Issue 5's bar: from 3 rendered frames with sensor noise, the mount within 1 mm and 0.1 deg,
// for three mounts (straight down; higher, off-centre, tilted 5 deg and turned 3 deg; lower,
// off to the right, tilted 8 deg sideways). The frames are rendered with the true mount; the
// calibration only knows the intrinsics and the tags' poses.
TEST(MountCalibration, RecoversTheMountFromRenderedTagsWithinAMillimetreAndATenthDegree) {
  MountPose pitched = testing::straight_down_mount(0.25, -0.03, 0.13);
  pitched.rpy_rad.y() = deg_to_rad(8.0);
  for (const MountPose& truth :
       {testing::straight_down_mount(), testing::tilted_offset_mount(), pitched}) {
    const CameraModel camera(testing::default_intrinsics(), truth);
    const FloorTagsFile tags = tags_around(truth);
    const pipeline::FrameRenderer renderer(camera, scene_with(tags));
    std::vector<cv::Mat> frames;
    for (int f = 0; f < 3; ++f) frames.push_back(renderer.render({0, 0, 0}, {}, f));
    const MountCalibration m =
        calibrate_mount(testing::default_intrinsics(), frames, {"f0", "f1", "f2"}, tags);
    EXPECT_EQ(m.tags_seen, 4) << truth.describe();
    const Eigen::Vector3d dxyz = m.mount.xyz_m - truth.xyz_m;
    const Eigen::Matrix3d dr = m.mount.rotation().transpose() * truth.rotation();
    const double angle_deg = rad_to_deg(std::acos(std::clamp((dr.trace() - 1.0) / 2.0, -1.0, 1.0)));
    std::printf(
        "%s: error %.3f mm (%.3f, %.3f, %.3f), %.4f deg; RMS %.3f px; sigma %.3f mm "
        "%.4f deg\n",
        truth.describe().c_str(), 1e3 * dxyz.norm(), 1e3 * dxyz.x(), 1e3 * dxyz.y(), 1e3 * dxyz.z(),
        angle_deg, m.rms_px, 1e3 * m.sigma.head<3>().norm(), rad_to_deg(m.sigma.tail<3>().norm()));
    EXPECT_LT(std::abs(dxyz.x()), 0.001) << truth.describe();
    EXPECT_LT(std::abs(dxyz.y()), 0.001) << truth.describe();
    EXPECT_LT(std::abs(dxyz.z()), 0.001) << truth.describe();
    EXPECT_LT(angle_deg, 0.1) << truth.describe();
  }
}

TEST(MountCalibration, RefusesWhenNoKnownTagIsSeen) {
  const MountPose truth = testing::straight_down_mount();
  const CameraModel camera(testing::default_intrinsics(), truth);
  const pipeline::FrameRenderer renderer(camera, scene_with(tags_around(truth)));
  FloorTagsFile other;
  other.tags.push_back({99, 0.04, 0.3, 0.0, 0.0});
  EXPECT_THROW(calibrate_mount(testing::default_intrinsics(), {renderer.render({0, 0, 0}, {}, 0)},
                               {"f0"}, other),
               InputError);
}

// Four tags on the floor (issue 18's case: one of four wrong, three left to fit); TAGS.yaml
// places one 20 mm off, and (second case) says another lies at a yaw 90 deg from the one it has.
// The warning names the tag and how far or how it is turned, and the mount, refitted without
// it, is still within issue 5's 1 mm and 0.1 deg.
TEST(MountCalibration, ATagWhosePoseDisagreesIsNamedAndLeftOut) {
  const MountPose truth = testing::straight_down_mount();
  const FloorTagsFile placed = tags_around(truth);
  const CameraModel camera(testing::default_intrinsics(), truth);
  const pipeline::FrameRenderer renderer(camera, scene_with(placed));
  const std::vector<cv::Mat> frames = {renderer.render({0, 0, 0}, {}, 0),
                                       renderer.render({0, 0, 0}, {}, 1)};
  struct Case {
    int tag;
    double dx_m, dyaw_rad;
    const char* expected;
  };
  for (const Case& wrong :
       {Case{11, 0.02, 0.0, "mm on the floor"}, Case{12, 0.0, M_PI / 2, "turned by 270 deg"}}) {
    FloorTagsFile told = placed;
    for (FloorTagPose& t : told.tags) {
      if (t.id != wrong.tag) continue;
      t.x_m += wrong.dx_m;
      t.yaw_rad += wrong.dyaw_rad;
    }
    const MountCalibration m =
        calibrate_mount(testing::default_intrinsics(), frames, {"f0", "f1"}, told);
    ASSERT_FALSE(m.warnings.empty()) << wrong.tag;
    const std::string& warning = m.warnings.front();
    std::printf("%s\n", warning.c_str());
    EXPECT_NE(warning.find("tag " + std::to_string(wrong.tag) + " "), std::string::npos) << warning;
    EXPECT_NE(warning.find(wrong.expected), std::string::npos) << warning;
    bool excluded = false;
    for (const TagResidual& r : m.tags) excluded = excluded || (r.id == wrong.tag && r.excluded);
    EXPECT_TRUE(excluded) << wrong.tag;
    const Eigen::Vector3d dxyz = m.mount.xyz_m - truth.xyz_m;
    const Eigen::Matrix3d dr = m.mount.rotation().transpose() * truth.rotation();
    EXPECT_LT(dxyz.cwiseAbs().maxCoeff(), 0.001) << wrong.tag;
    EXPECT_LT(rad_to_deg(std::acos(std::clamp((dr.trace() - 1.0) / 2.0, -1.0, 1.0))), 0.1);
  }
}

}  // namespace
}  // namespace agv::perception
