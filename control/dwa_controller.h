#pragma once

#include <limits>
#include <memory>
#include <numbers>

#include "control/path.h"
#include "control/path_controller.h"

namespace agv::control {

// Dynamic window approach for path tracking, plain or with seed 002's improvements. Every
// period it samples (v, w) inside the window that the vehicle limits (speed, acceleration over
// one period), the stopping distance to the path's end (v <= sqrt(2 a remaining)) and a
// progress floor (v >= min_speed_fraction * path speed, where the window reaches it) allow,
// rolls each out at constant (v, w) for horizon_s, or for half the time the vehicle needs to
// bring its yaw rate from the limit back to zero (w_max / alpha_max) where that is longer (a
// shorter roll-out cannot see that a turn started now must be taken back), and scores it by
//   G = w_heading * head + w_clearance * clearance + w_speed * speed + w_area * area,
// each term normalised to [0, 1] by its range over the candidates (seed 002's sigma; a share
// of the sum, the classic form, lets a term that varies little among the candidates drown the
// others):
//   head:      pi - |angle between the rolled-out heading and the direction to the next path
//              point| (the path point lookahead_m beyond the foot of the rollout's end), less
//              the path's own bend from that foot to the point (the angle its chord makes with
//              the tangent): zero on the path and along it, on arcs too, where the uncorrected
//              angle leads the vehicle inside the curve by about lookahead^2 / (2 R);
//   clearance: distance left to the path's end after the rollout, capped at clearance_cap_m
//              (the scenarios have no obstacles; the end of the path is the one thing to stop
//              for);
//   speed:     closeness of v to the path speed;
//   area:      (improved only) the coverage area of the rolled-out front and rear wheel tracks
//              against the path (seed 002 Fig. 4/5) per metre travelled, that is the mean of
//              |front offset| + |rear offset| over the roll-out, smaller scoring higher (the
//              area itself grows with speed, and would make standing still score best).
// Improved DWA also drops candidates that a wheel cannot follow: wheel ground speed above
// max_wheel_speed_m_s, or a steered wheel beyond max_steer_rad.
// The path ahead: with a planned path and an input that knows where along it the vehicle is
// (pose input: remaining_m finite), the planned path itself, so the roll-outs see the next
// arc coming (as seed 002's planner does); otherwise (a camera) the perceived path: the arc of the
// estimate's curvature through the foot point, then, where perception previews a change of
// curvature, the arc of the curvature ahead. Between the w samples, the best sample's parabola
// through its neighbours' scores gives one more candidate (the window's w step is coarse against
// a millimetre's correction). Commands are (vx = v, vy = 0, wz = w).
class DwaController : public PathController {
 public:
  struct Options {
    bool improved = true;
    int v_samples = 11;
    int w_samples = 21;
    double horizon_s = 0.2;  // tuned with docs/dwa_tuning_suite.py
    double lookahead_m = 0.1;
    double weight_heading = 1.0;
    double weight_clearance = 0.1;
    double weight_speed = 0.3;
    double weight_area = 0.25;
    double clearance_cap_m = 1.0;
    double min_speed_fraction = 0.5;  // v >= this * path speed unless stopping for the end
    // The wheels on the centre line: x in the vehicle frame (improved: their speed and steer
    // limits; both: their tracks make the area).
    double front_wheel_x_m = 0.5;
    double rear_wheel_x_m = -0.5;
    double max_wheel_speed_m_s = 1.0;
    double max_steer_rad = std::numbers::pi / 2.0;
    // How fast a steered wheel turns (infinite: no steered wheels): at speed v a wheel x from
    // the reference point changes the yaw rate by at most v * rate / |x| per second (at zero
    // steer; more at larger angles), which bounds the window's w (both DWAs).
    double max_steer_rate_rad_s = std::numeric_limits<double>::infinity();
    bool front_steers = true;
    bool rear_steers = true;
    std::shared_ptr<const Path> planned_path;  // may be empty
  };

  explicit DwaController(const Options& options) : options_(options) {}

  ControllerOutput update(const TrackingEstimate& estimate, const ControlContext& context) override;
  void reset() override {}
  std::string name() const override { return options_.improved ? "improved_dwa" : "dwa"; }
  bool feeds_curvature_forward() const override { return false; }

  // Candidates scored in the last update (for the benchmark and tests).
  int last_candidates() const { return last_candidates_; }

 private:
  Options options_;
  int last_candidates_ = 0;
};

}  // namespace agv::control
