#include "perception/line_estimator.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "perception/contrast_axis.h"
#include "perception/nearest_piece.h"
#include "perception/one_edge_line.h"
#include "perception/tape_regions.h"

namespace agv::perception {
namespace {

LineMeasurement not_found(double stamp_s, const std::string& reason, LineDetection* details) {
  if (details) details->rejected_because = reason;
  LineMeasurement m;
  m.stamp_s = stamp_s;
  return m;
}

// Two colour axes whose weights point the same way in colour (within 90 deg: neighbouring
// chroma directions both separate a coloured tape from its floor; the opposite polarity does
// not).
bool same_colour_direction(const ContrastAxis& a, const ContrastAxis& b) {
  return a.weights.dot(b.weights) > 0.0f;
}

// Drops the lines whose width is unlike the tape followed in the frames before (history's
// width memory); returns the reason when none is left, else an empty string.
std::string drop_lines_unlike_the_tape(std::vector<DetectedLine>* lines,
                                       const FollowHistory* history) {
  if (!history || lines->empty()) return "";
  const std::optional<double> settled_m = history->width.settled_width_m();
  if (!settled_m) return "";
  const double first_width_m = lines->front().width_m;
  std::erase_if(*lines,
                [&](const DetectedLine& line) { return history->width.unlike(line.width_m); });
  if (!lines->empty()) return "";
  char why[120];
  std::snprintf(why, sizeof(why), "tape width %.1f mm unlike the %.1f mm tape seen so far",
                1e3 * first_width_m, 1e3 * *settled_m);
  return why;
}

// A region of one tape's width spreads across less than this many times its mean width (its
// second moments across; a band's is about 1, a corner's or a junction's far more).
constexpr double kBandSpread = 1.5;

// Whether the line `strip` is a strip along one edge of the wider tape `tape` (what bars
// narrower than that tape answer to): its middle within the tape, running along it (within
// kMaxTurn_rad), and more than kMinShare of its width (the plateau of two pieces of narrower tape
// overlapping at a fork or a corner is up to twice as wide as either, each of which is a line of
// its own).
bool strip_along(const DetectedLine& strip, const DetectedLine& tape) {
  constexpr double kMaxTurn_rad = 0.2, kMinShare = 0.55;
  const double middle_s = 0.5 * (strip.s_min_m + strip.s_max_m);
  const Eigen::Vector2d middle = strip.model.point_at(middle_s);
  const Eigen::Vector2d along = tape.model.tangent_at(tape.model.arc_position(middle));
  return std::abs(tape.model.signed_distance(middle)) <= 0.5 * tape.width_m &&
         std::abs(along.dot(strip.model.tangent_at(middle_s))) >= std::cos(kMaxTurn_rad) &&
         strip.width_m >= kMinShare * tape.width_m;
}

// Coefficients (c0, c1, c2) of the quadratic in l through (l_i, x_i), least squares; a line when
// the evidence spans too few lines to show a bend. Solved in a centred, scaled variable.
Eigen::Vector3d quadratic_fit(const std::vector<Eigen::Vector2d>& lx, bool with_bend) {
  double lo = 1e18, hi = -1e18;
  for (const Eigen::Vector2d& p : lx) {
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
  }
  const double origin = 0.5 * (lo + hi), scale = std::max(1.0, 0.5 * (hi - lo));
  // Normal equations from the power sums of t = (l - o) / S.
  double t_power[5] = {0, 0, 0, 0, 0}, y_t_power[3] = {0, 0, 0};
  for (const Eigen::Vector2d& p : lx) {
    const double t = (p.x() - origin) / scale, t2 = t * t;
    t_power[0] += 1.0;
    t_power[1] += t;
    t_power[2] += t2;
    t_power[3] += t2 * t;
    t_power[4] += t2 * t2;
    y_t_power[0] += p.y();
    y_t_power[1] += p.y() * t;
    y_t_power[2] += p.y() * t2;
  }
  Eigen::Matrix3d ata;
  ata << t_power[0], t_power[1], t_power[2], t_power[1], t_power[2], t_power[3], t_power[2],
      t_power[3], t_power[4];
  Eigen::Vector3d atx(y_t_power[0], y_t_power[1], y_t_power[2]);
  if (!with_bend) {
    ata.row(2).setZero();
    ata.col(2).setZero();
    ata(2, 2) = 1.0;
    atx[2] = 0.0;
  }
  const Eigen::Vector3d c = ata.ldlt().solve(atx);
  // c0 + c1 (l - o) / S + c2 (l - o)^2 / S^2, expanded in l.
  const double s2 = scale * scale;
  return {c[0] - c[1] * origin / scale + c[2] * origin * origin / s2,
          c[1] / scale - 2.0 * c[2] * origin / s2, c[2] / s2};
}

// Where the previous frame's followed line predicts the tape: its clean chords' edges along the
// scan direction most of them used, extended by 15 % of the image beyond the evidence.
std::optional<PredictedBand> band_of(const LineDetection& previous, const cv::Size& image) {
  if (previous.followed < 0 || previous.followed >= static_cast<int>(previous.lines.size()))
    return std::nullopt;
  const DetectedLine& line = previous.lines[previous.followed];
  int rows = 0;
  for (int index : line.clean_chords) rows += previous.edges[index].along_rows ? 1 : 0;
  PredictedBand band;
  band.along_rows = 2 * rows >= static_cast<int>(line.clean_chords.size());
  std::vector<Eigen::Vector2d> firsts, seconds;
  double l_min = 1e18, l_max = -1e18;
  for (int index : line.clean_chords) {
    const EdgePair& e = previous.edges[index];
    if (e.along_rows != band.along_rows) continue;
    const double l = band.along_rows ? e.first_px.y : e.first_px.x;
    firsts.emplace_back(l, band.along_rows ? e.first_px.x : e.first_px.y);
    seconds.emplace_back(l, band.along_rows ? e.second_px.x : e.second_px.y);
    l_min = std::min(l_min, l);
    l_max = std::max(l_max, l);
  }
  if (firsts.size() < 8) return std::nullopt;
  const int line_count = band.along_rows ? image.height : image.width;
  const bool with_bend = l_max - l_min >= 0.2 * line_count;
  band.first = quadratic_fit(firsts, with_bend);
  band.second = quadratic_fit(seconds, with_bend);
  const double extend = 0.15 * line_count;
  band.first_line = std::max(0, static_cast<int>(std::floor(l_min - extend)));
  band.last_line = std::min(line_count - 1, static_cast<int>(std::ceil(l_max + extend)));
  return band;
}

}  // namespace

LineEstimator::LineEstimator(const CameraModel& camera, const Options& options)
    : camera_(camera), options_(options), floor_map_(FloorMap::shared(camera)) {
  // Tape width in downsampled pixels at the middle of the view; without a configured width,
  // widths from 8 to 128 mm in steps of 2x (a bar detector answers to about 0.7-1.4 times its
  // width), those that fit the view: a bar and its flanks (twice its width) across at most the
  // image's shorter side (a wider bar answers to the lens's vignetting and the light's
  // gradient, not to tape).
  const double footprint_m = std::max(1e-6, floor_map_->typical_footprint_m());
  const double widest_m =
      std::min(camera.intrinsics().width_px, camera.intrinsics().height_px) * footprint_m / 2.0;
  std::vector<double> widths_m;
  if (options_.tape.width_m > 0.0) {
    widths_m = {options_.tape.width_m};
  } else {
    for (double width_m = 0.008; width_m <= 0.13; width_m *= 2.0)
      if (width_m <= widest_m || widths_m.empty()) widths_m.push_back(width_m);
  }
  tape_width_px_ = *std::max_element(widths_m.begin(), widths_m.end()) / footprint_m;
  // A tape between the last bar that fits and the widest that fits (a low camera: 90 mm tape
  // across nearly half the view) is answered to by neither: the widest that fits too, for a
  // second search (search_on_axis; the scans' flanks stay those of the ladder: wider ones reach
  // other tape at junctions).
  if (options_.tape.width_m <= 0.0 && widest_m < 0.128 && widest_m > 1.4 * widths_m.back()) {
    widths_m.push_back(widest_m);
    widest_bar_beyond_ladder_ = true;
  }
  for (double width_m : widths_m)
    bar_widths_small_px_.push_back(width_m / footprint_m / options_.downsample);
  if (options_.tape.width_m <= 0.0) plateau_min_width_px_ = tape_width_px_;
  options_.lines.expected_width_m = options_.tape.width_m;
  if (options.tape.width_m > 0.0) {
    Options any_width = options;
    any_width.tape.width_m = 0.0;
    any_width_ = std::make_shared<const LineEstimator>(camera, any_width);
  }
  // Pieces of tape laid end to end are rarely collinear to better than a tenth of their width:
  // the inlier band grows with the width so that such a seam does not split a line.
  const double reference_width_m = options_.tape.width_m > 0.0 ? options_.tape.width_m : 0.025;
  options_.lines.fit.inlier_threshold_m =
      std::max(options_.lines.fit.inlier_threshold_m, 0.12 * reference_width_m);
  options_.lines.full_span_m = floor_map_->view_radius_m();
  options_.lines.scan_spacing_m = footprint_m * std::max(1, options_.scan.step);
}

LineMeasurement LineEstimator::estimate(const cv::Mat& frame, double stamp_s,
                                        LineDetection* details,
                                        const FollowHistory* history) const {
  const LineMeasurement m = estimate_with_widths(frame, stamp_s, details, history);
  if (m.line_found) return m;
  if (any_width_) {
    LineDetection any;
    const LineMeasurement found =
        any_width_->estimate_with_widths(frame, stamp_s, details ? &any : nullptr, history);
    if (found.line_found) {
      if (details) *details = std::move(any);
      return found;
    }
  }
  if (history && frame_problem(frame).empty()) {
    if (auto found = from_one_edge(frame, stamp_s, details, *history)) return *found;
  }
  return m;  // the reason the (configured) width gave
}

std::optional<LineMeasurement> LineEstimator::from_one_edge(const cv::Mat& frame, double stamp_s,
                                                            LineDetection* details,
                                                            const FollowHistory& history) const {
  // Only the tape just followed, of a settled width, on the axis it was found on.
  constexpr int kMaxFramesLost = 5;
  const std::optional<double> width_m = history.width.last_settled_width_m();
  if (!width_m || !history.followed || !history.axis ||
      history.frames_without_line > kMaxFramesLost)
    return std::nullopt;
  const int step = std::max(1, options_.track_step / 2);
  // The axis maps the floor to about 0 and the tape to about 1.
  constexpr float kMinContrast = 0.4f;
  LineDetection d;
  std::vector<Chord> border_chords;
  for (bool along_rows : {true, false}) {
    for (const EdgePair& pair :
         scan_border_edges(frame, *history.axis, along_rows, step, kMinContrast, options_.scan)) {
      const auto seen = pair.first_at_border ? pair.second_px : pair.first_px;
      const auto border = pair.first_at_border ? pair.first_px : pair.second_px;
      const auto a = floor_map_->at(seen.x, seen.y);
      const auto b = floor_map_->at(border.x, border.y);
      if (!a || !b) continue;
      d.edges.push_back(pair);
      border_chords.push_back({*a, *b});
    }
  }
  OneEdgeOptions one;
  one.scan_spacing_m = floor_map_->typical_footprint_m() * step;
  one.full_span_m = options_.lines.full_span_m;
  const CurveModel& followed = *history.followed;
  std::optional<DetectedLine> line =
      line_from_one_edge(border_chords, *width_m, followed.tangent(), one, &d.chords, nullptr);
  if (!line) return std::nullopt;
  // Near the line followed: within half a width of it where the edge is seen, and turned from it
  // by no more than the vehicle turns in a few frames.
  constexpr double kMaxTurn_rad = 0.3;
  const double s_mid = 0.5 * (line->s_min_m + line->s_max_m);
  const Eigen::Vector2d mid = line->model.point_at(s_mid);
  const Eigen::Vector2d t_new = line->model.tangent_at(s_mid);
  const Eigen::Vector2d t_old = followed.tangent_at(followed.arc_position(mid));
  if (std::abs(followed.signed_distance(mid)) > 0.5 * *width_m ||
      std::abs(t_new.dot(t_old)) < std::cos(kMaxTurn_rad))
    return std::nullopt;
  d.lines.push_back(std::move(*line));
  d.axis = *history.axis;
  d.one_edge = true;
  LineMeasurement m = measurement_of(d, frame, stamp_s, &history);
  if (details) *details = std::move(d);
  return m;
}

LineMeasurement LineEstimator::estimate_with_widths(const cv::Mat& frame, double stamp_s,
                                                    LineDetection* details,
                                                    const FollowHistory* history) const {
  LineDetection local;
  LineDetection& d = details ? *details : local;
  d = LineDetection{};
  if (const std::string problem = frame_problem(frame); !problem.empty())
    return not_found(stamp_s, problem, &d);

  // Block means over ds x ds pixels; in 2x steps, which OpenCV does three times faster than
  // one 4x step, with the same result.
  cv::Mat small = frame;
  const int ds = options_.downsample;
  for (int factor = 1; factor < ds; factor *= 2) {
    cv::resize(small, small, cv::Size(small.cols / 2, small.rows / 2), 0, 0, cv::INTER_AREA);
  }
  // Where the axis this frame suggests points another way in colour than the one the tape
  // followed was last found on, the remembered axis alone is searched: on a blotchy floor the
  // blotches' polarity can win, and between the two legs of a fork of dark tape the floor is a
  // light strip of about a tape's width. A tape of another colour is taken up once the axis is
  // forgotten (FollowHistory::kForgetAxisAfterFrames frames without a line).
  // Without a remembered axis, where the frame's best axis gives no line, the next best that
  // points another way in colour is searched too (a glare spot can stand out more than narrow
  // dark tape).
  const std::vector<ContrastAxis> axes =
      choose_contrast_axes(small, options_.tape.color_bgr, ladder_bars_small_px(), 2);
  const std::optional<ContrastAxis> remembered = history ? history->axis : std::nullopt;
  if (remembered && (axes.empty() || !same_colour_direction(axes.front(), *remembered)))
    return search_on_axis(frame, small, *remembered, stamp_s, &d, history);
  if (axes.empty()) return not_found(stamp_s, "flat frame: nothing differs from the floor", &d);
  const LineMeasurement m = search_on_axis(frame, small, axes.front(), stamp_s, &d, history);
  if (m.line_found) return m;
  // The next axis: with one remembered (of the same colour direction as the frame's best, which
  // a glare spot in view may have turned towards white), that one; else the frame's next best.
  std::optional<ContrastAxis> next;
  if (remembered) {
    if (remembered->weights != axes.front().weights || remembered->offset != axes.front().offset)
      next = *remembered;
  } else if (axes.size() >= 2) {
    next = axes[1];
  }
  if (!next) return m;
  LineDetection second;
  const LineMeasurement other = search_on_axis(frame, small, *next, stamp_s, &second, history);
  if (!other.line_found) return m;  // the best axis's reason
  d = std::move(second);
  return other;
}

LineMeasurement LineEstimator::search_on_axis(const cv::Mat& frame, const cv::Mat& small,
                                              const ContrastAxis& axis, double stamp_s,
                                              LineDetection* detection,
                                              const FollowHistory* history) const {
  // The widest bar beyond the ladder only where the ladder's bars give no line for the sparse
  // evidence of a tape wider than they are (on narrower tape it answers to the two legs of a
  // fork near their split as to one wide tape; on frames without tape, a second chance at
  // floor texture).
  LineMeasurement m =
      search_with_bars(frame, small, axis, ladder_bars_small_px(), stamp_s, detection, history);
  if (!m.line_found && widest_bar_beyond_ladder_ && detection->rejected_because == kSparseEvidence)
    m = search_with_bars(frame, small, axis, bar_widths_small_px_, stamp_s, detection, history);
  // Tape wider than every bar (a low camera over 100 mm tape: half the view) answers to them
  // only next to its edges, one edge a region (where they give a line, it is a strip along one
  // edge): its plateau, the contrast itself, is the region then. Only lines as wide as the
  // ladder's widest bar are taken from it, where the bars give none, or, before the tape's width
  // has settled, where theirs is such a strip or unlike the width last settled (below). Once it
  // has settled a strip is unlike the tape and dropped; a line the bars give then is the tape,
  // and a plateau there is more often two pieces of it overlapping (a fork's legs, a corner's)
  // than one tape.
  if (plateau_min_width_px_ <= 0.0) return m;
  if (m.line_found && history && history->width.settled_width_m()) return m;
  LineDetection plateau;
  const LineMeasurement wide = search_with_bars(frame, small, axis, {}, stamp_s, &plateau, history);
  if (!wide.line_found) return m;  // the bars' reason
  if (m.line_found) {
    const DetectedLine& bars_line = detection->lines[detection->followed];
    const DetectedLine& plateau_line = plateau.lines[plateau.followed];
    // ... or where the width settled before (lines of other widths since have unsettled it: a
    // fork's overlap) and theirs is unlike it while the plateau's is that width: a band between a
    // hard shadow's edge across wide tape and a tape edge (agv evaluate seed 18, sequence 4: 250
    // mm / 60 deg off), not two pieces of the tape overlapping (seed 28, sequence 11: a plateau
    // 147 mm wide at a fork, against 80 mm settled).
    const std::optional<double> last_m =
        history ? history->width.last_settled_width_m() : std::nullopt;
    const bool unlike_the_tape =
        last_m && history->width.unlike_last_settled(bars_line.width_m) &&
        std::abs(plateau_line.width_m - *last_m) <= TapeWidthMemory::kTolerance * *last_m;
    if (!strip_along(bars_line, plateau_line) && !unlike_the_tape) return m;
  }
  *detection = std::move(plateau);
  return wide;
}

std::vector<double> LineEstimator::ladder_bars_small_px() const {
  return {bar_widths_small_px_.begin(),
          bar_widths_small_px_.end() - (widest_bar_beyond_ladder_ ? 1 : 0)};
}

LineMeasurement LineEstimator::search_with_bars(const cv::Mat& frame, const cv::Mat& small,
                                                const ContrastAxis& axis,
                                                const std::vector<double>& bars_small_px,
                                                double stamp_s, LineDetection* detection,
                                                const FollowHistory* history) const {
  LineDetection& d = *detection;
  d = LineDetection{};
  const int ds = options_.downsample;
  const TapeRegions coarse =
      find_tape_regions(small, axis, ds, bars_small_px, options_.min_region_area_small_px);
  if (coarse.regions.empty()) return not_found(stamp_s, "no tape-like region", &d);
  d.axis = axis;
  d.floor_noise = coarse.floor_noise;

  // The bar response covers at least the tape's middle half: 0.6 of a width beyond it reaches
  // past the edges onto the floor.
  const int regions = std::min<int>(options_.max_regions, static_cast<int>(coarse.regions.size()));
  const bool plateau = bars_small_px.empty();
  for (int r = 0; r < regions; ++r) {
    const TapeRegion& region = coarse.regions[r];
    // The plateau of one tape, not of a junction's pieces (an L, a Y).
    if (plateau && (region.width_px < plateau_min_width_px_ ||
                    region.spread_px >= kBandSpread * region.width_px))
      continue;
    // A single band (long, one tape wide) is crossed best by scan lines across it; anything
    // else (curves, corners, junctions) is scanned both ways. Without a configured width, a band
    // is as wide across as its area says, and where the region is no band its own width (area
    // over length: an upper bound for a corner or a crossing) is the widest tape it can hold.
    const bool configured = options_.tape.width_m > 0.0;
    const bool band = region.length_px > 4.0 * region.width_px &&
                      (configured ? region.width_px < 1.6 * tape_width_px_
                                  : region.spread_px < kBandSpread * region.width_px);
    const double width_px = plateau              ? region.width_px
                            : configured || band ? tape_width_px_
                                                 : std::min(tape_width_px_, 1.5 * region.width_px);
    // Dips (worn spots) are crossed up to a quarter of the tape's width; without a configured
    // width, of the region's own (a band's tape may be the widest there is, but a dip as long as
    // a quarter of that crosses a coarse floor texture's gaps onto blotches as bright as tape).
    const double dip_width_px =
        configured || plateau ? width_px : std::min(tape_width_px_, 1.5 * region.width_px);
    EdgeScanOptions scan = options_.scan;
    scan.flank_px = std::max(scan.flank_px, static_cast<int>(std::ceil(0.6 * width_px)));
    scan.max_dip_px = std::max(scan.max_dip_px, static_cast<int>(0.25 * dip_width_px));
    const bool rows_first = std::abs(region.direction.y) >= std::abs(region.direction.x);
    for (bool along_rows : {true, false}) {
      if (band && along_rows != rows_first) continue;
      add_chords(scan_tape_edges(frame, axis, coarse, region, along_rows, scan), &d);
    }
  }

  std::vector<std::string> rejections;
  d.lines = extract_lines(d.chords, options_.lines, &rejections);
  if (plateau) {
    // As wide as the ladder's widest bar, and as the tape followed so far where its width has
    // settled (not up to two tapes, as where pieces of it overlap: the bars' lines there).
    const double min_width_m = plateau_min_width_px_ * floor_map_->typical_footprint_m();
    const std::optional<double> settled_m =
        history ? history->width.settled_width_m() : std::nullopt;
    std::erase_if(d.lines, [&](const DetectedLine& line) {
      return line.width_m < min_width_m ||
             (settled_m &&
              std::abs(line.width_m - *settled_m) > TapeWidthMemory::kTolerance * *settled_m);
    });
  }
  if (d.lines.empty())
    return not_found(stamp_s, rejections.empty() ? "no line" : rejections.front(), &d);
  if (const std::string unlike = drop_lines_unlike_the_tape(&d.lines, history); !unlike.empty())
    return not_found(stamp_s, unlike, &d);
  return measurement_of(d, frame, stamp_s, history);
}

LineMeasurement LineEstimator::track(const cv::Mat& frame, double stamp_s,
                                     const LineDetection& previous, LineDetection* details,
                                     const FollowHistory* history) const {
  LineDetection local;
  LineDetection& d = details ? *details : local;
  d = LineDetection{};
  d.tracked = true;
  if (const std::string problem = frame_problem(frame); !problem.empty())
    return not_found(stamp_s, problem, &d);
  std::optional<PredictedBand> band = band_of(previous, frame.size());
  if (!band) return not_found(stamp_s, "no line in the frame before to track", &d);
  const DetectedLine& prior = previous.lines[previous.followed];
  const double footprint_m = floor_map_->typical_footprint_m();
  band->step = std::max(1, options_.track_step);
  band->min_contrast = options_.scan.min_contrast_to_noise * std::max(previous.floor_noise, 0.01f);
  EdgeScanOptions scan = options_.scan;
  scan.max_dip_px = std::max(scan.max_dip_px, static_cast<int>(0.25 * tape_width_px_));
  // First where the tape went (a coarse search on a few lines), then a narrow band around it.
  band = recentre_band(frame, previous.axis, *band,
                       std::max(options_.track_search_m, prior.width_m) / footprint_m, scan);
  if (!band) return not_found(stamp_s, "the tracked tape is no longer where it was", &d);
  band->margin_px = std::max(options_.track_margin_m, 0.1 * prior.width_m) / footprint_m;
  PredictedScanStats stats;
  const std::vector<EdgePair> edges =
      scan_predicted_edges(frame, previous.axis, *band, scan, &stats);
  d.axis = previous.axis;
  d.floor_noise = previous.floor_noise;
  if (stats.covered > std::max(2, stats.windows / 20))
    return not_found(stamp_s, "another tape crosses the tracked band", &d);
  add_chords(edges, &d);
  LineSetOptions lines = options_.lines;
  lines.scan_spacing_m = footprint_m * band->step;
  std::vector<std::string> rejections;
  // The prior as the frame before saw it (not its near-part model, which is a local correction).
  std::optional<DetectedLine> line =
      track_line(d.chords, prior.model, prior.width_m, lines, &rejections);
  if (!line) return not_found(stamp_s, rejections.empty() ? "no line" : rejections.front(), &d);
  // Many chords with one edge only on the tape: another tape runs into it (a fork's branch
  // still overlapping it), which only the full search sees.
  if (10 * line->clean_chords.size() < 7 * line->chords.size())
    return not_found(stamp_s, "another tape joins or leaves the tracked one", &d);
  d.lines.push_back(std::move(*line));
  if (const std::string unlike = drop_lines_unlike_the_tape(&d.lines, history); !unlike.empty())
    return not_found(stamp_s, unlike, &d);
  return measurement_of(d, frame, stamp_s, history);
}

void LineEstimator::add_chords(const std::vector<EdgePair>& edges, LineDetection* d) const {
  // The map's entries asked for a few pairs ahead: after a frame is rendered or read they have
  // left the nearer caches, and a tracked frame's 60 pairs waited for them one by one (agv
  // bench: 9.9 us a frame, 3.7 us with the map in cache).
  constexpr size_t kAhead = 8;
  auto prefetch_pair = [&](size_t i) {
    if (i >= edges.size()) return;
    floor_map_->prefetch(edges[i].first_px.x, edges[i].first_px.y);
    floor_map_->prefetch(edges[i].second_px.x, edges[i].second_px.y);
  };
  for (size_t i = 0; i < kAhead; ++i) prefetch_pair(i);
  for (size_t i = 0; i < edges.size(); ++i) {
    prefetch_pair(i + kAhead);
    const EdgePair& pair = edges[i];
    const auto a = floor_map_->at(pair.first_px.x, pair.first_px.y);
    const auto b = floor_map_->at(pair.second_px.x, pair.second_px.y);
    if (!a || !b) continue;
    d->edges.push_back(pair);
    d->chords.push_back({*a, *b});
  }
}

std::string LineEstimator::frame_problem(const cv::Mat& frame) const {
  const CameraIntrinsics& intrinsics = camera_.intrinsics();
  if (frame.empty()) return "empty frame";
  if (frame.cols != intrinsics.width_px || frame.rows != intrinsics.height_px)
    return "frame size differs from the camera's";
  if (frame.type() != CV_8UC3 && frame.type() != CV_8UC1) return "frame is not 8-bit BGR or grey";
  return "";
}

LineMeasurement LineEstimator::measurement_of(LineDetection& d, const cv::Mat& frame,
                                              double stamp_s, const FollowHistory* history) const {
  // Where the evidence of each line ends: at the image border the tape goes on unseen.
  const double border_px = 0.04 * std::min(frame.cols, frame.rows);
  // Whether the evidence ending at p runs into the border (*open), and into the left or right
  // border (*at_side); a point outside the image is at the border but at no side.
  auto border_at = [&](const Eigen::Vector2d& p, bool* open, bool* at_side) {
    const auto pixel = camera_.floor_to_pixel(p);
    *at_side = pixel && (pixel->x < border_px || pixel->x > frame.cols - 1 - border_px);
    *open = !pixel || *at_side || pixel->y < border_px || pixel->y > frame.rows - 1 - border_px;
  };
  for (DetectedLine& line : d.lines) {
    border_at(line.model.point_at(line.s_min_m), &line.open_start, &line.open_start_at_side);
    border_at(line.model.point_at(line.s_max_m), &line.open_end, &line.open_end_at_side);
  }
  // A branch is a piece of tape leaving the junction by more than a tape width (less is the
  // overlap of a corner), or running out of view once clear of the crossing tape. The width is
  // the configured one, else the widest measured (the lines are pieces of one tape).
  double width_m = options_.tape.width_m;
  if (!(width_m > 0.0))
    for (const DetectedLine& line : d.lines) width_m = std::max(width_m, line.width_m);
  d.junction = find_junction(d.lines, width_m, std::max(0.01, width_m), 0.6 * width_m);
  const FollowedLine followed =
      choose_line(d.lines, d.junction, options_.branch, options_.max_branch_turn_rad, history);
  d.followed = followed.line;
  d.followed_model = followed.model;
  d.branch_heading_rad = followed.branch_heading_rad;
  d.branch = options_.branch;
  if (const auto near = near_model_if_different(d.chords, d.lines[followed.line], options_.lines)) {
    // The near model runs as the line's model, which followed.model is, or reversed (one curve:
    // their directions at the origin's foot point are the same or opposite).
    const bool same_way =
        d.lines[followed.line].model.tangent().dot(followed.model.tangent()) >= 0.0;
    d.followed_model = same_way ? *near : near->reversed();
  }
  if (const auto piece = nearest_piece(d.chords, d.lines[followed.line], d.followed_model))
    d.followed_model = *piece;

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
