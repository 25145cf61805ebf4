#include "perception/line_set.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

namespace agv::perception {
namespace {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + i, values.end());
  return values[i];
}

// The direction `model` runs in where its evidence lies (the mean of `points` where `mask`): the
// `forward` that fits to the same evidence are oriented by. Not its tangent at the vehicle's
// foot point: around a tight arc that point may lie half a turn from the evidence, where the
// curve runs the other way, and the edges' sides fitted with it swap (real frames,
// datasets/lines/lrp_floor_curves line_4, R 0.1 m, with the camera 0.2 m ahead of the origin:
// the tape refused as of varying width). Nor its tangent at the middle of the evidence's arc
// positions, which jump by a turn where the evidence straddles the point opposite the foot.
Eigen::Vector2d direction_at_evidence(const CurveModel& model,
                                      const std::vector<Eigen::Vector2d>& points,
                                      const std::vector<bool>& mask) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!mask[i]) continue;
    sum += points[i];
    ++count;
  }
  if (count == 0) return model.tangent();
  return model.prepared().unit_direction_at(sum / count);
}

// Width of the tape at a chord: the chord's extent across the curve (`prepared`: its model's).
double chord_width(const Chord& chord, const CurveModel::Prepared& prepared) {
  const Eigen::Vector2d ahead = prepared.unit_direction_at(chord.centre());
  return std::abs(Eigen::Vector2d(-ahead.y(), ahead.x()).dot(chord.a - chord.b));
}

}  // namespace

std::optional<CurveModel> near_model_if_different(const std::vector<Chord>& chords,
                                                  const DetectedLine& line,
                                                  const LineSetOptions& options, double sigmas) {
  std::vector<double> distances;
  distances.reserve(line.clean_chords.size());
  for (int index : line.clean_chords) distances.push_back(chords[index].centre().norm());
  if (static_cast<int>(distances.size()) < 2 * options.min_points) return std::nullopt;
  const double median = quantile(distances, 0.5);
  std::vector<Eigen::Vector2d> centres;
  centres.reserve(chords.size());
  for (const Chord& chord : chords) centres.push_back(chord.centre());
  std::vector<bool> near(chords.size(), false);
  for (int index : line.clean_chords) near[index] = chords[index].centre().norm() <= median;
  // Cheap test first: the whole model fits the near evidence to its own residual level.
  {
    std::vector<double> misfit;
    misfit.reserve(line.clean_chords.size());
    const CurveModel::Prepared whole = line.model.prepared();
    for (size_t i = 0; i < chords.size(); ++i) {
      if (near[i]) misfit.push_back(std::abs(whole.signed_distance(centres[i])));
    }
    if (quantile(misfit, 0.5) <= std::max(0.001, 3.0 * line.residual_rms_m)) return std::nullopt;
  }
  CurveFitOptions fit_options = options.fit;
  fit_options.forward = direction_at_evidence(line.model, centres, near);
  const CurveFit fit = fit_curve_robust(centres, fit_options, &near);
  if (!fit.ok || fit.inlier_count < options.min_points) return std::nullopt;
  if (fit.s_max_m - fit.s_min_m < std::max(options.min_visible_length_m, 0.05)) return std::nullopt;
  const double difference = std::abs(fit.model.curvature_1_m - line.model.curvature_1_m);
  if (difference <= sigmas * fit.curvature_sigma_1_m + 0.05) return std::nullopt;
  std::vector<double> misfit;
  const CurveModel::Prepared whole = line.model.prepared();
  for (size_t i = 0; i < chords.size(); ++i) {
    if (fit.inliers[i]) misfit.push_back(std::abs(whole.signed_distance(centres[i])));
  }
  if (quantile(misfit, 0.5) <= std::max(0.001, 3.0 * fit.rms_m)) return std::nullopt;
  return fit.model.oriented_like(line.model, fit.model.point_at(0.5 * (fit.s_min_m + fit.s_max_m)));
}

namespace {

// The chords as the fits see them.
struct ChordSet {
  std::vector<Eigen::Vector2d> centres, firsts, seconds;
};

// The side offsets of each chord's edges for an edge fit: half_width_m on the side of `curve`
// where the edge lies.
void side_offsets(const ChordSet& c, const CurveModel& curve, double half_width_m,
                  std::vector<double>* first_offsets, std::vector<double>* second_offsets) {
  const CurveModel::Prepared prepared = curve.prepared();
  first_offsets->resize(c.firsts.size());
  second_offsets->resize(c.seconds.size());
  for (size_t i = 0; i < c.firsts.size(); ++i) {
    (*first_offsets)[i] =
        prepared.signed_distance(c.firsts[i]) >= 0.0 ? half_width_m : -half_width_m;
    (*second_offsets)[i] =
        prepared.signed_distance(c.seconds[i]) >= 0.0 ? half_width_m : -half_width_m;
  }
}

// A line's model from the chords marked in `available`: a first fit on the midpoints finds the
// candidate and the tape's width; a fit on the edges (each on its side of the curve, at half
// the width) decides which chords crossed one clean piece of tape (both edges on it); the model
// then comes from the clean chords' midpoints, where errors common to both edges (blur,
// compression, wear) cancel, unless clean chords cover too little of the evidence (a fork
// merging over much of the view), when the edges carry it. `alternative` (fork hypothesis)
// receives, where many chords had only one good edge, the model fitted on the clean chords and
// the other edge of each of those.
struct Candidate {
  CurveFit fit;
  std::vector<std::uint8_t> edge_inliers;  // of the edge fit, per chord
};

std::optional<Candidate> fit_candidate(const ChordSet& c, const std::vector<Chord>& chords,
                                       const std::vector<bool>& available,
                                       const LineSetOptions& options,
                                       std::optional<Candidate>* alternative) {
  const CurveFit first = fit_curve_robust(c.centres, options.fit, &available);
  if (!first.ok || first.inlier_count < options.min_points) return std::nullopt;
  std::vector<double> widths;
  const CurveModel::Prepared first_curve = first.model.prepared();
  for (size_t i = 0; i < chords.size(); ++i) {
    if (first.inliers[i]) widths.push_back(chord_width(chords[i], first_curve));
  }
  // The edges lie at half the tape's measured width (real tape differs from its nominal width
  // by millimetres; the configured width is checked afterwards).
  const double half_width_m = 0.5 * quantile(widths, 0.5);
  std::vector<double> first_offsets, second_offsets;
  side_offsets(c, first.model, half_width_m, &first_offsets, &second_offsets);
  CurveFitOptions edge_options = options.fit;
  edge_options.forward = direction_at_evidence(first.model, c.centres, first.inliers);
  const EdgeObservations edges{&c.firsts, &c.seconds, &first_offsets, &second_offsets};
  CurveFit edge_fit = fit_curve_robust(c.centres, edge_options, &available, &edges);
  if (!edge_fit.ok || edge_fit.inlier_count < options.min_points) return Candidate{first, {}};
  // The width measured across the first fit is off where that fit was (a tight arc, one-edge
  // chords of a tape leaving the image): a tenth of a millimetre on the edges of one side only
  // bends the curve by ~0.1 1/m over a 0.1 m view. Measure it again across the edge fit, with
  // the sides it gives, and refit from there.
  {
    std::vector<double> edge_widths;
    const CurveModel::Prepared edge_curve = edge_fit.model.prepared();
    for (size_t i = 0; i < chords.size(); ++i) {
      if (edge_fit.edge_inliers[i] == 3) edge_widths.push_back(chord_width(chords[i], edge_curve));
    }
    std::vector<double> firsts_again, seconds_again;
    const double half_width_again_m = 0.5 * quantile(edge_widths, 0.5);
    side_offsets(c, edge_fit.model, half_width_again_m, &firsts_again, &seconds_again);
    // Refit when a side or the width moved by more than 20 micrometres.
    bool moved = std::abs(half_width_again_m - half_width_m) > 2e-5;
    for (size_t i = 0; i < chords.size() && !moved; ++i) {
      moved = (firsts_again[i] > 0) != (first_offsets[i] > 0) ||
              (seconds_again[i] > 0) != (second_offsets[i] > 0);
    }
    if (static_cast<int>(edge_widths.size()) >= options.min_points && moved) {
      std::swap(first_offsets, firsts_again);  // `edges` points at these
      std::swap(second_offsets, seconds_again);
      const CurveFit again =
          fit_curve_robust(c.centres, edge_options, &available, &edges, &edge_fit.model);
      if (again.ok && again.inlier_count >= options.min_points) {
        edge_fit = again;
      } else {  // keep the offsets the edge fit was made with
        std::swap(first_offsets, firsts_again);
        std::swap(second_offsets, seconds_again);
      }
    }
  }

  // Clean: both edges within max(1 mm, 3 robust sigmas) of where the tape's edges should be.
  const double clean_band_m = std::max(0.001, 3.0 * edge_fit.rms_m);
  const CurveModel::Prepared edge_curve = edge_fit.model.prepared();
  const double edge_middle_s_m = 0.5 * (edge_fit.s_min_m + edge_fit.s_max_m);
  std::vector<bool> clean(chords.size(), false);
  int clean_count = 0, one_edge_count = 0;
  double clean_s_min = 1e9, clean_s_max = -1e9;
  for (size_t i = 0; i < chords.size(); ++i) {
    if (edge_fit.edge_inliers[i] == 1 || edge_fit.edge_inliers[i] == 2) ++one_edge_count;
    if (edge_fit.edge_inliers[i] != 3) continue;
    if (std::abs(edge_curve.signed_distance(c.firsts[i]) - first_offsets[i]) > clean_band_m ||
        std::abs(edge_curve.signed_distance(c.seconds[i]) - second_offsets[i]) > clean_band_m) {
      continue;
    }
    clean[i] = true;
    ++clean_count;
    const double s = edge_curve.arc_position_near(c.centres[i], edge_middle_s_m);
    clean_s_min = std::min(clean_s_min, s);
    clean_s_max = std::max(clean_s_max, s);
  }
  Candidate candidate{edge_fit, edge_fit.edge_inliers};
  CurveFitOptions centre_options = options.fit;
  centre_options.forward = direction_at_evidence(edge_fit.model, c.centres, edge_fit.inliers);
  const bool clean_covers =
      clean_s_max - clean_s_min >= 0.7 * (edge_fit.s_max_m - edge_fit.s_min_m);
  const bool few_one_edge = one_edge_count * 10 < edge_fit.inlier_count;  // no fork, no merging
  if (clean_count >= options.min_points && clean_covers && !edge_fit.is_line && few_one_edge) {
    // An arc: its edges lie exactly on concentric circles at half the width, but a chord's
    // midpoint is not on the centre circle where the scan line crosses the tape obliquely (it
    // falls inside by up to a millimetre for tight arcs). Fit the clean chords' edges.
    CurveFit arc_fit = fit_curve_robust(c.centres, centre_options, &clean, &edges);
    if (arc_fit.ok && arc_fit.inlier_count >= options.min_points) {
      for (size_t i = 0; i < chords.size(); ++i) {
        if (edge_fit.inliers[i]) arc_fit.inliers[i] = true;
      }
      candidate.fit = arc_fit;
    }
  } else if (clean_count >= options.min_points && clean_covers) {
    // A straight tape: midpoints lie exactly on its centre line, and errors common to both edges
    // cancel in them. Usually (clean tape) the clean chords are exactly the first fit's inliers:
    // that fit is the midpoint fit on them already.
    bool same = true;
    for (size_t i = 0; i < chords.size() && same; ++i)
      same = clean[i] == (first.inliers[i] && available[i]);
    CurveFit centre_fit = same ? first : fit_curve_robust(c.centres, centre_options, &clean);
    if (centre_fit.ok && centre_fit.inlier_count >= options.min_points) {
      // One-edge chords belong to this tape too, though they do not shape the model.
      for (size_t i = 0; i < chords.size(); ++i) {
        if (edge_fit.inliers[i]) centre_fit.inliers[i] = true;
      }
      candidate.fit = centre_fit;
    }
  }
  if (alternative && one_edge_count >= std::max(options.min_points, edge_fit.inlier_count / 5)) {
    // Fork hypothesis: the clean chords and, of each one-edge chord, the edge that did not fit.
    std::vector<double> alt_first(chords.size(), std::nan("")),
        alt_second(chords.size(), std::nan(""));
    std::vector<bool> alt_mask(chords.size(), false);
    for (size_t i = 0; i < chords.size(); ++i) {
      const std::uint8_t e = edge_fit.edge_inliers[i];
      if (e == 0 || !available[i]) continue;
      alt_mask[i] = true;
      if (e == 3 || e == 2) alt_first[i] = e == 3 ? first_offsets[i] : first_offsets[i];
      if (e == 3 || e == 1) alt_second[i] = second_offsets[i];
      if (e == 1) alt_first[i] = std::nan("");
      if (e == 2) alt_second[i] = std::nan("");
    }
    const EdgeObservations alt_edges{&c.firsts, &c.seconds, &alt_first, &alt_second};
    const CurveFit alt = fit_curve_robust(c.centres, edge_options, &alt_mask, &alt_edges);
    if (alt.ok && alt.inlier_count >= options.min_points)
      *alternative = Candidate{alt, alt.edge_inliers};
  }
  return candidate;
}

// The chords as the fits see them; `usable` marks those not much longer than the tape is wide
// (a longer one runs along the tape or through a junction: its midpoint is on no centre line).
ChordSet chord_set(const std::vector<Chord>& chords, const LineSetOptions& options,
                   std::vector<bool>* usable) {
  ChordSet c;
  const double max_chord_m = options.expected_width_m > 0.0 ? 3.0 * options.expected_width_m : 0.3;
  usable->clear();
  usable->reserve(chords.size());
  for (std::vector<Eigen::Vector2d>* v : {&c.centres, &c.firsts, &c.seconds})
    v->reserve(chords.size());
  for (const Chord& chord : chords) {
    c.centres.push_back(chord.centre());
    c.firsts.push_back(chord.a);
    c.seconds.push_back(chord.b);
    usable->push_back((chord.a - chord.b).norm() <= max_chord_m);
  }
  return c;
}

// Whether the fit's evidence runs inside the tape of one of the `accepted` lines (the median
// of its chords' centres within half that tape's width of its centre line).
bool runs_inside(const CurveFit& fit, const ChordSet& c,
                 const std::vector<DetectedLine>& accepted) {
  for (const DetectedLine& other : accepted) {
    const CurveModel::Prepared other_curve = other.model.prepared();
    std::vector<double> apart;
    for (size_t i = 0; i < c.centres.size(); ++i)
      if (fit.inliers[i]) apart.push_back(std::abs(other_curve.signed_distance(c.centres[i])));
    if (quantile(apart, 0.5) < 0.5 * std::max(other.width_m, 0.005)) return true;
  }
  return false;
}

// Checks a candidate's evidence and makes it a line, or says why not (in `rejections`).
// `accepted`: the lines accepted before, `explained_by_others` marks their chords (empty: none).
std::optional<DetectedLine> evaluate(const Candidate& candidate, const std::vector<Chord>& chords,
                                     const ChordSet& c, const LineSetOptions& options,
                                     const std::vector<DetectedLine>& accepted,
                                     const std::vector<bool>& explained_by_others,
                                     std::vector<std::string>* rejections) {
  auto reject = [&](const std::string& why) {
    if (rejections) rejections->push_back(why);
  };
  const CurveFit& fit = candidate.fit;
  DetectedLine line;
  line.model = fit.model;
  line.residual_rms_m = fit.rms_m;
  line.s_min_m = fit.s_min_m;
  line.s_max_m = fit.s_max_m;
  line.points_used = fit.inlier_count;
  const CurveModel::Prepared curve = fit.model.prepared();
  std::vector<double> widths;
  widths.reserve(fit.inlier_count);
  line.chords.reserve(fit.inlier_count);
  line.clean_chords.reserve(fit.inlier_count);
  for (size_t i = 0; i < chords.size(); ++i) {
    if (!fit.inliers[i]) continue;
    line.chords.push_back(static_cast<int>(i));
    // Width and clean chords: both edges on this tape (not one edge at a fork).
    if (candidate.edge_inliers.empty() || candidate.edge_inliers[i] == 3) {
      line.clean_chords.push_back(static_cast<int>(i));
      widths.push_back(chord_width(chords[i], curve));
    }
  }
  line.width_m = quantile(widths, 0.5);
  line.width_spread_m = quantile(widths, 0.9) - quantile(widths, 0.1);
  const double span_m = fit.s_max_m - fit.s_min_m;
  // How much of the evidence near this line it explains: chords whose centre lies within a
  // tape width of it but are not inliers speak against it, unless they are a line's accepted
  // before, alongside this one's evidence, and this one does not run inside that line's tape
  // (at a tangential fork the other leg runs within a width of this one for 0.2 m: agv evaluate
  // seed 4, sequence 3, the way straight on refused for 13 frames and the branch followed; the
  // pieces of one S-bend meet end to end, not alongside; a texture's alignment within wide tape
  // runs inside it: seed 9, sequence 6).
  int near = 0, near_unexplained = 0;
  for (size_t i = 0; i < chords.size(); ++i) {
    if (std::abs(curve.signed_distance(c.centres[i])) >= std::max(line.width_m, 0.005)) continue;
    ++near;
    // A chord of a line accepted before, where this one's evidence runs alongside it.
    bool explained = !fit.inliers[i] && !explained_by_others.empty() && explained_by_others[i];
    if (explained) {
      const double s = curve.arc_position_near(c.centres[i], 0.5 * (fit.s_min_m + fit.s_max_m));
      explained = s >= fit.s_min_m && s <= fit.s_max_m;
    }
    if (!explained) ++near_unexplained;
  }
  double inlier_fraction = static_cast<double>(fit.inlier_count) / std::max(1, near);
  if (inlier_fraction < options.min_inlier_fraction && !runs_inside(fit, c, accepted))
    inlier_fraction = static_cast<double>(fit.inlier_count) / std::max(1, near_unexplained);
  if (span_m < options.min_visible_length_m) {
    reject("visible tape too short");
    return std::nullopt;
  }
  // Tape leaves evidence all along (even interrupted tape, in pieces); a chance alignment of
  // texture blobs has it only here and there.
  line.coverage = std::min(1.0, fit.inlier_count * options.scan_spacing_m / span_m);
  if (line.coverage < options.min_coverage) {
    reject(kSparseEvidence);
    return std::nullopt;
  }
  if (inlier_fraction < options.min_inlier_fraction) {
    reject("edge points do not lie on one line");
    return std::nullopt;
  }
  if (options.expected_width_m <= 0.0 && !widths.empty() &&
      (line.width_m < options.min_width_m || line.width_m > options.max_width_m)) {
    char why[128];
    std::snprintf(why, sizeof(why), "width %.1f mm is no tape's (%.0f-%.0f mm)", 1e3 * line.width_m,
                  1e3 * options.min_width_m, 1e3 * options.max_width_m);
    reject(why);
    return std::nullopt;
  }
  double width_error = 0.0;
  if (options.expected_width_m > 0.0) {
    width_error = std::abs(line.width_m - options.expected_width_m) / options.expected_width_m;
    if (width_error > options.width_tolerance) {
      char why[128];
      std::snprintf(why, sizeof(why), "tape width %.1f mm does not match the configured %.1f mm",
                    1e3 * line.width_m, 1e3 * options.expected_width_m);
      reject(why);
      return std::nullopt;
    }
  }
  if (line.width_spread_m > options.width_spread_tolerance * line.width_m + 0.0005) {
    reject("tape width varies along the line");
    return std::nullopt;
  }
  // Confidence: every factor is 1 for a clean, fully visible tape of the right width.
  const double span_factor = std::min(1.0, span_m / options.full_span_m);
  const double width_factor =
      options.expected_width_m > 0.0 ? std::exp(-0.5 * std::pow(width_error / 0.15, 2)) : 1.0;
  const double residual_factor = 1.0 / (1.0 + std::pow(fit.rms_m / 0.0005, 2));
  const double coverage_factor = std::min(1.0, line.coverage / 0.6);
  line.confidence = std::min(1.0, inlier_fraction) * span_factor * width_factor * residual_factor *
                    coverage_factor;
  if (line.confidence < options.min_confidence) {
    reject("evidence too weak");
    return std::nullopt;
  }
  return line;
}

// Whether `line` is another reading of the tape of `other`: its curve, over its evidence, runs
// within kSameTape of a tape width of `other`'s centre line (either way along it: a model's
// orientation is arbitrary), where `other` has evidence too. At a fork whose legs still overlap,
// the one-edge chords of a leg read once as a line and once as an arc (agv evaluate seed 12,
// sequence 3: 62 mm tape, its branch read twice within 1.4 mm; the two crossed, a junction was
// found between them and the branch followed for the way right). A branch leaving tangentially
// parts from the way straight on by more (scenarios/fork_right.yaml: 11 mm of 25 mm tape over
// its evidence when first seen as a line of its own; dropped at half a width, it was missed and
// the junction with it: 7.4 mm RMS).
bool second_reading_of(const DetectedLine& line, const DetectedLine& other, double width_m) {
  constexpr int kSamples = 9;
  constexpr double kSameTape = 0.1;
  const CurveModel::Prepared curve = other.model.prepared();
  for (int k = 0; k < kSamples; ++k) {
    const double s = line.s_min_m + (line.s_max_m - line.s_min_m) * k / (kSamples - 1);
    const Eigen::Vector2d p = line.model.point_at(s);
    if (std::abs(curve.signed_distance(p)) > kSameTape * width_m) return false;
    const double s_other = curve.arc_position_near(p, 0.5 * (other.s_min_m + other.s_max_m));
    if (s_other < other.s_min_m - 0.5 * width_m || s_other > other.s_max_m + 0.5 * width_m)
      return false;
  }
  return true;
}

}  // namespace

std::vector<DetectedLine> extract_lines(const std::vector<Chord>& chords,
                                        const LineSetOptions& options,
                                        std::vector<std::string>* rejections) {
  std::vector<DetectedLine> lines;
  auto reject = [&](const std::string& why) {
    if (rejections) rejections->push_back(why);
  };
  std::vector<bool> available;
  const ChordSet c = chord_set(chords, options, &available);
  std::vector<bool> explained(chords.size(), false);  // inliers of the lines accepted
  auto accept = [&](DetectedLine line) {
    for (int i : line.chords) explained[i] = true;
    lines.push_back(std::move(line));
  };

  for (int attempt = 0;
       attempt < 2 * options.max_lines && static_cast<int>(lines.size()) < options.max_lines;
       ++attempt) {
    const int remaining = static_cast<int>(std::count(available.begin(), available.end(), true));
    if (remaining < options.min_points) {
      if (lines.empty()) reject("too few edge points on the tape");
      break;
    }
    std::optional<Candidate> alternative;
    const std::optional<Candidate> candidate =
        fit_candidate(c, chords, available, options, &alternative);
    if (!candidate) {
      if (lines.empty()) reject("edge points do not lie on one line");
      break;
    }
    for (size_t i = 0; i < chords.size(); ++i) {
      if (candidate->fit.inliers[i]) available[i] = false;  // used, accepted or not
    }
    if (auto line = evaluate(*candidate, chords, c, options, lines, explained, rejections))
      accept(std::move(*line));
    // A fork seen where its two tapes still overlap: the other reading of the one-edge chords is
    // a line of its own when it leaves in another direction.
    if (alternative && static_cast<int>(lines.size()) < options.max_lines) {
      const CurveModel& a = candidate->fit.model;
      const CurveModel& b = alternative->fit.model;
      const Eigen::Vector2d far_a = a.point_at(candidate->fit.s_max_m);
      const double apart_m = std::abs(b.signed_distance(far_a));
      // Apart by the end of the evidence: a fork (a wear pattern's alternative differs by a
      // millimetre or two).
      if (apart_m > std::max(0.003, 0.2 * options.expected_width_m)) {
        if (auto line = evaluate(*alternative, chords, c, options, lines, explained, rejections))
          accept(std::move(*line));
      }
    }
    // No line yet, and the best-supported curve left was a chance alignment of floor texture,
    // its evidence under half as dense along it as a tape's may be: what is left has less support
    // still (tape-free frames tried up to 2 max_lines such curves, 1-2 ms each).
    const double span_m = candidate->fit.s_max_m - candidate->fit.s_min_m;
    if (lines.empty() && span_m > 0.0 &&
        candidate->fit.inlier_count * options.scan_spacing_m < 0.5 * options.min_coverage * span_m)
      break;
  }
  // A line that no chord crosses cleanly (each has one edge on another tape) is a reading of
  // tapes that overlap; where another line shows clean tape, it is that overlap read once more
  // (at a fork's split, the outer edges of both legs make a phantom tape a width aside).
  const bool any_clean = std::any_of(lines.begin(), lines.end(), [&](const DetectedLine& line) {
    return static_cast<int>(line.clean_chords.size()) >= options.min_points;
  });
  if (any_clean)
    std::erase_if(lines, [](const DetectedLine& line) { return line.clean_chords.empty(); });
  // Of two readings of one tape, the better supported stays.
  std::vector<bool> second(lines.size(), false);
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = 0; j < lines.size() && !second[i]; ++j) {
      if (j == i || second[j] || lines[j].confidence < lines[i].confidence) continue;
      const double width_m = std::max(
          {lines[i].width_m, lines[j].width_m, options.expected_width_m, options.min_width_m});
      second[i] = second_reading_of(lines[i], lines[j], width_m);
    }
  }
  for (size_t i = lines.size(); i-- > 0;) {
    if (second[i]) lines.erase(lines.begin() + static_cast<long>(i));
  }
  return lines;
}

std::optional<DetectedLine> track_line(const std::vector<Chord>& chords, const CurveModel& prior,
                                       double prior_width_m, const LineSetOptions& options,
                                       std::vector<std::string>* rejections) {
  std::vector<bool> usable;
  const ChordSet c = chord_set(chords, options, &usable);
  // The vehicle moved since the prior: its offset and turn show as a residual of the chord
  // centres growing linearly along the curve, d = a + b s. Removing it (least squares with one
  // round of Cauchy weights) brings the prior close enough for the fit's inlier band.
  const CurveModel::Prepared prior_curve = prior.prepared();
  std::vector<Eigen::Vector2d> samples;  // (s, d)
  for (size_t i = 0; i < chords.size(); ++i) {
    if (usable[i])
      samples.emplace_back(prior_curve.arc_position(c.centres[i]),
                           prior_curve.signed_distance(c.centres[i]));
  }
  if (static_cast<int>(samples.size()) < options.min_points) {
    if (rejections) rejections->push_back("too few edge points on the tracked tape");
    return std::nullopt;
  }
  Eigen::Vector2d ab = Eigen::Vector2d::Zero();
  double scale_m = 1.0;  // first round unweighted
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix2d ata = Eigen::Matrix2d::Zero();
    Eigen::Vector2d atd = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& sd : samples) {
      const double r = (sd.y() - ab[0] - ab[1] * sd.x()) / scale_m;
      const double w = 1.0 / (1.0 + r * r);
      const Eigen::Vector2d row(1.0, sd.x());
      ata += w * row * row.transpose();
      atd += w * row * sd.y();
    }
    ab = ata.ldlt().solve(atd);
    scale_m = std::max(0.001, 0.5 * prior_width_m);
  }
  CurveModel initial = prior;
  initial.e_d_m -= ab[0];
  initial.heading_rad += ab[1];
  // Edges at half the prior's width, each on its side of the moved prior.
  std::vector<double> first_offsets, second_offsets;
  side_offsets(c, initial, 0.5 * prior_width_m, &first_offsets, &second_offsets);
  CurveFitOptions fit_options = options.fit;
  fit_options.forward = direction_at_evidence(initial, c.centres, usable);
  const EdgeObservations edges{&c.firsts, &c.seconds, &first_offsets, &second_offsets};
  const CurveFit fit = fit_curve_robust(c.centres, fit_options, &usable, &edges, &initial);
  if (!fit.ok || fit.inlier_count < options.min_points) {
    if (rejections) rejections->push_back("edge points do not lie on the tracked line");
    return std::nullopt;
  }
  return evaluate(Candidate{fit, fit.edge_inliers}, chords, c, options, {}, {}, rejections);
}

}  // namespace agv::perception
