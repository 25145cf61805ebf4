#include "perception/one_edge_line.h"

#include <algorithm>
#include <cmath>

#include "perception/curve_fit.h"

namespace agv::perception {

std::optional<DetectedLine> line_from_one_edge(const std::vector<Chord>& border_chords,
                                               double width_m, const Eigen::Vector2d& forward,
                                               const OneEdgeOptions& options,
                                               std::vector<Chord>* completed, std::string* why) {
  auto refuse = [&](const char* reason) -> std::optional<DetectedLine> {
    if (why) *why = reason;
    return std::nullopt;
  };
  if (!(width_m > 0.0)) return refuse("no tape width known to complete one edge");
  std::vector<Eigen::Vector2d> edge_points;
  for (const Chord& chord : border_chords) edge_points.push_back(chord.a);
  CurveFitOptions fit_options;
  fit_options.inlier_threshold_m = options.inlier_threshold_m;
  fit_options.forward = forward;
  const CurveFit fit = fit_curve_robust(edge_points, fit_options);
  if (!fit.ok || fit.inlier_count < options.min_points)
    return refuse("too few points on the one edge in view");

  // Which side of the edge the tape lies on (+1: left of the fitted curve), and how far across
  // it reaches in view, per inlier.
  std::vector<int> side(border_chords.size(), 0);
  const CurveModel::Prepared edge = fit.model.prepared();
  std::vector<double> visible_m;
  int left = 0, right = 0;
  for (size_t i = 0; i < border_chords.size(); ++i) {
    if (!fit.inliers[i]) continue;
    // Where the tape leaves the image, across the edge curve (exact on an arc).
    const double across = edge.signed_distance(border_chords[i].b);
    side[i] = across >= 0.0 ? 1 : -1;
    (across >= 0.0 ? left : right) += 1;
    visible_m.push_back(std::abs(across));
  }
  const int tape_side = left >= right ? 1 : -1;
  const int agreeing = std::max(left, right);
  if (agreeing < options.min_same_side * (left + right))
    return refuse("the tape lies on both sides of the one edge in view");
  std::nth_element(visible_m.begin(), visible_m.begin() + 9 * visible_m.size() / 10,
                   visible_m.end());
  if (visible_m[9 * visible_m.size() / 10] > options.max_visible_fraction * width_m)
    return refuse("more tape in view beside the one edge than the tape is wide");
  const double span_m = fit.s_max_m - fit.s_min_m;
  if (span_m < options.min_span_m) return refuse("visible tape too short");
  const double coverage = std::min(1.0, agreeing * options.scan_spacing_m / span_m);
  if (coverage < options.min_coverage) return refuse(kSparseEvidence);

  const double shift_m = 0.5 * width_m * tape_side;  // to the left of the edge curve
  const double k = fit.model.curvature_1_m;
  if (1.0 - k * shift_m < 0.2) return refuse("the one edge in view bends too tightly");
  DetectedLine line;
  line.model = fit.model;
  line.model.e_d_m -= shift_m;
  line.model.curvature_1_m = k / (1.0 - k * shift_m);
  line.width_m = width_m;
  line.residual_rms_m = fit.rms_m;
  line.coverage = coverage;
  *completed = border_chords;
  line.s_min_m = 1e9;
  line.s_max_m = -1e9;
  for (size_t i = 0; i < border_chords.size(); ++i) {
    if (side[i] != tape_side) continue;
    Chord& chord = (*completed)[i];
    const Eigen::Vector2d t = fit.model.tangent_at(fit.model.arc_position(chord.a));
    chord.b = chord.a + tape_side * width_m * Eigen::Vector2d(-t.y(), t.x());
    line.chords.push_back(static_cast<int>(i));
    const double s = line.model.arc_position(chord.centre());
    line.s_min_m = std::min(line.s_min_m, s);
    line.s_max_m = std::max(line.s_max_m, s);
  }
  line.clean_chords = line.chords;
  line.points_used = static_cast<int>(line.chords.size());
  // Half the confidence of both edges seen: the centre rests on a width from other frames.
  line.confidence =
      0.5 * std::min(1.0, coverage / 0.6) * std::min(1.0, span_m / options.full_span_m);
  return line;
}

}  // namespace agv::perception
