#pragma once

#include <Eigen/Core>
#include <optional>

#include "perception/curve_fit.h"

namespace agv::perception {

// A corner as guide paths are laid: the line in, a circular arc tangent to it and to the line
// out, the line out. Given a point of each line where the tape was last (in) and first (out)
// seen, with the tape's direction there (vehicle frame, along the travel), the arc's tangent
// length is the shorter of the two points' distances to where the lines meet (the tape seen on
// that side reaching the arc; the other side's unseen stretch up to the arc straight). Returns the
// piece nearest the vehicle origin as the model of the origin's foot point on it (the arc's
// curvature on the arc, none on the lines); nullopt where the lines do not meet ahead of the
// point in and behind the point out, turn by less than 1 deg or more than 179 deg, or the arc's
// radius is under 0.1 mm (a point seen at the corner itself).
// Where the line in (through in_m along in_heading_rad) and the line out meet: that point's
// distance ahead of in_m along the line in (d_in) and behind out_m along the line out (d_out),
// either signed; nullopt where the lines are parallel.
struct LinesMeet {
  double d_in_m, d_out_m;
};
std::optional<LinesMeet> where_lines_meet(const Eigen::Vector2d& in_m, double in_heading_rad,
                                          const Eigen::Vector2d& out_m, double out_heading_rad);

std::optional<CurveModel> corner_fillet(const Eigen::Vector2d& in_m, double in_heading_rad,
                                        const Eigen::Vector2d& out_m, double out_heading_rad);

}  // namespace agv::perception
