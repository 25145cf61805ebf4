#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "perception/contrast_axis.h"
#include "perception/tape_regions.h"

namespace agv::perception {

// The two edges of the tape on one scan line (an image row or column), to sub-pixel precision.
// "first" is the edge at the lower coordinate along the scan line.
struct EdgePair {
  cv::Point2f first_px;
  cv::Point2f second_px;
  float contrast = 0.0f;  // tape level minus floor level on this scan line
  bool along_rows = true;
  // The tape runs beyond the image border on this scan line (scan_border_edges): that "edge" is
  // the border pixel, not the tape's edge.
  bool first_at_border = false, second_at_border = false;
};

struct EdgeScanOptions {
  int margin_px = 8;  // floor samples taken beyond the coarse region on each side
  int flank_px = 0;   // and at least this far (set from the tape width in pixels:
                      // the coarse bar response covers only the tape's core)
  // An edge pair counts where the tape stands out by this many times the floor's spread at the
  // coarse bar's scale (texture included; the line checks reject what texture alone gives).
  float min_contrast_to_noise = 3.0f;
  int max_dip_px = 0;  // worn spots: dips inside the tape up to this long are crossed
  int step = 1;        // scan every step-th line
};

// Scans one coarse region at full resolution along rows (along_rows) or columns. Every run of
// the region on a scan line is one crossing of the tape: around it, the two places where the
// contrast crosses half-way between the floor's and the tape's levels right next to that edge
// (each edge separately). Half-way crossings of a blurred, symmetric edge sit on the true edge.
// A window that ends on the tape (the run held only part of its width) is widened once. Dips
// up to max_dip_px are crossed (worn spots), except, on a textured floor (floor noise 0.05 tape
// contrasts or more), where the crossing's edge beyond a dip does not line up with the edges the
// neighbouring scan lines agree on and the edge before it does: the dip was a gap of floor
// between the tape and a blob as bright as it.
std::vector<EdgePair> scan_tape_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                      const TapeRegions& coarse, const TapeRegion& region,
                                      bool along_rows, const EdgeScanOptions& options);

// Where the tape is expected in a frame, from the frame before (tracking): on scan lines
// first_line, first_line + step, ... up to last_line (image rows when along_rows, else
// columns), its two edges at coordinates along the line given by quadratics in the line index,
// c[0] + c[1] l + c[2] l^2. The tape may have moved by margin_px since. The contrast axis maps
// the floor to about 0 and the tape to about 1.
struct PredictedBand {
  bool along_rows = true;
  int first_line = 0, last_line = -1, step = 1;
  Eigen::Vector3d first = Eigen::Vector3d::Zero(), second = Eigen::Vector3d::Zero();
  double margin_px = 8.0;
  float min_contrast = 0.1f;  // on the contrast axis

  std::pair<double, double> edges_at(int line) const;  // predicted first, second edge
};

// Moves a band onto where the tape is in this frame (the vehicle moved since the band was
// predicted): on `lines` lines spread over the band, the tape is searched within
// search_margin_px of the prediction; the shift of its centre, a linear function of the line
// index fitted robustly, moves both edges. Nullopt when fewer than half the lines find tape.
std::optional<PredictedBand> recentre_band(const cv::Mat& frame, const ContrastAxis& axis,
                                           const PredictedBand& band, double search_margin_px,
                                           const EdgeScanOptions& options, int lines = 9);

// Scans each line of the band for the tape's two edges, within the predicted run widened by
// the margin (and floor samples beyond it), like scan_tape_edges. Lines whose window leaves the
// image, or where no tape stands out, give no pair; neither does a line where the tape runs
// beyond the window (a crossing tape, or one that moved too far).
// `stats` (optional) receives how many lines had their window in the image, and on how many
// of them tape reached the window's end (covered: another tape crosses or joins the band).
struct PredictedScanStats {
  int windows = 0;
  int covered = 0;
};
std::vector<EdgePair> scan_predicted_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                           const PredictedBand& band,
                                           const EdgeScanOptions& options,
                                           PredictedScanStats* stats = nullptr);

// Scan lines (every step-th image row when along_rows, else column) on which the tape runs out
// of the image at one end (or leaves too little floor there to measure its edge against: under
// 2 * side samples, side = max(3, margin_px / 2)): from that border the contrast stays on the
// tape (above half-way, about 0.5 on the axis; dips up to max_dip_px crossed) until one edge,
// beyond which at least
// 2 * side floor samples lie in the image. That edge is placed where the profile crosses
// half-way between the tape's and the floor's levels right next to it (as scan_tape_edges
// places an edge); the pair's other end is the border pixel, flagged. A line whose both ends lie
// on tape, or whose tape beside the edge stands out from the floor by less than min_contrast,
// gives no pair. Unlike scan_tape_edges, nothing says the tape is whole: one edge is all a tape
// wider than the part of the view it leaves shows.
std::vector<EdgePair> scan_border_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                        bool along_rows, int step, float min_contrast,
                                        const EdgeScanOptions& options);

}  // namespace agv::perception
