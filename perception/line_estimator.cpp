#include "perception/line_estimator.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "perception/contrast_axis.h"
#include "perception/line_fit.h"
#include "perception/tape_regions.h"

namespace agv::perception {
namespace {

double median_of(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

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
}

LineMeasurement LineEstimator::estimate(const cv::Mat& frame, double stamp_s,
                                        LineDetection* details) const {
  if (details) *details = LineDetection{};
  const CameraIntrinsics& intrinsics = camera_.intrinsics();
  if (frame.empty()) return not_found(stamp_s, "empty frame", details);
  if (frame.cols != intrinsics.width_px || frame.rows != intrinsics.height_px) {
    return not_found(stamp_s, "frame size differs from the camera's", details);
  }
  if (frame.type() != CV_8UC3 && frame.type() != CV_8UC1) {
    return not_found(stamp_s, "frame is not 8-bit BGR or grey", details);
  }

  // Block means over ds x ds pixels; in 2x steps, which OpenCV does three times faster than
  // one 4x step, with the same result.
  cv::Mat small = frame;
  const int ds = options_.downsample;
  for (int factor = 1; factor < ds; factor *= 2) {
    cv::resize(small, small, cv::Size(small.cols / 2, small.rows / 2), 0, 0, cv::INTER_AREA);
  }
  const std::optional<ContrastAxis> axis = estimate_contrast_axis(small, options_.tape.color_bgr);
  if (!axis) return not_found(stamp_s, "flat frame: nothing differs from the floor", details);
  const TapeRegions coarse =
      find_tape_regions(small, *axis, ds, bar_widths_small_px_, options_.min_region_area_small_px);
  if (coarse.regions.empty()) return not_found(stamp_s, "no tape-like region", details);

  // The largest region is the line (junctions and branches come with multi-line support).
  const TapeRegion& region = coarse.regions.front();
  // The bar response covers at least the tape's middle half: 0.6 of a width beyond it reaches
  // past the edges onto the floor.
  EdgeScanOptions scan = options_.scan;
  scan.flank_px = std::max(
      scan.flank_px,
      static_cast<int>(std::ceil(
          0.6 * ds * *std::max_element(bar_widths_small_px_.begin(), bar_widths_small_px_.end()))));
  const std::vector<EdgePair> edges = scan_tape_edges(frame, *axis, coarse, region, scan);

  std::vector<Eigen::Vector2d> centres, firsts, seconds;
  std::vector<EdgePair> kept_edges;
  for (const EdgePair& pair : edges) {
    const auto a = floor_map_.at(pair.first_px.x, pair.first_px.y);
    const auto b = floor_map_.at(pair.second_px.x, pair.second_px.y);
    if (!a || !b) continue;
    firsts.push_back(*a);
    seconds.push_back(*b);
    centres.push_back(0.5 * (*a + *b));
    kept_edges.push_back(pair);
  }
  if (details) {
    details->edges = kept_edges;
    details->centre_points_m = centres;
    for (size_t i = 0; i < centres.size(); ++i)
      details->widths_m.push_back((firsts[i] - seconds[i]).norm());
  }
  if (static_cast<int>(centres.size()) < options_.min_points) {
    return not_found(stamp_s, "too few edge points on the tape", details);
  }

  const LineFit fit =
      fit_line_robust(centres, options_.inlier_threshold_m, options_.ransac_iterations);
  if (!fit.ok) return not_found(stamp_s, "line fit failed", details);
  Eigen::Vector2d direction = fit.direction;
  if (direction.x() < 0.0) direction = -direction;  // travel direction: forward in the vehicle
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  std::vector<double> widths;
  for (size_t i = 0; i < centres.size(); ++i) {
    if (fit.inliers[i]) widths.push_back(std::abs(normal.dot(firsts[i] - seconds[i])));
  }
  const double width_m = median_of(widths);
  // Tape has one width along its length; a chance chain of floor texture does not.
  std::sort(widths.begin(), widths.end());
  const double width_spread_m =
      widths.empty() ? 0.0 : widths[widths.size() * 9 / 10] - widths[widths.size() / 10];
  if (details) {
    details->inliers = fit.inliers;
    details->line_point_m = fit.point;
    details->line_direction = direction;
    details->residual_rms_m = fit.rms_m;
    details->span_m = fit.span_m;
    details->measured_width_m = width_m;
  }

  const double inlier_fraction = static_cast<double>(fit.inlier_count) / centres.size();
  if (fit.inlier_count < options_.min_points || inlier_fraction < options_.min_inlier_fraction) {
    return not_found(stamp_s, "edge points do not lie on one line", details);
  }
  if (fit.span_m < options_.min_visible_length_m) {
    return not_found(stamp_s, "visible tape too short", details);
  }
  const double expected_width_m = options_.tape.width_m;
  double width_error = 0.0;
  if (expected_width_m > 0.0) {
    width_error = std::abs(width_m - expected_width_m) / expected_width_m;
    if (width_error > options_.width_tolerance) {
      return not_found(stamp_s, "tape width does not match the configured width", details);
    }
  }

  if (width_spread_m > options_.width_spread_tolerance * width_m + 0.0005) {
    return not_found(stamp_s, "tape width varies along the line", details);
  }

  LineMeasurement m;
  m.stamp_s = stamp_s;
  m.line_found = true;
  m.e_theta_rad = -std::atan2(direction.y(), direction.x());
  // Signed distance of the vehicle origin from the line, positive when the vehicle is left.
  m.e_d_m = direction.y() * fit.point.x() - direction.x() * fit.point.y();
  m.curvature_1_m = 0.0;
  m.points_used = fit.inlier_count;
  m.tape_width_m = width_m;
  // Confidence: every factor is 1 for a clean, fully visible tape of the right width.
  const double full_span_m = floor_map_.view_radius_m();
  const double span_factor = std::min(1.0, fit.span_m / full_span_m);
  const double width_factor =
      expected_width_m > 0.0 ? std::exp(-0.5 * std::pow(width_error / 0.15, 2)) : 1.0;
  const double residual_factor = 1.0 / (1.0 + std::pow(fit.rms_m / 0.0005, 2));
  m.confidence = inlier_fraction * span_factor * width_factor * residual_factor;
  if (m.confidence < options_.min_confidence)
    return not_found(stamp_s, "evidence too weak", details);
  return m;
}

}  // namespace agv::perception
