#pragma once

#include <limits>

namespace agv {

// What perception reports about the guide line in one frame, in the conventions of
// shared/DESIGN.md: e_theta = vehicle yaw - path tangent yaw (CCW positive), e_d = signed
// distance of the vehicle reference point from the path (positive: vehicle left of the path).
struct LineMeasurement {
  double stamp_s = 0.0;     // time the frame was taken
  bool line_found = false;  // false: the other fields carry no line
  double e_theta_rad = 0.0;
  double e_d_m = 0.0;
  double curvature_1_m = 0.0;   // path curvature at the foot point (left turn positive)
  double confidence = 0.0;      // 0 (no evidence) .. 1 (strong evidence)
  int points_used = 0;          // centre-line points that support the fit
  double tape_width_m = 0.0;    // measured width of the tape
  int lines_seen = 0;           // guide lines in view (junctions, forks, crossings: more than 1)
  bool junction_ahead = false;  // lines meet in view
  // The errors come from the line in view carried back to the vehicle (no remembered tape under
  // it yet), not from the tape under the vehicle.
  bool extrapolated = false;
  // No line in view: the errors come from the remembered tape under the vehicle alone (the
  // camera, ahead of the vehicle, has passed a corner, or the line was refused where the frame
  // still shows the tape where it is remembered), placed by the odometry.
  bool remembered_only = false;
  // The tape ahead (preview): the curvature changes to curvature_ahead_1_m this far ahead of the
  // foot point, along the tape; infinite when no change is seen.
  double curvature_change_m = std::numeric_limits<double>::infinity();
  double curvature_ahead_1_m = 0.0;
  // Pose input only (controller.input: pose): arc length from the foot point to the end of
  // the path, negative past it. A camera cannot see it: infinite.
  double path_remaining_m = std::numeric_limits<double>::infinity();
};

}  // namespace agv
