#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "perception/curve_fit.h"

namespace agv::perception {

// One crossing of the tape by a scan line, mapped to the floor (vehicle frame): the points on
// the tape's two edges. Their midpoint lies on the tape's centre line.
struct Chord {
  Eigen::Vector2d a, b;
  Eigen::Vector2d centre() const { return 0.5 * (a + b); }
};

// One guide line found in a frame.
struct DetectedLine {
  CurveModel model;             // e_d, heading (e_theta = -heading) and curvature at the vehicle
  double width_m = 0.0;         // median width across the tape
  double width_spread_m = 0.0;  // 10-90 % range of the widths
  double residual_rms_m = 0.0;
  double s_min_m = 0.0, s_max_m = 0.0;  // extent of the evidence along the curve
  int points_used = 0;
  double coverage = 0.0;  // evidence per scan line over the span (1: every line crossed)
  double confidence = 0.0;
  std::vector<int> chords;        // indices of the chords that support it
  std::vector<int> clean_chords;  // of those, the ones with both edges on this tape
  bool open_start = false;        // the evidence runs into the image border at s_min / s_max:
  bool open_end = false;          // the tape goes on beyond what is seen
  // ... into the image's left or right border there (the tape turns out of the view sideways)
  bool open_start_at_side = false, open_end_at_side = false;
};

struct LineSetOptions {
  int max_lines = 4;  // a crossing of tape laid in pieces needs more than 2
  int min_points = 12;
  double min_visible_length_m = 0.03;
  double expected_width_m = 0.025;  // 0: unknown
  double width_tolerance = 0.35;    // accepted |measured - expected| / expected
  // Without an expected width: the widths guide tape comes in (8-150 mm), with room for the
  // measurement's error. A line of no clean chord has no width and is not checked.
  double min_width_m = 0.006, max_width_m = 0.2;
  double width_spread_tolerance = 0.3;  // accepted 10-90 % width range / median width
  double min_inlier_fraction = 0.5;     // of the chords near the line
  double min_confidence = 0.1;
  double full_span_m = 0.15;       // evidence this long counts as fully seen
  double scan_spacing_m = 0.0004;  // floor distance between scan lines (one chord each)
  double min_coverage = 0.25;      // chords per scan line along the span: tape gives ~1
  CurveFitOptions fit;
};

// A path's curvature may change within view (a straight running into an arc, an arc into a
// straight); the model that holds at the vehicle is then the one of the evidence nearest to it.
// Fits the nearer half of a line's chords (by distance from the vehicle origin) and returns that
// model, oriented as the line's, when the whole line's model misfits that nearer evidence (by
// more than 1 mm and three times the near fit's own residuals) and their curvatures differ by
// more than `sigmas` of the near fit's uncertainty; nullopt when the whole-line model stands.
std::optional<CurveModel> near_model_if_different(const std::vector<Chord>& chords,
                                                  const DetectedLine& line,
                                                  const LineSetOptions& options,
                                                  double sigmas = 4.0);

// The line that `prior` (a line of the frame before, of measured width prior_width_m) has become
// in this frame's chords, which come from scans where the prior predicted the tape: one fit on
// the chords' edges started from the prior, then the same checks as extract_lines. Nullopt
// (with the reason in `rejections`) when the chords do not make that line.
std::optional<DetectedLine> track_line(const std::vector<Chord>& chords, const CurveModel& prior,
                                       double prior_width_m, const LineSetOptions& options,
                                       std::vector<std::string>* rejections = nullptr);

// The rejection of a line whose evidence covers too little of its length (what the edges of a
// tape wider than the scan windows give: chords only where a window happened to reach both).
inline constexpr const char* kSparseEvidence = "evidence too sparse along the line";

// Up to max_lines lines through the chords' centres, found one after the other (the best
// supported first), each checked for width, width consistency, length and straightness of
// evidence; of two readings of one tape (the curve of one runs within a tenth of a tape width of
// the other's over all its evidence) the better supported is kept.
// `rejections` (optional) receives why candidates were turned down.
std::vector<DetectedLine> extract_lines(const std::vector<Chord>& chords,
                                        const LineSetOptions& options,
                                        std::vector<std::string>* rejections = nullptr);

}  // namespace agv::perception
