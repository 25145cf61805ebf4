#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/line_measurement.h"
#include "perception/camera_model.h"
#include "perception/edge_scan.h"
#include "perception/floor_map.h"
#include "perception/junction.h"
#include "perception/line_set.h"

namespace agv::perception {

// What is known in advance about the tape.
struct TapeHints {
  double width_m = 0.025;              // expected width; 0: unknown (no width check)
  std::optional<cv::Vec3d> color_bgr;  // tape colour; nullopt: found from the image
};

// Everything the estimator saw in one frame, for annotation, plots and tests.
struct LineDetection {
  std::vector<EdgePair> edges;       // pixel edges per scan line
  std::vector<Chord> chords;         // the same on the floor, vehicle frame
  std::vector<DetectedLine> lines;   // every line accepted (up to LineSetOptions::max_lines)
  std::optional<Junction> junction;  // where lines meet, if they do in view
  int followed = -1;                 // index in `lines` of the line reported
  CurveModel followed_model;         // that line, oriented along the travel direction
  std::optional<double> branch_heading_rad;  // the branch chosen, where there was a choice
  BranchChoice branch = BranchChoice::kStraight;  // the way the caller takes at junctions
  std::string rejected_because;              // why no line, when none
  bool tracked = false;      // found from the frame before's line (LineEstimator::track)
  bool one_edge = false;     // from the tape's one edge in view and its known width
  ContrastAxis axis;         // the colour axis the tape was found on
  float floor_noise = 0.0f;  // robust noise of the floor's contrast on that axis
};

// Finds the guide line(s) in a frame and reports the one to follow as (e_theta, e_d, curvature)
// of the vehicle reference point (shared/DESIGN.md), through the camera's floor mapping:
//  1. a linear colour axis (tape colour hint or automatic) turns the frame into contrast; with a
//     history whose tape was found on an axis of the opposite polarity to this frame's, that
//     axis is tried first;
//  2. on a 1/4-size copy, a bar detector tuned to the tape width, a threshold and connected
//     regions say where tape may be;
//  3. along full-resolution rows and columns across each region, the tape's two edges are found
//     to sub-pixel precision at the half-way crossings of the local contrast;
//  4. both edges are mapped to the floor; their midpoint lies on the tape's centre line
//     whatever the perspective (it is the midpoint of points on two parallel curves);
//  5. up to LineSetOptions::max_lines curves (arcs or lines) are fitted robustly through the
//     midpoints, each checked against the tape width, its consistency and the visible length;
//  6. where lines meet, the branch chosen (left, straight, right) gives the line to follow,
//     extrapolated along its curve to the vehicle's foot point.
class LineEstimator {
 public:
  struct Options {
    TapeHints tape;
    int downsample = 4;  // a power of two
    int min_region_area_small_px = 12;
    int max_regions = 4;
    LineSetOptions lines;  // expected width and full span are set from the rest
    EdgeScanOptions scan;
    BranchChoice branch = BranchChoice::kStraight;
    double max_branch_turn_rad = 1.05;  // sharper branches are taken when reached (60 deg)
    // track: scan every track_step-th row or column. Every 10th, not every 8th (2026-12-05, agv
    // bench: perception as the loop runs it 10.8-11.0 -> 11.8-12.2x the baseline; agv evaluate
    // seeds 1-12 1.800 -> 1.656 mm / 0.841 -> 0.727 deg, the median sequence 0.140 -> 0.136 mm;
    // the fork examples with their start and speed moved, runs over 0.5 mm 6 -> 2 of 54; the
    // default run 0.097 -> 0.115 mm). Every 12th: the median sequence 0.148 mm.
    int track_step = 10;
    double track_search_m = 0.02;       // track: the tape may move this much (or a width)
    double track_margin_m = 0.002;      // track: band margin around the moved tape (or 0.1 w)
    bool tracking = true;               // TrackingLineEstimator: track between full searches
    int search_every_frames = 10;       // TrackingLineEstimator: full search at least this often
  };

  LineEstimator(const CameraModel& camera, const Options& options);

  // Measurement of one frame taken at stamp_s (8-bit BGR or grey, the camera's size; any other
  // frame gives line_found = false with the reason in `details`). A configured tape width is a
  // hint: where it finds no line, the frame is searched again for tape of any width (its
  // measured width is in the measurement; the caller can tell the user). `history` (optional):
  // what the frames before followed, kept to through junctions (choose_line). Where no line is
  // found, the history settled a width and followed a line in the last few frames, a tape of
  // that width running out of the image with one edge in view near where it was followed is the
  // line (one_edge_line.h; detection.one_edge).
  LineMeasurement estimate(const cv::Mat& frame, double stamp_s, LineDetection* details = nullptr,
                           const FollowHistory* history = nullptr) const;

  // The same, for a frame that follows `previous` (a detection that found a line): the frame is
  // scanned only where the previous line, widened by a margin, predicts the tape, on the same
  // colour axis, and one fit started from the previous model gives the line, with the same
  // checks as estimate. Much faster; it sees only the line it follows. line_found = false (with
  // the reason) when the tape is not where predicted, when another tape crosses the band (a
  // junction) or the evidence fails a check: the caller then runs estimate.
  LineMeasurement track(const cv::Mat& frame, double stamp_s, const LineDetection& previous,
                        LineDetection* details = nullptr,
                        const FollowHistory* history = nullptr) const;

  const FloorMap& floor_map() const { return *floor_map_; }
  const CameraModel& camera() const { return camera_; }
  const Options& options() const { return options_; }

 private:
  // The reason a frame cannot be measured (size, type), or empty.
  std::string frame_problem(const cv::Mat& frame) const;
  // Appends the edge pairs whose ends map to the floor, with their floor chords.
  void add_chords(const std::vector<EdgePair>& edges, LineDetection* d) const;
  // From the lines found (d.lines not empty): junction, branch choice and the measurement.
  LineMeasurement measurement_of(LineDetection& d, const cv::Mat& frame, double stamp_s,
                                 const FollowHistory* history) const;
  // The line from the tape's one edge in view (estimate's last resort), or nullopt.
  std::optional<LineMeasurement> from_one_edge(const cv::Mat& frame, double stamp_s,
                                               LineDetection* details,
                                               const FollowHistory& history) const;
  // estimate() with the widths of this estimator only.
  LineMeasurement estimate_with_widths(const cv::Mat& frame, double stamp_s, LineDetection* details,
                                       const FollowHistory* history) const;
  // The search for lines once the colour axis is known (steps 2-6 below), on the frame and its
  // 1/downsample copy `small`.
  LineMeasurement search_on_axis(const cv::Mat& frame, const cv::Mat& small,
                                 const ContrastAxis& axis, double stamp_s, LineDetection* detection,
                                 const FollowHistory* history) const;
  // The bars of the ladder: bar_widths_small_px_ without the widest beyond it, if there is one.
  std::vector<double> ladder_bars_small_px() const;
  // search_on_axis with these bars (bar_widths_small_px_ or the ladder's part of it; none: the
  // plateau of tape wider than every bar, see search_on_axis).
  LineMeasurement search_with_bars(const cv::Mat& frame, const cv::Mat& small,
                                   const ContrastAxis& axis,
                                   const std::vector<double>& bars_small_px, double stamp_s,
                                   LineDetection* detection, const FollowHistory* history) const;

  CameraModel camera_;
  Options options_;
  std::shared_ptr<const FloorMap> floor_map_;  // FloorMap::shared
  std::vector<double> bar_widths_small_px_;    // bar detector widths (see find_tape_regions)
  double tape_width_px_ = 0.0;                 // largest expected tape width in full-size pixels
  // Whether the last bar is the widest that fits the view, beyond the ladder's widest
  // (tape_width_px_): searched with only where the ladder's candidate was refused for sparse
  // evidence (the colour axis is chosen with the ladder's).
  bool widest_bar_beyond_ladder_ = false;
  // Without a configured width: tape at least as wide in full-size pixels as the ladder's widest
  // bar is searched for by its plateau too (see search_on_axis); 0 with a configured width.
  double plateau_min_width_px_ = 0.0;
  // With a configured width: the same estimator for tape of any width (the hint's fallback).
  std::shared_ptr<const LineEstimator> any_width_;
};

}  // namespace agv::perception
