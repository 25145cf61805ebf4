#pragma once

#include <opencv2/core.hpp>
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
};

struct EdgeScanOptions {
  int margin_px = 8;  // floor samples taken beyond the coarse region on each side
  int flank_px = 0;   // and at least this far (set from the tape width in pixels:
                      // the coarse bar response covers only the tape's core)
  float min_contrast_to_noise = 5.0f;
  int max_dip_px = 0;  // worn spots: dips inside the tape up to this long are crossed
  int step = 1;        // scan every step-th line
};

// Scans one coarse region at full resolution along rows (along_rows) or columns. Every run of
// the region on a scan line is one crossing of the tape: around it, the two places where the
// contrast crosses half-way between the local floor level (each side separately) and the local
// tape level. Half-way crossings of a blurred, symmetric edge sit on the true edge.
std::vector<EdgePair> scan_tape_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                      const TapeRegions& coarse, const TapeRegion& region,
                                      bool along_rows, const EdgeScanOptions& options);

}  // namespace agv::perception
