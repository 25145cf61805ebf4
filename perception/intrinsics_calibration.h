#pragma once

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "perception/camera_model.h"

namespace agv::perception {

// A planar calibration board:
//   chessboard: inner corners per row (cols) and per column (rows), square size;
//   charuco:    a ChArUco board of cols x rows squares, square_m across, ArUco markers marker_m
//               across from `dictionary` (OpenCV's aruco module); any 6 or more corners make a
//               view;
//   apriltag:   a grid of cols x rows tags of the family, ids 0, 1, ... row by row from the top
//               left, each tag_m across (AprilTag's size), centres pitch_x_m apart along a row
//               and pitch_y_m down a column. Any 4 or more tags of the grid in view make a view.
struct BoardSpec {
  enum class Kind { kChessboard, kCharuco, kAprilTagGrid };
  Kind kind = Kind::kChessboard;
  int cols = 9;
  int rows = 6;
  double square_m = 0.025;  // chessboard, charuco
  double marker_m = 0.0;    // charuco
  std::string dictionary = "DICT_4X4_50";
  double tag_m = 0.0, pitch_x_m = 0.0, pitch_y_m = 0.0;  // AprilTag grid
  std::string family = "tag36h11";
  std::string text;  // as given, for messages
};

// "chessboard:COLSxROWS:SQUARE_M" (e.g. chessboard:9x6:0.025),
// "charuco:COLSxROWS:SQUARE_M:MARKER_M[:DICTIONARY]" (squares; e.g.
// charuco:5x7:0.04:0.02:DICT_4X4_50) or "apriltag:COLSxROWS:TAG_M:PITCH_M[:PITCH_Y_M]"
// (tag36h11; one pitch: the same both ways). Throws InputError naming --board.
BoardSpec parse_board(const std::string& text);

// The lens models calibrate_intrinsics fits (OpenCV's): k1 k2 p1 p2 k3 (pinhole), k1..k6 p1 p2
// (rational), or the equidistant fisheye k1..k4 (cv::fisheye).
enum class LensModel { kPinhole, kRational, kFisheye };
LensModel parse_lens_model(const std::string& text);  // throws InputError naming --model

struct CalibrationView {
  std::string name;
  bool board_found = false;
  bool used = false;    // found and kept (not rejected as an outlier)
  double rms_px = 0.0;  // reprojection RMS of its corners with the final calibration
  double worst_corner_px = 0.0;
  std::string detector;  // which detector found the corners
  cv::Size board_seen;   // a chessboard larger than --board seen here (0: none)
  std::vector<cv::Point2f> corners_px;
  std::vector<cv::Point3f> board_points;  // the corners' places on the board
};

struct IntrinsicsCalibration {
  bool fitted = false;  // false: no model fits; `failure` says why (the views are still filled)
  std::string failure;
  CameraIntrinsics intrinsics;
  std::string model;    // the model written, in words (which coefficients were fitted)
  double rms_px = 0.0;  // over the corners of the used views
  std::vector<CalibrationView> views;
  int used_views = 0;
  double coverage = 0.0;              // fraction of a 5x5 grid over the image with a corner in it
  std::vector<std::string> notes;     // what was done that a user should know (a refit)
  std::vector<std::string> warnings;  // what a user should act on
};

// Finds the board in each image (chessboards: findChessboardCornersSB in accuracy mode, the
// classic detector with a sub-pixel window sized from the squares as a fallback), calibrates
// with OpenCV (the model asked for), rejects views whose RMS is above max(1 px, 3x the median)
// and calibrates again without them. When the fitted distortion folds the image (the
// projection stops moving outwards before an image corner: typical where the board never
// reached the corners) it refits with fewer coefficients (k3 fixed, then k2 and k3), and says
// so in `notes`. Warns when fewer than 8 views are used, when the corners cover less than half
// the image, when no view is tilted, when fx/fy is far from 1, when the RMS is above 1 px, and
// when leaving one view out moves the focal length by more than 1 %. Throws InputError when
// images differ in size, when fewer than 3 views show the board (naming what was searched and,
// for a chessboard, the size of the board the images do show), or when the images show a
// chessboard larger than the one given. `progress` (optional) is told the fraction of the images
// searched after each one (the search is most of the time).
IntrinsicsCalibration calibrate_intrinsics(const std::vector<std::string>& names,
                                           const std::vector<cv::Mat>& images,
                                           const BoardSpec& board,
                                           LensModel model = LensModel::kPinhole,
                                           const std::function<void(double)>& progress = nullptr);

// Where the used views' corners fell: the image area with each view's corners in its own
// colour and the 5x5 coverage grid (cells without corners shaded).
cv::Mat coverage_picture(const IntrinsicsCalibration& calibration);

}  // namespace agv::perception
