#include "perception/camera_file.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/input_error.h"

namespace agv::perception {
namespace {

namespace fs = std::filesystem;

// A file in the layout OpenCV's calibration sample (samples/cpp/tutorial_code/calib3d/
// camera_calibration) writes: %YAML:1.0 header, opencv-matrix nodes, its bookkeeping keys.
const char* kOpenCvSampleFile = R"(%YAML:1.0
---
calibration_time: "Mon 23 Nov 2026 10:12:41 CET"
nr_of_frames: 13
image_width: 640
image_height: 480
board_width: 9
board_height: 6
square_size: 25.
fix_aspect_ratio: 1.
# flags:  +fix_aspectRatio +fix_principal_point +zero_tangent_dist
flags: 14
fisheye_model: 0
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 5.3646318593402209e+02, 0., 3.1950000000000000e+02, 0.,
       5.3646318593402209e+02, 2.3950000000000000e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -2.7990589454612962e-01, 1.3187516658592591e-01, 0., 0.,
       -2.9466040815099436e-02 ]
avg_reprojection_error: 4.0854025470612519e-01
per_view_reprojection_errors: !!opencv-matrix
   rows: 2
   cols: 1
   dt: f
   data: [ 3.91563356e-01, 4.52087820e-01 ]
extrinsic_parameters: !!opencv-matrix
   rows: 2
   cols: 6
   dt: d
   data: [ -2.5e-01, 3.1e-01, 1.5, -6.2e+01, -1.1e+02, 3.9e+02, 1.2e-01,
       -2.1e-01, 1.4, -5.1e+01, -9.5e+01, 4.1e+02 ]
)";

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("agv_camera_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  // The InputError message for loading `text`, or "" when it loads.
  std::string error_for(const std::string& text) {
    try {
      load_camera_file(write("bad.yaml", text));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(TempDir, FileFromOpenCvCalibrationSampleLoadsAsIntrinsics) {
  const std::string path = write("opencv_sample.yml", kOpenCvSampleFile);
  const CameraFile camera = load_camera_file(path);
  EXPECT_EQ(camera.intrinsics.width_px, 640);
  EXPECT_EQ(camera.intrinsics.height_px, 480);
  EXPECT_NEAR(camera.intrinsics.camera_matrix(0, 0), 536.46318593402209, 1e-9);
  EXPECT_NEAR(camera.intrinsics.camera_matrix(1, 2), 239.5, 1e-12);
  ASSERT_EQ(camera.intrinsics.distortion.size(), 5u);
  EXPECT_NEAR(camera.intrinsics.distortion[0], -0.27990589454612962, 1e-15);
  EXPECT_NEAR(camera.intrinsics_calibration.avg_reprojection_error_px, 0.40854, 1e-5);
  EXPECT_EQ(camera.intrinsics_calibration.views, 13);
  EXPECT_FALSE(camera.mount.has_value());
  try {
    camera_model_of(camera, path);
    FAIL() << "a file without a mount must not make a camera model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mount_xyz_m"), std::string::npos);
  }
}

TEST_F(TempDir, ShippedDefaultCameraLoads) {
  const CameraFile camera =
      load_camera_file(std::string(AGV_SOURCE_DIR) + "/pipeline/config/default_camera.yaml");
  ASSERT_TRUE(camera.mount.has_value());
  EXPECT_NEAR(camera.mount->xyz_m.x(), 0.30, 1e-12);
  EXPECT_NEAR(camera.mount->xyz_m.z(), 0.15, 1e-12);
  EXPECT_NEAR(camera.intrinsics.camera_matrix(0, 0), 384.0, 1e-12);
}

TEST_F(TempDir, SaveThenLoadGivesTheSameNumbers) {
  CameraFile camera;
  camera.intrinsics.camera_matrix = cv::Matx33d(500.25, 0, 321.5, 0, 501.75, 242.25, 0, 0, 1);
  camera.intrinsics.distortion = {-0.1, 0.03, 0.001, -0.002, 0.004};
  MountPose mount;
  mount.xyz_m = {0.31, -0.012, 0.162};
  mount.rpy_rad = {3.1, 0.02, -1.55};
  camera.mount = mount;
  camera.mount_calibration.avg_reprojection_error_px = 0.21;
  camera.mount_calibration.views = 4;
  const std::string path = (dir_ / "saved.yaml").string();
  save_camera_file(path, camera);
  const CameraFile back = load_camera_file(path);
  for (int i = 0; i < 9; ++i)
    EXPECT_DOUBLE_EQ(back.intrinsics.camera_matrix.val[i], camera.intrinsics.camera_matrix.val[i]);
  EXPECT_EQ(back.intrinsics.distortion, camera.intrinsics.distortion);
  ASSERT_TRUE(back.mount);
  EXPECT_TRUE(back.mount->xyz_m.isApprox(mount.xyz_m, 1e-15));
  EXPECT_TRUE(back.mount->rpy_rad.isApprox(mount.rpy_rad, 1e-15));
  EXPECT_EQ(back.mount_calibration.views, 4);
}

// DESIGN.md: the mount keys may be a 1x3 opencv-matrix or a plain YAML sequence.
TEST_F(TempDir, MountAsMatrixOrSequence) {
  const std::string base = std::string(kOpenCvSampleFile);
  const CameraFile a =
      load_camera_file(write("a.yaml", base + "mount_xyz_m: [ 0.3, 0.0, 0.15 ]\n"
                                              "mount_rpy_rad: [ 3.14159, 0.0, -1.5708 ]\n"));
  const CameraFile b = load_camera_file(
      write("b.yaml", base + "mount_xyz_m: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   "
                             "data: [ 0.3, 0.0, 0.15 ]\n"
                             "mount_rpy_rad: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   "
                             "data: [ 3.14159, 0., -1.5708 ]\n"));
  ASSERT_TRUE(a.mount && b.mount);
  EXPECT_TRUE(a.mount->xyz_m.isApprox(b.mount->xyz_m));
  EXPECT_TRUE(a.mount->rpy_rad.isApprox(b.mount->rpy_rad));
}

TEST_F(TempDir, BadFilesNameTheFileAndTheField) {
  const std::string good = kOpenCvSampleFile;
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  struct Case {
    std::string text;
    std::string field;
  };
  const Case cases[] = {
      {"", "empty"},
      {"this: is: not: yaml: [", "not a readable"},
      {replaced("image_width: 640", "image_width: -640"), "image_width"},
      {replaced("image_width: 640", "image_width: wide"), "image_width"},
      {replaced("5.3646318593402209e+02, 0., 3.1950000000000000e+02",
                "0., 0., 3.1950000000000000e+02"),
       "camera_matrix"},
      {replaced("5.3646318593402209e+02, 0., 3.1950000000000000e+02",
                ".nan, 0., 3.1950000000000000e+02"),
       "camera_matrix"},
      {replaced("-2.7990589454612962e-01, 1.3187516658592591e-01", "-3.0, 1.3187516658592591e-01"),
       "distortion_coefficients"},
      {replaced("board_width: 9", "bord_width: 9"), "bord_width"},
      {good + "mount_xyz_m: [ 0.3, 0.0 ]\nmount_rpy_rad: [ 3.14159, 0.0, -1.5708 ]\n",
       "mount_xyz_m"},
      {good + "mount_xyz_m: [ 0.3, 0.0, 0.15 ]\n", "mount_rpy_rad"},
      // Found by fuzzing: a huge declared shape made OpenCV allocate it before reading data.
      {replaced("rows: 3", "rows: 2000000000"), "camera_matrix"},
      {good + "mount_xyz_m: [ 0.3, 0.0, 0.15 ]\nmount_rpy_rad: [ 0.0, 0.0, 0.0 ]\n",
       "mount_rpy_rad"},  // looks up
      {good + "mount_xyz_m: [ 0.3, 0.0, -0.15 ]\nmount_rpy_rad: [ 3.14159, 0.0, -1.5708 ]\n",
       "mount_xyz_m"},
  };
  for (const Case& c : cases) {
    const std::string message = error_for(c.text);
    EXPECT_NE(message.find("bad.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find(c.field), std::string::npos)
        << "expected '" << c.field << "' in: " << message;
  }
  try {
    load_camera_file((dir_ / "missing.yaml").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace agv::perception
