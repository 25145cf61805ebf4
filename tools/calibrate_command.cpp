#include "tools/calibrate_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/input_error.h"
#include "perception/camera_file.h"
#include "perception/intrinsics_calibration.h"
#include "perception/mount_calibration.h"
#include "pipeline/config/floor_tags_file.h"
#include "pipeline/dataset.h"
#include "tools/progress_bar.h"

namespace agv::tools {
namespace fs = std::filesystem;

void add_calibrate_command(CLI::App& app, CalibrateArgs& args) {
  CLI::App* calibrate =
      app.add_subcommand("calibrate",
                         "Camera calibration: intrinsics from chessboard images, or the mount "
                         "(camera offset) from AprilTags on the floor; see `agv calibrate "
                         "intrinsics --help`, `agv calibrate mount --help`");
  calibrate->require_subcommand(1);
  CLI::App* sub = calibrate->add_subcommand(
      "intrinsics",
      "Intrinsics from images of a chessboard (findChessboardCornersSB, the classic detector as "
      "a fallback), a ChArUco board or an AprilTag grid: OpenCV's calibration with the lens "
      "model asked for, outlier views rejected; a fit whose distortion folds the image is "
      "refitted with fewer coefficients (k3, then k2 held at 0), and says so. Writes the camera "
      "YAML (OpenCV sample layout, no mount) and <out>_coverage.png (where the corners fell); "
      "prints each view's detector and RMS, the RMS over all, and warnings a user can act on "
      "(views, coverage, tilt, fx/fy, a view the result leans on). When no model fits it prints "
      "the table and what to do, writes nothing and exits 2.");
  sub->add_option("--images", args.images_dir, "Folder of images (PNG, JPEG, BMP, TIFF)")
      ->required();
  sub->add_option("--board", args.board,
                  "chessboard:COLSxROWS:SQUARE_M (inner corners; default chessboard:9x6:0.025) or "
                  "charuco:COLSxROWS:SQUARE_M:MARKER_M[:DICTIONARY] (squares; dictionary default "
                  "DICT_4X4_50) or "
                  "apriltag:COLSxROWS:TAG_M:PITCH_M[:PITCH_Y_M] (a grid of tag36h11 tags, ids 0.. "
                  "row by row from the top left, TAG_M across, centres PITCH_M apart along a row "
                  "and PITCH_Y_M down a column)")
      ->capture_default_str();
  sub->add_option("--model", args.model,
                  "Lens model: pinhole (k1 k2 p1 p2 k3), rational (k1..k6 p1 p2) or fisheye "
                  "(OpenCV's equidistant k1..k4)")
      ->capture_default_str();
  sub->add_option("--out", args.out,
                  "Camera YAML to write (default camera_<date>-<time>.yaml); an existing file is "
                  "replaced only with --force");
  sub->add_flag("--force", args.force, "Replace an existing output file");
  sub->add_flag("--json", args.json, "Print the result as JSON");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
  sub->callback([&args] { args.command = "intrinsics"; });

  CLI::App* mount = calibrate->add_subcommand(
      "mount",
      "The camera's mount on the vehicle (the camera offset) from AprilTags lying on the floor "
      "at known poses in the vehicle frame: one joint PnP over every corner of every frame. "
      "Prints the mount (xyz, rpy and in words), its reprojection RMS and standard deviations; "
      "writes the camera YAML with the mount.");
  mount->add_option("--frames", args.frames, "Folder of images, or a dataset folder (frames/)")
      ->required();
  mount
      ->add_option("--tags", args.tags_file,
                   "TAGS.yaml: family (default tag36h11) and tags: [{id, size_m, x_m, y_m, "
                   "yaw_rad}] in the vehicle frame")
      ->required();
  mount->add_option("--camera", args.camera_file, "Camera YAML with the intrinsics")->required();
  mount->add_option("--out", args.out,
                    "Camera YAML to write (default camera_<date>-<time>.yaml); an existing file "
                    "is replaced only with --force");
  mount->add_flag("--force", args.force, "Replace an existing output file");
  mount->add_flag("--json", args.json, "Print the result as JSON");
  mount->add_flag("--quiet", args.quiet, "No progress bar");
  mount->callback([&args] { args.command = "mount"; });
}

namespace {

// The images of a folder in name order, grey; throws InputError naming the file.
void read_images(const std::string& folder, std::vector<std::string>* names,
                 std::vector<cv::Mat>* images) {
  if (!fs::is_directory(folder)) throw InputError(folder + ": not a folder of images");
  const std::vector<fs::path> files = pipeline::image_files_in(folder);
  if (files.empty()) throw InputError(folder + ": no images (PNG, JPEG, BMP, TIFF) in it");
  for (const fs::path& file : files) {
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw InputError(file.string() + ": cannot be read or decoded");
    names->push_back(file.filename().string());
    images->push_back(image);
  }
}

// The output file: the one given (refused when it exists, unless --force), else
// camera_<date>-<time>.yaml in the working directory.
std::string output_path(const CalibrateArgs& args) {
  if (args.out.empty()) {
    const std::time_t now = std::time(nullptr);
    char name[64];
    std::strftime(name, sizeof(name), "camera_%Y%m%d-%H%M%S.yaml", std::localtime(&now));
    return name;
  }
  if (fs::exists(args.out) && !args.force)
    throw InputError(args.out + ": exists; pass --force to replace it, or another --out");
  return args.out;
}

std::string now_text() {
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  return date;
}

int run_mount(const CalibrateArgs& args) {
  const std::string out = output_path(args);
  perception::CameraFile camera = perception::load_camera_file(args.camera_file);
  const perception::FloorTagsFile tags = pipeline::load_floor_tags_file(args.tags_file);
  const std::string folder =
      fs::is_directory(fs::path(args.frames) / "frames") ? args.frames + "/frames" : args.frames;
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  read_images(folder, &names, &images);
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].cols != camera.intrinsics.width_px ||
        images[i].rows != camera.intrinsics.height_px)
      throw InputError(names[i] + ": image size differs from " + args.camera_file);
  }
  ProgressBar bar("finding tags in " + std::to_string(images.size()) + " frames",
                  !args.quiet && !args.json);
  const perception::MountCalibration m = perception::calibrate_mount(
      camera.intrinsics, images, names, tags, [&bar](double f) { bar.update(f); });
  bar.finish();
  const std::optional<perception::MountPose> before = camera.mount;
  camera.mount = m.mount;
  camera.mount_calibration.avg_reprojection_error_px = m.rms_px;
  camera.mount_calibration.views = m.frames_used;
  camera.mount_calibration.method =
      "agv calibrate mount, " + std::to_string(m.tags_seen) + " " + tags.family + " tags";
  camera.mount_calibration.date = now_text();
  if (fs::path(out).has_parent_path()) fs::create_directories(fs::path(out).parent_path());
  perception::save_camera_file(out, camera);
  const double deg = 180.0 / M_PI;
  if (args.json) {
    nlohmann::json j;
    j["mount_xyz_m"] = {m.mount.xyz_m.x(), m.mount.xyz_m.y(), m.mount.xyz_m.z()};
    j["mount_rpy_rad"] = {m.mount.rpy_rad.x(), m.mount.rpy_rad.y(), m.mount.rpy_rad.z()};
    j["sigma_xyz_m"] = {m.sigma[0], m.sigma[1], m.sigma[2]};
    j["sigma_rpy_rad"] = {m.sigma[3], m.sigma[4], m.sigma[5]};
    j["rms_px"] = m.rms_px;
    j["frames"] = images.size();
    j["frames_used"] = m.frames_used;
    j["tags_seen"] = m.tags_seen;
    j["points"] = m.points;
    j["description"] = m.mount.describe();
    for (const perception::TagResidual& t : m.tags)
      j["per_tag"].push_back({{"id", t.id}, {"rms_px", t.rms_px}, {"excluded", t.excluded}});
    j["warnings"] = m.warnings;
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("mount_xyz_m  [%.4f, %.4f, %.4f] m  +- [%.2f, %.2f, %.2f] mm\n", m.mount.xyz_m.x(),
                m.mount.xyz_m.y(), m.mount.xyz_m.z(), 1e3 * m.sigma[0], 1e3 * m.sigma[1],
                1e3 * m.sigma[2]);
    std::printf("mount_rpy_rad [%.5f, %.5f, %.5f] +- [%.3f, %.3f, %.3f] deg\n", m.mount.rpy_rad.x(),
                m.mount.rpy_rad.y(), m.mount.rpy_rad.z(), m.sigma[3] * deg, m.sigma[4] * deg,
                m.sigma[5] * deg);
    std::printf("camera %s\n", m.mount.describe().c_str());
    for (const perception::TagResidual& t : m.tags) {
      if (t.excluded) {
        std::printf("tag %d: left out (disagrees with the others)\n", t.id);
      } else {
        std::printf("tag %d: RMS %.3f px\n", t.id, t.rms_px);
      }
    }
    if (before) {
      const Eigen::Vector3d d = m.mount.xyz_m - before->xyz_m;
      std::printf("change from %s: %.1f mm (%.1f, %.1f, %.1f)\n", args.camera_file.c_str(),
                  1e3 * d.norm(), 1e3 * d.x(), 1e3 * d.y(), 1e3 * d.z());
    }
    std::printf("RMS reprojection %.3f px | %d of %zu frames, %d tags, %d corners | output: %s\n",
                m.rms_px, m.frames_used, images.size(), m.tags_seen, m.points, out.c_str());
  }
  for (const std::string& warning : m.warnings)
    std::cerr << "agv calibrate mount: warning: " << warning << '\n';
  return 0;
}

}  // namespace

namespace {

void print_views(const perception::IntrinsicsCalibration& result) {
  std::printf("%-32s %-9s %8s %10s\n", "image", "detector", "rms_px", "worst_px");
  for (const perception::CalibrationView& v : result.views) {
    const std::string detector =
        v.board_found ? v.detector : (v.board_seen.empty() ? "-" : "larger");
    std::printf("%-32s %-9s %8s %10s\n", v.name.c_str(), detector.c_str(),
                v.used ? cv::format("%.3f", v.rms_px).c_str() : (v.board_found ? "rejected" : "-"),
                v.used ? cv::format("%.2f", v.worst_corner_px).c_str() : "");
  }
}

}  // namespace

int run_calibrate(const CalibrateArgs& args) {
  if (args.command == "mount") return run_mount(args);
  const perception::BoardSpec board = perception::parse_board(args.board);
  const perception::LensModel model = perception::parse_lens_model(args.model);
  const std::string out = output_path(args);
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  read_images(args.images_dir, &names, &images);
  ProgressBar bar("finding the board in " + std::to_string(images.size()) + " images",
                  !args.quiet && !args.json);
  const perception::IntrinsicsCalibration result = perception::calibrate_intrinsics(
      names, images, board, model, [&bar](double f) { bar.update(f); });
  bar.finish();
  if (!result.fitted) {
    if (!args.json) {
      print_views(result);
      for (const std::string& note : result.notes) std::printf("tried %s\n", note.c_str());
    }
    throw InputError(args.images_dir + ": " + result.failure);
  }

  perception::CameraFile camera;
  camera.intrinsics = result.intrinsics;
  camera.intrinsics_calibration.avg_reprojection_error_px = result.rms_px;
  camera.intrinsics_calibration.views = result.used_views;
  camera.intrinsics_calibration.method =
      "agv calibrate intrinsics, " + args.board + ", " + result.model;
  camera.intrinsics_calibration.date = now_text();
  perception::validate_intrinsics(camera.intrinsics, "calibration result");
  if (fs::path(out).has_parent_path()) fs::create_directories(fs::path(out).parent_path());
  perception::save_camera_file(out, camera);
  const fs::path coverage =
      fs::path(out).parent_path() / (fs::path(out).stem().string() + "_coverage.png");
  cv::imwrite(coverage.string(), perception::coverage_picture(result));

  const cv::Matx33d& k = result.intrinsics.camera_matrix;
  if (args.json) {
    nlohmann::json j;
    j["rms_px"] = result.rms_px;
    j["views"] = images.size();
    j["views_used"] = result.used_views;
    j["coverage"] = result.coverage;
    j["model"] = result.model;
    j["fisheye"] = result.intrinsics.fisheye;
    j["fx_px"] = k(0, 0);
    j["fy_px"] = k(1, 1);
    j["cx_px"] = k(0, 2);
    j["cy_px"] = k(1, 2);
    j["distortion"] = result.intrinsics.distortion;
    j["notes"] = result.notes;
    j["warnings"] = result.warnings;
    j["output"] = out;
    for (const perception::CalibrationView& v : result.views)
      j["per_view"].push_back({{"image", v.name},
                               {"board_found", v.board_found},
                               {"detector", v.detector},
                               {"used", v.used},
                               {"rms_px", v.rms_px},
                               {"worst_corner_px", v.worst_corner_px}});
    std::cout << j.dump(2) << '\n';
  } else {
    print_views(result);
    for (const std::string& note : result.notes) std::printf("note: %s\n", note.c_str());
    std::printf(
        "RMS reprojection error %.3f px over %d of %zu views | %s | fx %.2f fy %.2f cx %.2f cy "
        "%.2f px | coverage %.0f %%\n",
        result.rms_px, result.used_views, images.size(), result.model.c_str(), k(0, 0), k(1, 1),
        k(0, 2), k(1, 2), 100.0 * result.coverage);
    std::printf("output: %s, %s\n", out.c_str(), coverage.string().c_str());
  }
  for (const std::string& warning : result.warnings)
    std::cerr << "agv calibrate intrinsics: warning: " << warning << '\n';
  return 0;
}

}  // namespace agv::tools
