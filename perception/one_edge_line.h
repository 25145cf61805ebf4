#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "perception/line_set.h"

namespace agv::perception {

struct OneEdgeOptions {
  double inlier_threshold_m = 0.0015;  // a sharp edge scatters by tenths of a millimetre
  int min_points = 12;
  double min_span_m = 0.05;
  double min_coverage = 0.5;           // edge points per scan line along the span
  double min_same_side = 0.9;          // of the inliers, those with the tape on the usual side
  double max_visible_fraction = 1.15;  // visible part of the tape across / its width (p90)
  double scan_spacing_m = 0.002;       // floor distance between the scan lines
  double full_span_m = 0.15;           // evidence this long counts as fully seen
};

// A tape wider than the part of the view it leaves on one side shows one edge only; the other
// lies beyond the image border. With the tape's width known (measured in the frames before),
// that edge and the side the tape lies on give its centre line: the edge curve moved across by
// half the width towards the tape (a curve of curvature k moved by d to its left keeps its
// centre and heading and has curvature k / (1 - k d); the vehicle origin, at signed distance e_d
// from the edge, is at e_d - d from the moved curve).
//
// border_chords[i]: a is the edge seen, b where the tape leaves the image on that scan line
// (floor, vehicle frame). The edge points are fitted robustly with one curve oriented along
// `forward`; the fit must have min_points inliers over min_span_m at min_coverage, the tape on
// one side of it (min_same_side) and no wider in view than the tape (max_visible_fraction).
// Returns the line (its chords, all clean, are indices into `completed`: border_chords with the
// inliers' far edge put at the tape's width across from the seen one), or nullopt with the
// reason in `why`.
std::optional<DetectedLine> line_from_one_edge(const std::vector<Chord>& border_chords,
                                               double width_m, const Eigen::Vector2d& forward,
                                               const OneEdgeOptions& options,
                                               std::vector<Chord>* completed, std::string* why);

}  // namespace agv::perception
