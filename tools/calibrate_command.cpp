#include "tools/calibrate_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/input_error.h"
#include "perception/camera_file.h"
#include "perception/intrinsics_calibration.h"

namespace agv::tools {
namespace fs = std::filesystem;

void add_calibrate_command(CLI::App& app, CalibrateArgs& args) {
  CLI::App* calibrate =
      app.add_subcommand("calibrate", "Camera calibration: `agv calibrate intrinsics --help`");
  calibrate->require_subcommand(1);
  CLI::App* sub = calibrate->add_subcommand(
      "intrinsics",
      "Intrinsics from images of a chessboard: sub-pixel corners, OpenCV calibrateCamera "
      "(k1 k2 p1 p2 k3), outlier views rejected. Writes the camera YAML (OpenCV sample layout, "
      "no mount) and <out>_coverage.png (where the corners fell); prints the RMS reprojection "
      "error and each view's, and warns when views or coverage are too few to trust.");
  sub->add_option("--images", args.images_dir, "Folder of PNG/JPEG images")->required();
  sub->add_option("--board", args.board,
                  "Board: chessboard:COLSxROWS:SQUARE_M (inner corners), default 9x6, 25 mm");
  sub->add_option("--out", args.out, "Camera YAML to write (default camera.yaml)");
  sub->add_flag("--json", args.json, "Print the result as JSON");
}

int run_calibrate(const CalibrateArgs& args) {
  const perception::ChessboardSpec board = perception::parse_board(args.board);
  if (!fs::is_directory(args.images_dir))
    throw InputError(args.images_dir + ": not a folder of images");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(args.images_dir)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(args.images_dir + ": no .png or .jpg images in it");
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  for (const fs::path& file : files) {
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw InputError(file.string() + ": cannot be read or decoded");
    names.push_back(file.filename().string());
    images.push_back(image);
  }
  const perception::IntrinsicsCalibration result =
      perception::calibrate_intrinsics(names, images, board);

  perception::CameraFile camera;
  camera.intrinsics = result.intrinsics;
  camera.intrinsics_calibration.avg_reprojection_error_px = result.rms_px;
  camera.intrinsics_calibration.views = result.used_views;
  camera.intrinsics_calibration.method = "agv calibrate intrinsics, " + args.board;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  camera.intrinsics_calibration.date = date;
  perception::validate_intrinsics(camera.intrinsics, "calibration result");
  if (fs::path(args.out).has_parent_path()) fs::create_directories(fs::path(args.out).parent_path());
  perception::save_camera_file(args.out, camera);
  const fs::path coverage =
      fs::path(args.out).parent_path() / (fs::path(args.out).stem().string() + "_coverage.png");
  cv::imwrite(coverage.string(), perception::coverage_picture(result));

  const cv::Matx33d& k = result.intrinsics.camera_matrix;
  if (args.json) {
    nlohmann::json j;
    j["rms_px"] = result.rms_px;
    j["views"] = images.size();
    j["views_used"] = result.used_views;
    j["coverage"] = result.coverage;
    j["fx_px"] = k(0, 0);
    j["fy_px"] = k(1, 1);
    j["cx_px"] = k(0, 2);
    j["cy_px"] = k(1, 2);
    j["distortion"] = result.intrinsics.distortion;
    j["warnings"] = result.warnings;
    for (const perception::CalibrationView& v : result.views)
      j["per_view"].push_back({{"image", v.name},
                               {"board_found", v.board_found},
                               {"used", v.used},
                               {"rms_px", v.rms_px}});
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("%-32s %8s %10s\n", "image", "board", "rms_px");
    for (const perception::CalibrationView& v : result.views) {
      std::printf(
          "%-32s %8s %10s\n", v.name.c_str(), v.board_found ? "found" : "-",
          v.used ? cv::format("%.3f", v.rms_px).c_str() : (v.board_found ? "rejected" : "-"));
    }
    std::printf(
        "RMS reprojection error %.3f px over %d of %zu views | fx %.2f fy %.2f cx %.2f cy %.2f px "
        "| coverage %.0f %%\n",
        result.rms_px, result.used_views, images.size(), k(0, 0), k(1, 1), k(0, 2), k(1, 2),
        100.0 * result.coverage);
    std::printf("output: %s, %s\n", args.out.c_str(), coverage.string().c_str());
  }
  for (const std::string& warning : result.warnings)
    std::cerr << "agv calibrate intrinsics: warning: " << warning << '\n';
  return 0;
}

}  // namespace agv::tools
