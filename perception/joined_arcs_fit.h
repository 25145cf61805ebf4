#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <vector>

namespace agv::perception {

// A stretch of tape as guide paths are laid: one arc (or line), or two joined with a common
// tangent at a breakpoint (a line running into an arc, an arc into a line or into another arc).
// Fitted to centre-line points given in a frame whose x axis runs roughly along the tape and
// whose origin is where the answer is wanted, as y(x) = a + b x + k1 x^2 / 2 + (k2 - k1) (x -
// x_b)_+^2 / 2 (the curvature is y'' for the small slopes this frame keeps), the breakpoint x_b
// chosen by the evidence: the two-piece model is kept only when it explains the points better
// than one piece by more than the Bayesian information criterion asks.
struct JoinedArcs {
  double offset_m = 0.0;            // y at x = 0
  double slope = 0.0;               // dy/dx at x = 0
  double curvature_1_m = 0.0;       // curvature at x = 0 (of the piece that holds there)
  double curvature_far_1_m = 0.0;   // curvature of the piece beyond the breakpoint (x > x_b)
  std::optional<double> break_x_m;  // where the curvature changes, if it does in the window
  double rms_m = 0.0;               // residual of the points kept
  int points = 0;
  // Standard deviation of curvature_1_m (options.curvature_sigma; else NaN): the residual
  // variance inflated by the residuals' correlation along x (points seen in overlapping frames
  // share the tape's wear and the floor's texture, which more points do not average out).
  double curvature_sigma_1_m = std::numeric_limits<double>::quiet_NaN();
};

struct JoinedArcsOptions {
  double breakpoint_step_m = 0.004;  // breakpoints tried every this much along x
  double min_piece_m = 0.01;         // each piece must hold at least this much of the points
  double outlier_sigmas = 4.0;       // points this many robust sigmas off are dropped, once
  bool both_sides = true;  // the points must lie on both sides of x = 0 (false: extrapolate)
  bool curvature_sigma = false;  // also work out curvature_sigma_1_m
  bool joint = true;             // false: one piece only (no breakpoint search; cheaper)
};

// Nullopt when fewer than 6 points, or (options.both_sides) they do not span both sides of
// x = 0.
std::optional<JoinedArcs> fit_joined_arcs(const std::vector<Eigen::Vector2d>& points,
                                          const JoinedArcsOptions& options = {});
// The same with each point counting weights[i] times (how many observations it stands for: the
// fused points of the path memory); `points` then counts those observations.
std::optional<JoinedArcs> fit_joined_arcs(const std::vector<Eigen::Vector2d>& points,
                                          const std::vector<double>& weights,
                                          const JoinedArcsOptions& options = {});

}  // namespace agv::perception
