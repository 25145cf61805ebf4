#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "perception/camera_model.h"

namespace agv::perception {

// A planar calibration board:
//   chessboard: inner corners per row (cols) and per column (rows), square size;
//   apriltag:   a grid of cols x rows tags of the family, ids 0, 1, ... row by row from the top
//               left, each tag_m across (AprilTag's size), centres pitch_m apart. Any 4 or more
//               tags of the grid in view make a view.
struct BoardSpec {
  enum class Kind { kChessboard, kAprilTagGrid };
  Kind kind = Kind::kChessboard;
  int cols = 9;
  int rows = 6;
  double square_m = 0.025;            // chessboard
  double tag_m = 0.0, pitch_m = 0.0;  // AprilTag grid
  std::string family = "tag36h11";
  std::string text;  // as given, for messages
};

// "chessboard:COLSxROWS:SQUARE_M" (e.g. chessboard:9x6:0.025) or
// "apriltag:COLSxROWS:TAG_M:PITCH_M" (tag36h11). Throws InputError naming --board.
BoardSpec parse_board(const std::string& text);

struct CalibrationView {
  std::string name;
  bool board_found = false;
  bool used = false;    // found and kept (not rejected as an outlier)
  double rms_px = 0.0;  // reprojection RMS of its corners with the final calibration
  std::vector<cv::Point2f> corners_px;
  std::vector<cv::Point3f> board_points;  // the corners' places on the board
};

struct IntrinsicsCalibration {
  CameraIntrinsics intrinsics;
  double rms_px = 0.0;  // over the corners of the used views
  std::vector<CalibrationView> views;
  int used_views = 0;
  double coverage = 0.0;  // fraction of a 5x5 grid over the image with a corner in it
  std::vector<std::string> warnings;
};

// Finds the board in each image (sub-pixel corners), calibrates with OpenCV's calibrateCamera
// (k1 k2 p1 p2 k3), rejects views whose RMS is above max(1 px, 3x the median) and calibrates
// again without them. Warns when fewer than 8 views are used, when the corners cover less than
// half the image, or when every view sees the board nearly face on (focal length poorly
// determined). Throws InputError when images differ in size, or when fewer than 3 views show
// the board (naming what was searched).
IntrinsicsCalibration calibrate_intrinsics(const std::vector<std::string>& names,
                                           const std::vector<cv::Mat>& images,
                                           const BoardSpec& board);

// Where the used views' corners fell: the image area with each view's corners in its own
// colour and the 5x5 coverage grid (cells without corners shaded).
cv::Mat coverage_picture(const IntrinsicsCalibration& calibration);

}  // namespace agv::perception
