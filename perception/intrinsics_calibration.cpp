#include "perception/intrinsics_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/input_error.h"
#include "perception/apriltag_detector.h"

namespace agv::perception {
namespace {

constexpr int kGrid = 5;

std::vector<cv::Point3f> board_points(const BoardSpec& board) {
  std::vector<cv::Point3f> points;
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c)
      points.emplace_back(static_cast<float>(c * board.square_m),
                          static_cast<float>(r * board.square_m), 0.0f);
  }
  return points;
}

double view_rms_px(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image,
                   const cv::Mat& k, const cv::Mat& d, const cv::Mat& rvec, const cv::Mat& tvec) {
  std::vector<cv::Point2f> projected;
  cv::projectPoints(object, rvec, tvec, k, d, projected);
  double sum = 0.0;
  for (size_t i = 0; i < image.size(); ++i) {
    const cv::Point2f e = projected[i] - image[i];
    sum += e.dot(e);
  }
  return std::sqrt(sum / std::max<size_t>(1, image.size()));
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
    const double cx = (tag.id % board.cols) * board.pitch_m;
    const double cy = (tag.id / board.cols) * board.pitch_m;
    for (int k = 0; k < 4; ++k) {
      view->corners_px.emplace_back(static_cast<float>(tag.corners_px[k].x),
                                    static_cast<float>(tag.corners_px[k].y));
      view->board_points.emplace_back(static_cast<float>(cx + ideal[k][0] * board.tag_m / 2),
                                      static_cast<float>(cy + ideal[k][1] * board.tag_m / 2), 0.0f);
    }
  }
}

}  // namespace

BoardSpec parse_board(const std::string& text) {
  BoardSpec board;
  board.text = text;
  int consumed = 0;
  if (text.rfind("apriltag:", 0) == 0) {
    board.kind = BoardSpec::Kind::kAprilTagGrid;
    if (std::sscanf(text.c_str(), "apriltag:%dx%d:%lf:%lf%n", &board.cols, &board.rows,
                    &board.tag_m, &board.pitch_m, &consumed) != 4 ||
        consumed != static_cast<int>(text.size()))
      throw InputError("--board " + text + ": expected apriltag:COLSxROWS:TAG_M:PITCH_M");
    if (board.cols < 1 || board.rows < 1 || board.cols * board.rows < 4 || board.cols > 100 ||
        board.rows > 100)
      throw InputError("--board " + text + ": a grid of 4 to 10000 tags");
    if (!(board.tag_m > 0.0 && board.tag_m < board.pitch_m && board.pitch_m < 10.0))
      throw InputError("--board " + text + ": need 0 < TAG_M < PITCH_M < 10");
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

IntrinsicsCalibration calibrate_intrinsics(const std::vector<std::string>& names,
                                           const std::vector<cv::Mat>& images,
                                           const BoardSpec& board) {
  IntrinsicsCalibration result;
  const cv::Size pattern(board.cols, board.rows);
  std::unique_ptr<AprilTagDetector> tag_detector;
  if (board.kind == BoardSpec::Kind::kAprilTagGrid) {
    AprilTagDetector::Options options;
    options.family = board.family;
    tag_detector = std::make_unique<AprilTagDetector>(options);
  }
  cv::Size size;
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
    if (board.kind == BoardSpec::Kind::kChessboard) {
      view.board_found =
          cv::findChessboardCorners(grey, pattern, view.corners_px,
                                    cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
      if (view.board_found) {
        cv::cornerSubPix(
            grey, view.corners_px, cv::Size(11, 11), cv::Size(-1, -1),
            cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
        view.board_points = board_points(board);
      }
    } else {
      add_grid_tags(*tag_detector, grey, board, &view);
      view.board_found = view.corners_px.size() >= 16;
    }
    result.views.push_back(view);
  }
  auto calibrate = [&](bool keep_used) {
    std::vector<std::vector<cv::Point3f>> objects;
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> index;
    for (size_t i = 0; i < result.views.size(); ++i) {
      CalibrationView& v = result.views[i];
      if (!v.board_found || (keep_used && !v.used)) continue;
      objects.push_back(v.board_points);
      corners.push_back(v.corners_px);
      index.push_back(static_cast<int>(i));
    }
    if (objects.size() < 3) {
      const std::string what = board.kind == BoardSpec::Kind::kChessboard
                                   ? "a " + std::to_string(board.cols) + "x" +
                                         std::to_string(board.rows) + " chessboard (inner corners)"
                                   : "an AprilTag grid (" + board.text + ", 4 tags or more)";
      throw InputError(what + " was found in " + std::to_string(objects.size()) + " of " +
                       std::to_string(result.views.size()) +
                       " images; at least 3 views are needed");
    }
    cv::Mat k, d;
    std::vector<cv::Mat> rvecs, tvecs;
    result.rms_px = cv::calibrateCamera(objects, corners, size, k, d, rvecs, tvecs);
    for (size_t j = 0; j < index.size(); ++j) {
      CalibrationView& v = result.views[index[j]];
      v.used = true;
      v.rms_px = view_rms_px(v.board_points, v.corners_px, k, d, rvecs[j], tvecs[j]);
    }
    result.intrinsics.width_px = size.width;
    result.intrinsics.height_px = size.height;
    result.intrinsics.camera_matrix = cv::Matx33d(k);
    result.intrinsics.distortion.assign(d.begin<double>(), d.end<double>());
    return rvecs;
  };
  std::vector<cv::Mat> rvecs = calibrate(false);
  // Outliers: views far worse than the others (a blurred frame, a wrongly ordered detection).
  std::vector<double> errors;
  for (const CalibrationView& v : result.views) {
    if (v.used) errors.push_back(v.rms_px);
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  const double limit_px = std::max(1.0, 3.0 * errors[errors.size() / 2]);
  bool rejected = false;
  for (CalibrationView& v : result.views) {
    if (v.used && v.rms_px > limit_px) {
      v.used = false;
      rejected = true;
    }
  }
  if (rejected) rvecs = calibrate(true);

  result.used_views = static_cast<int>(std::count_if(
      result.views.begin(), result.views.end(), [](const CalibrationView& v) { return v.used; }));
  const std::vector<bool> covered = covered_cells(result);
  bool any_tilted = false;
  for (const cv::Mat& rvec : rvecs) {
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    // Angle between the board's normal and the optical axis.
    if (std::acos(std::min(1.0, std::abs(r(2, 2)))) > 15.0 * CV_PI / 180.0) any_tilted = true;
  }
  result.coverage =
      static_cast<double>(std::count(covered.begin(), covered.end(), true)) / (kGrid * kGrid);
  if (result.used_views < 8)
    result.warnings.push_back("only " + std::to_string(result.used_views) +
                              " views used; 10-20 views at varied poses give a trustworthy result");
  if (result.coverage < 0.5) {
    char text[160];
    std::snprintf(text, sizeof(text),
                  "corners cover %.0f %% of the image (5x5 grid); the distortion far from them is "
                  "a guess: move the board into the corners",
                  100.0 * result.coverage);
    result.warnings.push_back(text);
  }
  if (!any_tilted)
    result.warnings.push_back(
        "every view sees the board within 15 deg of face on: the focal length is poorly "
        "determined; tilt the board in some views");
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
