#pragma once

#include <limits>
#include <string>

#include "common/body_twist.h"
#include "control/vehicle_limits.h"

namespace agv::control {

// The controller's best knowledge of the tracking error at the time the command is computed.
struct TrackingEstimate {
  double e_theta_rad = 0.0;
  double e_d_m = 0.0;
  double curvature_1_m = 0.0;  // path curvature at the foot point, left turn positive
  double age_s = 0.0;          // age of the measurement it came from (before prediction)
  // Arc length from the foot point to the end of the path (negative past it); infinite when
  // the input cannot see the end (a camera: the tape's end shows as line loss).
  double remaining_m = std::numeric_limits<double>::infinity();
  // The tape ahead (preview): the curvature changes to curvature_ahead_1_m this far ahead of the
  // foot point, now; infinite when no change is known.
  double curvature_change_m = std::numeric_limits<double>::infinity();
  double curvature_ahead_1_m = 0.0;
};

// What a controller needs to know besides the error, once per control period.
struct ControlContext {
  double ts_s = 0.1;
  double path_speed_m_s = 0.3;  // v_tau: speed along the path
  BodyTwist previous_command;   // the command sent last period
  VehicleLimits limits;
};

struct ControllerOutput {
  BodyTwist command;
  int horizon_steps = 0;             // finite-step controllers: N used this period
  bool no_feasible_horizon = false;  // no N in range met the limits; the command is saturated
};

// A path-tracking law from (e_theta, e_d) to a body twist, called once per control period.
// The caller (LineTracker) handles line loss and applies the vehicle limits afterwards.
class PathController {
 public:
  virtual ~PathController() = default;
  virtual ControllerOutput update(const TrackingEstimate& estimate,
                                  const ControlContext& context) = 0;
  // Forget internal state (a manoeuvre under way, integrators): called when tracking restarts.
  virtual void reset() = 0;
  virtual std::string name() const = 0;
  // Whether the law feeds the curvature forward as a turn rate (true), so that a drive slow to
  // make a new turn rate needs it early, or plans on the path's geometry itself (DWA's roll-outs
  // against the curve ahead), which the curvature fed early would move.
  virtual bool feeds_curvature_forward() const { return true; }
};

}  // namespace agv::control
