#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "common/line_measurement.h"
#include "control/drive_response.h"
#include "control/error_prediction.h"
#include "control/path_controller.h"

namespace agv::control {

// Bits of TrackerOutput::flags.
enum TrackerFlag : std::uint32_t {
  kLineLost = 1u << 0,           // the newest measurement found no line
  kHolding = 1u << 1,            // tracking the last good estimate while the line is lost
  kStopping = 1u << 2,           // line lost for longer than the hold time: braking to a stop
  kNoFeasibleHorizon = 1u << 3,  // the controller found no N within the limits
  kSaturated = 1u << 4,          // the vehicle limits changed the controller's command
  kNoMeasurementYet = 1u << 5,   // nothing measured since start: the last command is kept
  kNoMeasurements = 1u << 6,     // no measurement arrived this period (camera late or stalled)
  kSlowForCurve = 1u << 7,       // the path speed is lowered for the curvature here or ahead
};

struct TrackerOutput {
  BodyTwist command;  // within the vehicle limits, always
  std::uint32_t flags = 0;
  int horizon_steps = 0;
  bool has_estimate = false;
  TrackingEstimate estimate;  // what the controller acted on (after latency prediction)
};

// Runs a PathController once per period on the newest measurement and makes every command safe:
// a lost line is tracked on the last good estimate for `line_lost_hold_s`, then the vehicle is
// braked to a stop within its acceleration limit and waits until the line is seen again. The
// same holds when measurements stop arriving at all (a stalled camera or perception): after
// `line_lost_hold_s` without any measurement the vehicle stops. With
// latency compensation on, the error is predicted from the frame's time to now with the
// commands already sent, as the drive responds to them (as Nav2 MPPI's model delay and Autoware
// MPC's input delay with its steering model do). Where
// the measurement previews a change of the path's curvature ahead, the curvature fed forward
// changes in the period the vehicle reaches it. On a curve the vehicle must turn at
// v * |curvature|: where that would exceed `curve_turn_fraction` of the yaw-rate limit (the rest
// is left for corrections), the speed along the path is lowered to fit, and it is lowered in time
// for a sharper curve the measurement previews, braking at `curve_decel_fraction` of the
// acceleration limit (v^2 = v_curve^2 + 2 a d).
class LineTracker {
 public:
  struct Options {
    double ts_s = 0.1;
    double path_speed_m_s = 0.3;
    double line_lost_hold_s = 0.3;
    bool latency_compensation = true;
    double curve_turn_fraction = 0.8;  // 0: the path speed is never lowered for a curve
    double curve_decel_fraction = 0.5;
    // How the vehicle's twist follows the commands (its wheels' steer rate, an actuator lag):
    // the latency prediction moves the vehicle as the drive does, not as it is told.
    DriveResponse::Options drive;
  };

  LineTracker(std::unique_ptr<PathController> controller, const VehicleLimits& limits,
              const Options& options, const BodyTwist& initial_command);

  // One control period at now_s. `newest` is the newest measurement that arrived since the
  // previous call, if any.
  TrackerOutput step(const std::optional<LineMeasurement>& newest, double now_s);

  // One control period at now_s of a vehicle told to stop (the run is ending): the command
  // brakes towards standstill within the limits, flagged kStopping.
  TrackerOutput brake(double now_s);

  const PathController& controller() const { return *controller_; }

 private:
  // The path's mean curvature over the coming period (what the controller feeds forward): the
  // measured curvature, or, where the measurement previews a change that the vehicle reaches
  // within the period, the two weighted by the travel on each side of it.
  double coming_curvature_1_m(const LineMeasurement& m, double now_s) const;
  // The highest speed along the path (m/s) at which the vehicle can turn through the curvature
  // here and reach, braking, the curvature the measurement previews: at most the path speed.
  double curve_speed_m_s(const LineMeasurement& m, double now_s) const;
  // Where the previewed curvature change lies now (m ahead of the origin), the vehicle having
  // driven on since the frame; infinite when none is previewed.
  double change_ahead_m(const LineMeasurement& m, double now_s) const;
  // Keeps the command sent at now_s for the latency prediction: the twist the drive makes of it
  // over the coming period.
  void record(double now_s, const BodyTwist& command);

  std::unique_ptr<PathController> controller_;
  VehicleLimits limits_;
  Options options_;
  BodyTwist previous_command_;
  DriveResponse drive_;     // the drive's expected response to the commands sent
  CommandHistory history_;  // ... the twists it makes of them
  std::optional<LineMeasurement> last_good_;
  bool line_lost_ = false;
  bool stopped_tracking_ = false;
  std::optional<double> first_step_s_;
  std::optional<double> last_arrival_s_;  // when the newest measurement (found or not) arrived
  double speed_m_s_;                      // the speed along the path this period
};

}  // namespace agv::control
