#include "perception/line_set.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace agv::perception {
namespace {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + i, values.end());
  return values[i];
}

// Width of the tape at a chord: the chord's extent across the curve.
double chord_width(const Chord& chord, const CurveModel& model) {
  const double s = model.arc_position(chord.centre());
  const Eigen::Vector2d ahead = model.point_at(s + 1e-3) - model.point_at(s - 1e-3);
  const Eigen::Vector2d normal = Eigen::Vector2d(-ahead.y(), ahead.x()).normalized();
  return std::abs(normal.dot(chord.a - chord.b));
}

}  // namespace

std::optional<CurveModel> near_model_if_different(const std::vector<Chord>& chords,
                                                  const DetectedLine& line,
                                                  const LineSetOptions& options, double sigmas) {
  std::vector<double> distances;
  for (int index : line.chords) distances.push_back(chords[index].centre().norm());
  if (static_cast<int>(distances.size()) < 2 * options.min_points) return std::nullopt;
  const double median = quantile(distances, 0.5);
  std::vector<Eigen::Vector2d> centres;
  for (const Chord& chord : chords) centres.push_back(chord.centre());
  std::vector<bool> near(chords.size(), false);
  for (int index : line.chords) near[index] = chords[index].centre().norm() <= median;
  CurveFitOptions fit_options = options.fit;
  fit_options.forward = line.model.tangent();
  const CurveFit fit = fit_curve_robust(centres, fit_options, &near);
  if (!fit.ok || fit.inlier_count < options.min_points) return std::nullopt;
  if (fit.s_max_m - fit.s_min_m < std::max(options.min_visible_length_m, 0.05)) return std::nullopt;
  const double difference = std::abs(fit.model.curvature_1_m - line.model.curvature_1_m);
  if (difference <= sigmas * fit.curvature_sigma_1_m + 0.05) return std::nullopt;
  return fit.model.tangent().dot(line.model.tangent()) >= 0.0 ? fit.model : fit.model.reversed();
}

std::vector<DetectedLine> extract_lines(const std::vector<Chord>& chords,
                                        const LineSetOptions& options,
                                        std::vector<std::string>* rejections) {
  std::vector<DetectedLine> lines;
  auto reject = [&](const std::string& why) {
    if (rejections) rejections->push_back(why);
  };
  std::vector<Eigen::Vector2d> centres;
  std::vector<bool> available;
  // A chord much longer than the tape is wide runs along the tape (or through a junction):
  // its midpoint is not on a centre line.
  const double max_chord_m = options.expected_width_m > 0.0 ? 3.0 * options.expected_width_m : 0.15;
  for (const Chord& chord : chords) {
    centres.push_back(chord.centre());
    available.push_back((chord.a - chord.b).norm() <= max_chord_m);
  }
  for (int attempt = 0;
       attempt < 2 * options.max_lines && static_cast<int>(lines.size()) < options.max_lines;
       ++attempt) {
    const int remaining = static_cast<int>(std::count(available.begin(), available.end(), true));
    if (remaining < options.min_points) {
      if (lines.empty()) reject("too few edge points on the tape");
      break;
    }
    const CurveFit fit = fit_curve_robust(centres, options.fit, &available);
    if (!fit.ok || fit.inlier_count < options.min_points) {
      if (lines.empty()) reject("edge points do not lie on one line");
      break;
    }
    for (size_t i = 0; i < centres.size(); ++i) {
      if (fit.inliers[i]) available[i] = false;  // used, accepted or not
    }
    DetectedLine line;
    line.model = fit.model;
    line.residual_rms_m = fit.rms_m;
    line.s_min_m = fit.s_min_m;
    line.s_max_m = fit.s_max_m;
    line.points_used = fit.inlier_count;
    std::vector<double> widths;
    for (size_t i = 0; i < chords.size(); ++i) {
      if (!fit.inliers[i]) continue;
      line.chords.push_back(static_cast<int>(i));
      widths.push_back(chord_width(chords[i], fit.model));
    }
    line.width_m = quantile(widths, 0.5);
    line.width_spread_m = quantile(widths, 0.9) - quantile(widths, 0.1);
    const double span_m = fit.s_max_m - fit.s_min_m;
    // How much of the evidence near this line it explains: chords whose centre lies within a
    // tape width of it but are not inliers speak against it.
    int near = 0;
    const CurveModel::Prepared curve = fit.model.prepared();
    for (size_t i = 0; i < centres.size(); ++i) {
      if (std::abs(curve.signed_distance(centres[i])) < std::max(line.width_m, 0.005)) ++near;
    }
    const double inlier_fraction = static_cast<double>(fit.inlier_count) / std::max(1, near);
    if (span_m < options.min_visible_length_m) {
      reject("visible tape too short");
      continue;
    }  // Tape leaves evidence all along (even interrupted tape, in pieces); a chance alignment of
    // texture blobs has it only here and there.
    line.coverage = std::min(1.0, fit.inlier_count * options.scan_spacing_m / span_m);
    if (line.coverage < options.min_coverage) {
      reject("evidence too sparse along the line");
      continue;
    }
    if (inlier_fraction < options.min_inlier_fraction) {
      reject("edge points do not lie on one line");
      continue;
    }
    double width_error = 0.0;
    if (options.expected_width_m > 0.0) {
      width_error = std::abs(line.width_m - options.expected_width_m) / options.expected_width_m;
      if (width_error > options.width_tolerance) {
        reject("tape width does not match the configured width");
        continue;
      }
    }
    if (line.width_spread_m > options.width_spread_tolerance * line.width_m + 0.0005) {
      reject("tape width varies along the line");
      continue;
    }
    // Confidence: every factor is 1 for a clean, fully visible tape of the right width.
    const double span_factor = std::min(1.0, span_m / options.full_span_m);
    const double width_factor =
        options.expected_width_m > 0.0 ? std::exp(-0.5 * std::pow(width_error / 0.15, 2)) : 1.0;
    const double residual_factor = 1.0 / (1.0 + std::pow(fit.rms_m / 0.0005, 2));
    const double coverage_factor = std::min(1.0, line.coverage / 0.6);
    line.confidence = std::min(1.0, inlier_fraction) * span_factor * width_factor *
                      residual_factor * coverage_factor;
    if (line.confidence < options.min_confidence) {
      reject("evidence too weak");
      continue;
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace agv::perception
