#include "perception/line_estimator.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "perception/contrast_axis.h"
#include "perception/tape_regions.h"

namespace agv::perception {
namespace {

LineMeasurement not_found(double stamp_s, const std::string& reason, LineDetection* details) {
  if (details) details->rejected_because = reason;
  LineMeasurement m;
  m.stamp_s = stamp_s;
  return m;
}

}  // namespace

LineEstimator::LineEstimator(const CameraModel& camera, const Options& options)
    : camera_(camera), options_(options), floor_map_(camera) {
  // Tape width in downsampled pixels at the middle of the view; without a configured width,
  // the common widths from 12 to 50 mm.
  const double footprint_m = std::max(1e-6, floor_map_.typical_footprint_m());
  const std::vector<double> widths_m = options_.tape.width_m > 0.0
                                           ? std::vector<double>{options_.tape.width_m}
                                           : std::vector<double>{0.012, 0.025, 0.05};
  for (double width_m : widths_m)
    bar_widths_small_px_.push_back(width_m / footprint_m / options_.downsample);
  tape_width_px_ = *std::max_element(widths_m.begin(), widths_m.end()) / footprint_m;
  options_.lines.expected_width_m = options_.tape.width_m;
  // Pieces of tape laid end to end are rarely collinear to better than a tenth of their width:
  // the inlier band grows with the width so that such a seam does not split a line.
  const double reference_width_m = options_.tape.width_m > 0.0 ? options_.tape.width_m : 0.025;
  options_.lines.fit.inlier_threshold_m =
      std::max(options_.lines.fit.inlier_threshold_m, 0.12 * reference_width_m);
  options_.lines.full_span_m = floor_map_.view_radius_m();
  options_.lines.scan_spacing_m = footprint_m * std::max(1, options_.scan.step);
}

LineMeasurement LineEstimator::estimate(const cv::Mat& frame, double stamp_s,
                                        LineDetection* details) const {
  LineDetection local;
  LineDetection& d = details ? *details : local;
  d = LineDetection{};
  const CameraIntrinsics& intrinsics = camera_.intrinsics();
  if (frame.empty()) return not_found(stamp_s, "empty frame", &d);
  if (frame.cols != intrinsics.width_px || frame.rows != intrinsics.height_px) {
    return not_found(stamp_s, "frame size differs from the camera's", &d);
  }
  if (frame.type() != CV_8UC3 && frame.type() != CV_8UC1) {
    return not_found(stamp_s, "frame is not 8-bit BGR or grey", &d);
  }

  // Block means over ds x ds pixels; in 2x steps, which OpenCV does three times faster than
  // one 4x step, with the same result.
  cv::Mat small = frame;
  const int ds = options_.downsample;
  for (int factor = 1; factor < ds; factor *= 2) {
    cv::resize(small, small, cv::Size(small.cols / 2, small.rows / 2), 0, 0, cv::INTER_AREA);
  }
  const std::optional<ContrastAxis> axis = choose_contrast_axis(
      small, options_.tape.color_bgr,
      *std::max_element(bar_widths_small_px_.begin(), bar_widths_small_px_.end()));
  if (!axis) return not_found(stamp_s, "flat frame: nothing differs from the floor", &d);
  const TapeRegions coarse =
      find_tape_regions(small, *axis, ds, bar_widths_small_px_, options_.min_region_area_small_px);
  if (coarse.regions.empty()) return not_found(stamp_s, "no tape-like region", &d);

  // The bar response covers at least the tape's middle half: 0.6 of a width beyond it reaches
  // past the edges onto the floor.
  EdgeScanOptions scan = options_.scan;
  scan.flank_px = std::max(scan.flank_px, static_cast<int>(std::ceil(0.6 * tape_width_px_)));
  scan.max_dip_px = std::max(scan.max_dip_px, static_cast<int>(0.25 * tape_width_px_));
  const int regions = std::min<int>(options_.max_regions, static_cast<int>(coarse.regions.size()));
  for (int r = 0; r < regions; ++r) {
    const TapeRegion& region = coarse.regions[r];
    // A single band (long, one tape wide) is crossed best by scan lines across it; anything
    // else (curves, corners, junctions) is scanned both ways.
    const bool band =
        region.length_px > 4.0 * region.width_px && region.width_px < 1.6 * tape_width_px_;
    const bool rows_first = std::abs(region.direction.y) >= std::abs(region.direction.x);
    for (bool along_rows : {true, false}) {
      if (band && along_rows != rows_first) continue;
      const std::vector<EdgePair> edges =
          scan_tape_edges(frame, *axis, coarse, region, along_rows, scan);
      for (const EdgePair& pair : edges) {
        const auto a = floor_map_.at(pair.first_px.x, pair.first_px.y);
        const auto b = floor_map_.at(pair.second_px.x, pair.second_px.y);
        if (!a || !b) continue;
        d.edges.push_back(pair);
        d.chords.push_back({*a, *b});
      }
    }
  }

  std::vector<std::string> rejections;
  d.lines = extract_lines(d.chords, options_.lines, &rejections);
  if (d.lines.empty())
    return not_found(stamp_s, rejections.empty() ? "no line" : rejections.front(), &d);
  // Where the evidence of each line ends: at the image border the tape goes on unseen.
  const double border_px = 0.04 * std::min(frame.cols, frame.rows);
  auto near_border = [&](const Eigen::Vector2d& p) {
    const auto pixel = camera_.floor_to_pixel(p);
    return !pixel || pixel->x < border_px || pixel->y < border_px ||
           pixel->x > frame.cols - 1 - border_px || pixel->y > frame.rows - 1 - border_px;
  };
  for (DetectedLine& line : d.lines) {
    line.open_start = near_border(line.model.point_at(line.s_min_m));
    line.open_end = near_border(line.model.point_at(line.s_max_m));
  }
  // A branch is a piece of tape leaving the junction by more than a tape width (less is the
  // overlap of a corner), or running out of view once clear of the crossing tape.
  const double width_m = options_.tape.width_m > 0.0 ? options_.tape.width_m : 0.025;
  d.junction = find_junction(d.lines, width_m, std::max(0.01, width_m), 0.6 * width_m);
  const FollowedLine followed =
      choose_line(d.lines, d.junction, options_.branch, options_.max_branch_turn_rad);
  d.followed = followed.line;
  d.followed_model = followed.model;
  if (const auto near = near_model_if_different(d.chords, d.lines[followed.line], options_.lines)) {
    const bool same_way = near->tangent().dot(followed.model.tangent()) >= 0.0;
    d.followed_model = same_way ? *near : near->reversed();
  }

  const DetectedLine& line = d.lines[followed.line];
  LineMeasurement m;
  m.stamp_s = stamp_s;
  m.line_found = true;
  m.e_theta_rad = -d.followed_model.heading_rad;
  m.e_d_m = d.followed_model.e_d_m;
  m.curvature_1_m = d.followed_model.curvature_1_m;
  m.confidence = line.confidence;
  m.points_used = line.points_used;
  m.tape_width_m = line.width_m;
  m.lines_seen = static_cast<int>(d.lines.size());
  m.junction_ahead = d.junction.has_value() && d.junction->branches.size() >= 2;
  return m;
}

}  // namespace agv::perception
