#include "perception/intrinsics_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/input_error.h"
#include "perception/apriltag_detector.h"
#include "perception/camera_file.h"

namespace agv::perception {
namespace {

constexpr int kGrid = 5;

std::vector<cv::Point3f> chessboard_points(const BoardSpec& board) {
  std::vector<cv::Point3f> points;
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c)
      points.emplace_back(static_cast<float>(c * board.square_m),
                          static_cast<float>(r * board.square_m), 0.0f);
  }
  return points;
}

// Which cells of a kGrid x kGrid grid over the image hold a corner of a used view (row-major).
std::vector<bool> covered_cells(const IntrinsicsCalibration& calibration) {
  const int w = calibration.intrinsics.width_px, h = calibration.intrinsics.height_px;
  std::vector<bool> covered(kGrid * kGrid, false);
  for (const CalibrationView& v : calibration.views) {
    if (!v.used) continue;
    for (const cv::Point2f& p : v.corners_px) {
      const int gx = std::clamp(static_cast<int>(p.x * kGrid / w), 0, kGrid - 1);
      const int gy = std::clamp(static_cast<int>(p.y * kGrid / h), 0, kGrid - 1);
      covered[gy * kGrid + gx] = true;
    }
  }
  return covered;
}

// The corners of the grid's tags found in the image, with their places on the board (x right, y
// down as printed; a tag's ideal corners (-1, 1), (1, 1), (1, -1), (-1, -1) in detector order).
void add_grid_tags(const AprilTagDetector& detector, const cv::Mat& grey, const BoardSpec& board,
                   CalibrationView* view) {
  const double ideal[4][2] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  for (const TagDetection& tag : detector.detect(grey)) {
    if (tag.id >= board.cols * board.rows) continue;
    const double cx = (tag.id % board.cols) * board.pitch_x_m;
    const double cy = (tag.id / board.cols) * board.pitch_y_m;
    for (int k = 0; k < 4; ++k) {
      view->corners_px.emplace_back(static_cast<float>(tag.corners_px[k].x),
                                    static_cast<float>(tag.corners_px[k].y));
      view->board_points.emplace_back(static_cast<float>(cx + ideal[k][0] * board.tag_m / 2),
                                      static_cast<float>(cy + ideal[k][1] * board.tag_m / 2), 0.0f);
    }
  }
  view->detector = "apriltag";
}

// The smallest distance between neighbouring corners of a found chessboard (px).
double smallest_corner_spacing_px(const std::vector<cv::Point2f>& corners, cv::Size pattern) {
  double spacing = 1e9;
  for (int r = 0; r < pattern.height; ++r) {
    for (int c = 0; c < pattern.width; ++c) {
      const cv::Point2f& p = corners[r * pattern.width + c];
      if (c + 1 < pattern.width)
        spacing = std::min(spacing, cv::norm(corners[r * pattern.width + c + 1] - p));
      if (r + 1 < pattern.height)
        spacing = std::min(spacing, cv::norm(corners[(r + 1) * pattern.width + c] - p));
    }
  }
  return spacing;
}

// A chessboard: findChessboardCornersSB in accuracy mode, allowed to find a larger board; where
// it does, SB is asked again for exactly the board given (the larger mode also extends a board
// by a row of its own frame's edge: OpenCV's right14.jpg reads 9x7 on a 9x6 board, which SB finds
// when asked for 9x6; on a board really larger it finds nothing), and a board larger still is
// recorded in board_seen and not used. Else the classic detector with cornerSubPix in a window
// that stays within the smallest square seen (a fixed 11x11 window pulls the corners of small
// squares towards the background).
void find_chessboard(const cv::Mat& grey, const BoardSpec& board, CalibrationView* view) {
  const cv::Size pattern(board.cols, board.rows);
  const int sb_flags = cv::CALIB_CB_ACCURACY | cv::CALIB_CB_NORMALIZE_IMAGE;
  std::vector<cv::Point2f> corners;
  cv::Mat meta;
  if (cv::findChessboardCornersSB(grey, pattern, corners, sb_flags | cv::CALIB_CB_LARGER, meta)) {
    if (static_cast<int>(corners.size()) != board.cols * board.rows &&
        !cv::findChessboardCornersSB(grey, pattern, corners, sb_flags)) {
      view->board_seen = cv::Size(std::max(meta.cols, meta.rows), std::min(meta.cols, meta.rows));
      return;
    }
    view->corners_px = corners;
    view->detector = "sb";
  } else if (cv::findChessboardCorners(
                 grey, pattern, corners,
                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
    const int half =
        std::clamp(static_cast<int>(0.3 * smallest_corner_spacing_px(corners, pattern)), 2, 11);
    cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    view->corners_px = corners;
    view->detector = "classic";
  } else {
    return;
  }
  view->board_points = chessboard_points(board);
  view->board_found = true;
}

cv::Ptr<cv::aruco::CharucoBoard> make_charuco(const BoardSpec& board) {
  static const std::vector<std::pair<std::string, int>> kDictionaries = {
      {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
      {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
      {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
      {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
      {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
      {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
      {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
      {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
      {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
      {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
      {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
      {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
      {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
      {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
      {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
      {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
      {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL}};
  for (const auto& [name, id] : kDictionaries) {
    if (name == board.dictionary)
      return cv::aruco::CharucoBoard::create(
          board.cols, board.rows, static_cast<float>(board.square_m),
          static_cast<float>(board.marker_m), cv::aruco::getPredefinedDictionary(id));
  }
  std::string known;
  for (const auto& entry : kDictionaries) known += (known.empty() ? "" : ", ") + entry.first;
  throw InputError("--board " + board.text + ": unknown ArUco dictionary " + board.dictionary +
                   " (one of " + known + ")");
}

void find_charuco(const cv::Mat& grey, const cv::Ptr<cv::aruco::CharucoBoard>& charuco,
                  CalibrationView* view) {
  std::vector<std::vector<cv::Point2f>> markers;
  std::vector<int> ids;
  cv::aruco::detectMarkers(grey, charuco->dictionary, markers, ids);
  view->detector = "charuco";
  if (ids.empty()) return;
  std::vector<cv::Point2f> corners;
  std::vector<int> corner_ids;
  cv::aruco::interpolateCornersCharuco(markers, ids, grey, charuco, corners, corner_ids);
  for (size_t i = 0; i < corner_ids.size(); ++i) {
    view->corners_px.push_back(corners[i]);
    view->board_points.push_back(charuco->chessboardCorners[corner_ids[i]]);
  }
  view->board_found = view->corners_px.size() >= 6;
}

// What the images show when no view matched --board: the size of the first chessboard found
// with any size (SB finds a board at least 3x3 and reports its real size).
std::optional<cv::Size> chessboard_in(const std::vector<cv::Mat>& greys) {
  for (size_t i = 0; i < greys.size() && i < 5; ++i) {
    std::vector<cv::Point2f> corners;
    cv::Mat meta;
    if (cv::findChessboardCornersSB(greys[i], cv::Size(3, 3), corners,
                                    cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_LARGER, meta) &&
        !meta.empty())
      return cv::Size(std::max(meta.cols, meta.rows), std::min(meta.cols, meta.rows));
  }
  return std::nullopt;
}

// The fits tried for a model, in order: all its coefficients, then fewer (a fit that folds the
// image where the board never was is refitted with the outer terms held at 0).
struct FitStep {
  int flags;
  const char* words;
};
std::vector<FitStep> fit_steps(LensModel model) {
  const std::vector<FitStep> pinhole = {
      {0, "pinhole, k1 k2 p1 p2 k3"},
      {cv::CALIB_FIX_K3, "pinhole, k1 k2 p1 p2 (k3 held at 0)"},
      {cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3, "pinhole, k1 p1 p2 (k2 and k3 held at 0)"}};
  switch (model) {
    case LensModel::kRational: {
      std::vector<FitStep> steps = {{cv::CALIB_RATIONAL_MODEL, "rational, k1..k6 p1 p2"},
                                    {cv::CALIB_RATIONAL_MODEL | cv::CALIB_FIX_K3 | cv::CALIB_FIX_K6,
                                     "rational, k1 k2 k4 k5 p1 p2 (k3 and k6 held at 0)"}};
      steps.insert(steps.end(), pinhole.begin(), pinhole.end());
      return steps;
    }
    case LensModel::kFisheye:
      return {{cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
               "fisheye (equidistant), k1..k4"},
              {cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW |
                   cv::fisheye::CALIB_FIX_K3 | cv::fisheye::CALIB_FIX_K4,
               "fisheye (equidistant), k1 k2 (k3 and k4 held at 0)"}};
    case LensModel::kPinhole:
      break;
  }
  return pinhole;
}

struct Fit {
  CameraIntrinsics intrinsics;
  double rms_px = 0.0;
  std::vector<cv::Mat> rvecs, tvecs;
};

// One calibration over the views given; throws cv::Exception when OpenCV gives up.
Fit fit(const std::vector<const CalibrationView*>& views, cv::Size size, LensModel model,
        int flags) {
  Fit f;
  std::vector<std::vector<cv::Point3f>> objects;
  std::vector<std::vector<cv::Point2f>> corners;
  for (const CalibrationView* v : views) {
    objects.push_back(v->board_points);
    corners.push_back(v->corners_px);
  }
  cv::Mat k, d;
  if (model == LensModel::kFisheye) {
    std::vector<std::vector<cv::Point3d>> objects_d;
    std::vector<std::vector<cv::Point2d>> corners_d;
    for (size_t i = 0; i < objects.size(); ++i) {
      objects_d.emplace_back(objects[i].begin(), objects[i].end());
      corners_d.emplace_back(corners[i].begin(), corners[i].end());
    }
    f.rms_px = cv::fisheye::calibrate(
        objects_d, corners_d, size, k, d, f.rvecs, f.tvecs, flags,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-10));
    f.intrinsics.fisheye = true;
  } else {
    f.rms_px = cv::calibrateCamera(objects, corners, size, k, d, f.rvecs, f.tvecs, flags);
  }
  f.intrinsics.width_px = size.width;
  f.intrinsics.height_px = size.height;
  f.intrinsics.camera_matrix = cv::Matx33d(k);
  f.intrinsics.distortion.assign(d.begin<double>(), d.end<double>());
  return f;
}

// Each view's reprojection RMS and worst corner under a fit.
void measure_views(const Fit& f, const std::vector<CalibrationView*>& views) {
  const CameraModel camera(f.intrinsics, MountPose{});
  for (size_t j = 0; j < views.size(); ++j) {
    CalibrationView& v = *views[j];
    std::vector<cv::Point2d> projected =
        camera.project_camera_points(v.board_points, f.rvecs[j], f.tvecs[j]);
    double sum = 0.0, worst = 0.0;
    for (size_t i = 0; i < v.corners_px.size(); ++i) {
      const cv::Point2d e = projected[i] - cv::Point2d(v.corners_px[i]);
      sum += e.dot(e);
      worst = std::max(worst, std::sqrt(e.dot(e)));
    }
    v.rms_px = std::sqrt(sum / std::max<size_t>(1, v.corners_px.size()));
    v.worst_corner_px = worst;
  }
}

// The first fit of `steps` that does not fold the image, over `views`; nullopt when none.
std::optional<Fit> first_fit(const std::vector<const CalibrationView*>& views, cv::Size size,
                             LensModel model, IntrinsicsCalibration* result) {
  const std::vector<FitStep> steps = fit_steps(model);
  for (size_t i = 0; i < steps.size(); ++i) {
    const LensModel step_model =
        model == LensModel::kRational && (steps[i].flags & cv::CALIB_RATIONAL_MODEL) == 0
            ? LensModel::kPinhole
            : model;
    std::string problem;
    try {
      Fit f = fit(views, size, step_model, steps[i].flags);
      problem = distortion_fold_problem(f.intrinsics);
      if (problem.empty()) {
        if (i > 0) result->notes.push_back("refitted as " + std::string(steps[i].words));
        result->model = steps[i].words;
        return f;
      }
    } catch (const cv::Exception& e) {
      problem = "OpenCV gave up (" + std::string(e.err) + ")";
    }
    result->notes.push_back(std::string(steps[i].words) + ": " + problem);
  }
  return std::nullopt;
}

}  // namespace

BoardSpec parse_board(const std::string& text) {
  BoardSpec board;
  board.text = text;
  int consumed = 0;
  auto check_grid = [&](int min_each) {
    if (board.cols < min_each || board.rows < min_each || board.cols > 100 || board.rows > 100)
      throw InputError("--board " + text + ": " + std::to_string(min_each) + " to 100 each way");
  };
  if (text.rfind("apriltag:", 0) == 0) {
    board.kind = BoardSpec::Kind::kAprilTagGrid;
    const int n =
        std::sscanf(text.c_str(), "apriltag:%dx%d:%lf:%lf%n:%lf%n", &board.cols, &board.rows,
                    &board.tag_m, &board.pitch_x_m, &consumed, &board.pitch_y_m, &consumed);
    if ((n != 4 && n != 5) || consumed != static_cast<int>(text.size()))
      throw InputError("--board " + text +
                       ": expected apriltag:COLSxROWS:TAG_M:PITCH_M[:PITCH_Y_M]");
    if (n == 4) board.pitch_y_m = board.pitch_x_m;
    check_grid(1);
    if (board.cols * board.rows < 4)
      throw InputError("--board " + text + ": a grid of 4 tags or more");
    if (!(board.tag_m > 0.0 && board.tag_m < std::min(board.pitch_x_m, board.pitch_y_m) &&
          std::max(board.pitch_x_m, board.pitch_y_m) < 10.0))
      throw InputError("--board " + text + ": need 0 < TAG_M < each PITCH < 10");
    return board;
  }
  if (text.rfind("charuco:", 0) == 0) {
    board.kind = BoardSpec::Kind::kCharuco;
    char dictionary[64] = {0};
    const int n = std::sscanf(text.c_str(), "charuco:%dx%d:%lf:%lf%n:%63[A-Z0-9_]%n", &board.cols,
                              &board.rows, &board.square_m, &board.marker_m, &consumed, dictionary,
                              &consumed);
    if ((n != 4 && n != 5) || consumed != static_cast<int>(text.size()))
      throw InputError("--board " + text +
                       ": expected charuco:COLSxROWS:SQUARE_M:MARKER_M[:DICTIONARY] (squares)");
    if (n == 5) board.dictionary = dictionary;
    check_grid(3);
    if (!(board.marker_m > 0.0 && board.marker_m < board.square_m && board.square_m < 10.0))
      throw InputError("--board " + text + ": need 0 < MARKER_M < SQUARE_M < 10");
    make_charuco(board);  // the dictionary is known
    return board;
  }
  if (std::sscanf(text.c_str(), "chessboard:%dx%d:%lf%n", &board.cols, &board.rows, &board.square_m,
                  &consumed) != 3 ||
      consumed != static_cast<int>(text.size()))
    throw InputError("--board " + text + ": expected chessboard:COLSxROWS:SQUARE_M");
  if (board.cols < 3 || board.rows < 3 || board.cols > 100 || board.rows > 100)
    throw InputError("--board " + text + ": inner corners must be 3 to 100 each way");
  if (!(board.square_m > 0.0 && board.square_m < 10.0))
    throw InputError("--board " + text + ": square size must be in (0, 10) m");
  return board;
}

LensModel parse_lens_model(const std::string& text) {
  if (text == "pinhole") return LensModel::kPinhole;
  if (text == "rational") return LensModel::kRational;
  if (text == "fisheye") return LensModel::kFisheye;
  throw InputError("--model " + text + ": expected pinhole, rational or fisheye");
}

IntrinsicsCalibration calibrate_intrinsics(const std::vector<std::string>& names,
                                           const std::vector<cv::Mat>& images,
                                           const BoardSpec& board, LensModel model,
                                           const std::function<void(double)>& progress) {
  IntrinsicsCalibration result;
  std::unique_ptr<AprilTagDetector> tag_detector;
  cv::Ptr<cv::aruco::CharucoBoard> charuco;
  if (board.kind == BoardSpec::Kind::kAprilTagGrid) {
    AprilTagDetector::Options options;
    options.family = board.family;
    tag_detector = std::make_unique<AprilTagDetector>(options);
  } else if (board.kind == BoardSpec::Kind::kCharuco) {
    charuco = make_charuco(board);
  }
  cv::Size size;
  std::vector<cv::Mat> greys;
  for (size_t i = 0; i < images.size(); ++i) {
    CalibrationView view;
    view.name = names[i];
    cv::Mat grey;
    if (images[i].channels() == 3) {
      cv::cvtColor(images[i], grey, cv::COLOR_BGR2GRAY);
    } else {
      grey = images[i];
    }
    if (size.empty()) size = grey.size();
    if (grey.size() != size) {
      throw InputError(names[i] + ": image is " + std::to_string(grey.cols) + "x" +
                       std::to_string(grey.rows) + ", the first was " + std::to_string(size.width) +
                       "x" + std::to_string(size.height));
    }
    switch (board.kind) {
      case BoardSpec::Kind::kChessboard:
        find_chessboard(grey, board, &view);
        break;
      case BoardSpec::Kind::kCharuco:
        find_charuco(grey, charuco, &view);
        break;
      case BoardSpec::Kind::kAprilTagGrid:
        add_grid_tags(*tag_detector, grey, board, &view);
        view.board_found = view.corners_px.size() >= 16;
        break;
    }
    result.views.push_back(view);
    greys.push_back(grey);
    if (progress) progress(static_cast<double>(i + 1) / images.size());
  }

  // A board of another size than --board: larger boards are seen by the detector itself; a
  // smaller one is found in no view.
  const std::string board_words = board.kind == BoardSpec::Kind::kChessboard
                                      ? "a " + std::to_string(board.cols) + "x" +
                                            std::to_string(board.rows) +
                                            " chessboard (inner corners)"
                                  : board.kind == BoardSpec::Kind::kCharuco
                                      ? "a ChArUco board (" + board.text + ", 6 corners or more)"
                                      : "an AprilTag grid (" + board.text + ", 4 tags or more)";
  // The size most views show (perspective may make the detector count one row more in one).
  int larger = 0;
  std::map<std::pair<int, int>, int> sizes;
  for (const CalibrationView& v : result.views) {
    if (!v.board_seen.empty()) {
      ++larger;
      ++sizes[{v.board_seen.width, v.board_seen.height}];
    }
  }
  cv::Size seen;
  int most = 0;
  for (const auto& [wh, count] : sizes) {
    if (count > most) {
      most = count;
      seen = cv::Size(wh.first, wh.second);
    }
  }
  const int found =
      static_cast<int>(std::count_if(result.views.begin(), result.views.end(),
                                     [](const CalibrationView& v) { return v.board_found; }));
  if (larger > 0 && larger >= found) {
    throw InputError("--board " + board.text + ": " + std::to_string(larger) + " of " +
                     std::to_string(result.views.size()) + " images show a chessboard of " +
                     std::to_string(seen.width) + "x" + std::to_string(seen.height) +
                     " inner corners, larger than the " + std::to_string(board.cols) + "x" +
                     std::to_string(board.rows) + " given: give the board's full size");
  }
  if (larger > 0)
    result.warnings.push_back(std::to_string(larger) + " images show a chessboard of " +
                              std::to_string(seen.width) + "x" + std::to_string(seen.height) +
                              " inner corners, larger than --board; they are not used");
  if (found < 3) {
    std::string what = board_words + " was found in " + std::to_string(found) + " of " +
                       std::to_string(result.views.size()) + " images; at least 3 views are needed";
    if (board.kind == BoardSpec::Kind::kChessboard) {
      if (const std::optional<cv::Size> other = chessboard_in(greys))
        what += "; the images show a chessboard of " + std::to_string(other->width) + "x" +
                std::to_string(other->height) + " inner corners: check --board";
    }
    throw InputError(what);
  }

  // Fit, reject views far worse than the others (a blurred frame, a wrongly ordered detection),
  // fit again without them.
  auto views_where = [&](auto keep) {
    std::vector<CalibrationView*> out;
    for (CalibrationView& v : result.views)
      if (keep(v)) out.push_back(&v);
    return out;
  };
  auto as_const = [](const std::vector<CalibrationView*>& views) {
    return std::vector<const CalibrationView*>(views.begin(), views.end());
  };
  std::vector<CalibrationView*> used =
      views_where([](const CalibrationView& v) { return v.board_found; });
  std::optional<Fit> f = first_fit(as_const(used), size, model, &result);
  if (f) {
    measure_views(*f, used);
    std::vector<double> errors;
    for (const CalibrationView* v : used) errors.push_back(v->rms_px);
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    const double limit_px = std::max(1.0, 3.0 * errors[errors.size() / 2]);
    std::vector<CalibrationView*> kept;
    for (CalibrationView* v : used)
      if (v->rms_px <= limit_px) kept.push_back(v);
    if (kept.size() < used.size() && kept.size() >= 3) {
      used = kept;
      result.notes.clear();
      f = first_fit(as_const(used), size, model, &result);
      if (f) measure_views(*f, used);
    }
  }
  for (CalibrationView* v : used) v->used = true;
  result.used_views = static_cast<int>(used.size());
  if (!f) {
    result.failure =
        "no lens model fits these views without folding the image: take views with the board "
        "near the image corners and edges, or try --model rational or --model fisheye";
    return result;
  }
  result.fitted = true;
  result.intrinsics = f->intrinsics;
  result.rms_px = f->rms_px;

  const std::vector<bool> covered = covered_cells(result);
  result.coverage =
      static_cast<double>(std::count(covered.begin(), covered.end(), true)) / (kGrid * kGrid);
  bool any_tilted = false;
  for (const cv::Mat& rvec : f->rvecs) {
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    // Angle between the board's normal and the optical axis.
    if (std::acos(std::min(1.0, std::abs(r(2, 2)))) > 15.0 * CV_PI / 180.0) any_tilted = true;
  }
  char text[256];
  if (result.used_views < 8)
    result.warnings.push_back("only " + std::to_string(result.used_views) +
                              " views used; 10-20 views at varied poses give a trustworthy result");
  if (result.coverage < 0.5) {
    std::snprintf(text, sizeof(text),
                  "corners cover %.0f %% of the image (5x5 grid, see the coverage picture); the "
                  "distortion far from them is a guess: move the board into the corners",
                  100.0 * result.coverage);
    result.warnings.push_back(text);
  }
  if (!any_tilted)
    result.warnings.push_back(
        "every view sees the board within 15 deg of face on: the focal length is poorly "
        "determined; tilt the board in some views");
  const cv::Matx33d& k = result.intrinsics.camera_matrix;
  const double aspect = k(0, 0) / k(1, 1);
  if (std::abs(aspect - 1.0) > 0.02) {
    std::snprintf(text, sizeof(text),
                  "fx/fy = %.3f: pixels are rarely this far from square; check the board's "
                  "squares are square as printed and that the images were not rescaled",
                  aspect);
    result.warnings.push_back(text);
  }
  if (result.rms_px > 1.0) {
    std::snprintf(text, sizeof(text),
                  "reprojection RMS %.2f px (above 1 px): blurred views, a board that is not flat, "
                  "or a lens the model does not fit (--model)",
                  result.rms_px);
    result.warnings.push_back(text);
  }
  // Leave one out: a view that moves the focal length by more than 1 % carries the result.
  if (used.size() >= 5) {
    for (size_t j = 0; j < used.size(); ++j) {
      std::vector<const CalibrationView*> others;
      for (size_t i = 0; i < used.size(); ++i)
        if (i != j) others.push_back(used[i]);
      IntrinsicsCalibration scratch;
      const std::optional<Fit> without = first_fit(others, size, model, &scratch);
      if (!without) continue;
      const double change = without->intrinsics.camera_matrix(0, 0) / k(0, 0) - 1.0;
      if (std::abs(change) > 0.01) {
        std::snprintf(text, sizeof(text),
                      "leaving out %s moves fx by %+.1f %%: the result leans on that view; add "
                      "views like it",
                      used[j]->name.c_str(), 100.0 * change);
        result.warnings.push_back(text);
      }
    }
  }
  return result;
}

cv::Mat coverage_picture(const IntrinsicsCalibration& calibration) {
  const int w = calibration.intrinsics.width_px, h = calibration.intrinsics.height_px;
  cv::Mat picture(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::vector<bool> covered = covered_cells(calibration);
  int view_index = 0;
  for (const CalibrationView& v : calibration.views) {
    if (!v.used) continue;
    cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar((view_index++ * 37) % 180, 220, 200)), bgr;
    cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
    const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
    for (const cv::Point2f& p : v.corners_px) {
      cv::circle(picture, p, 3, cv::Scalar(c[0], c[1], c[2]), cv::FILLED, cv::LINE_AA);
    }
  }
  for (int gy = 0; gy < kGrid; ++gy) {
    for (int gx = 0; gx < kGrid; ++gx) {
      const cv::Rect cell(gx * w / kGrid, gy * h / kGrid, w / kGrid, h / kGrid);
      if (!covered[gy * kGrid + gx]) {
        cv::Mat roi = picture(cell);
        roi -= cv::Scalar(40, 40, 0);
      }
      cv::rectangle(picture, cell, cv::Scalar(160, 160, 160), 1);
    }
  }
  char caption[160];
  std::snprintf(caption, sizeof(caption),
                "%d views, RMS %.3f px, coverage %.0f %% (shaded: no corners)",
                calibration.used_views, calibration.rms_px, 100.0 * calibration.coverage);
  cv::putText(picture, caption, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return picture;
}

}  // namespace agv::perception
