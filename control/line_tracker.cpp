#include "control/line_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace agv::control {
namespace {

bool differs(const BodyTwist& a, const BodyTwist& b) {
  constexpr double kEps = 1e-12;
  return std::abs(a.vx_m_s - b.vx_m_s) > kEps || std::abs(a.vy_m_s - b.vy_m_s) > kEps ||
         std::abs(a.wz_rad_s - b.wz_rad_s) > kEps;
}

}  // namespace

double LineTracker::change_ahead_m(const LineMeasurement& m, double now_s) const {
  if (!std::isfinite(m.curvature_change_m)) return std::numeric_limits<double>::infinity();
  return m.curvature_change_m - speed_m_s_ * (now_s - m.stamp_s);
}

double LineTracker::coming_curvature_1_m(const LineMeasurement& m, double now_s) const {
  // The drive takes time to make a new turn rate (wheels steering at their rate): a law that
  // feeds the curvature forward gets the change that much earlier, so that the vehicle turns
  // half way at the joint.
  const BodyTwist here{speed_m_s_, 0.0, speed_m_s_ * m.curvature_1_m};
  const BodyTwist there{speed_m_s_, 0.0, speed_m_s_ * m.curvature_ahead_1_m};
  const double lead_s =
      controller_->feeds_curvature_forward() ? drive_.half_response_s(here, there) : 0.0;
  const double ahead_m = change_ahead_m(m, now_s) - speed_m_s_ * lead_s;
  if (!std::isfinite(ahead_m)) return m.curvature_1_m;
  // How much of the coming period's travel lies beyond the change.
  const double period_m = std::max(1e-9, speed_m_s_ * options_.ts_s);
  const double beyond = std::clamp((period_m - ahead_m) / period_m, 0.0, 1.0);
  return (1.0 - beyond) * m.curvature_1_m + beyond * m.curvature_ahead_1_m;
}

double LineTracker::curve_speed_m_s(const LineMeasurement& m, double now_s) const {
  double speed = options_.path_speed_m_s;
  if (!(options_.curve_turn_fraction > 0.0)) return speed;
  const double turn_rad_s = options_.curve_turn_fraction * limits_.w_max_rad_s;
  const auto turning_speed = [&](double curvature_1_m) {
    return std::abs(curvature_1_m) > 1e-9 ? turn_rad_s / std::abs(curvature_1_m)
                                          : std::numeric_limits<double>::infinity();
  };
  speed = std::min(speed, turning_speed(m.curvature_1_m));
  const double ahead_m = change_ahead_m(m, now_s);
  if (std::isfinite(ahead_m)) {
    // This period's command holds for a period: the braking starts one period's travel on.
    const double braking_m = std::max(0.0, ahead_m - speed_m_s_ * options_.ts_s);
    const double v_curve = turning_speed(m.curvature_ahead_1_m);
    const double decel = options_.curve_decel_fraction * limits_.a_max_m_s2;
    speed = std::min(speed, std::sqrt(v_curve * v_curve + 2.0 * decel * braking_m));
  }
  return speed;
}

LineTracker::LineTracker(std::unique_ptr<PathController> controller, const VehicleLimits& limits,
                         const Options& options, const BodyTwist& initial_command)
    : controller_(std::move(controller)),
      limits_(limits),
      options_(options),
      previous_command_(initial_command),
      drive_(initial_command, options.drive),
      speed_m_s_(options.path_speed_m_s) {}

TrackerOutput LineTracker::step(const std::optional<LineMeasurement>& newest, double now_s) {
  if (!first_step_s_) first_step_s_ = now_s;
  if (newest) {
    line_lost_ = !newest->line_found;
    if (newest->line_found) last_good_ = newest;
    last_arrival_s_ = now_s;
  }

  TrackerOutput out;
  if (line_lost_) out.flags |= kLineLost;
  if (!newest) out.flags |= kNoMeasurements;
  BodyTwist desired;
  // Times are sums of periods: a nanosecond of slack keeps rounding from ending the hold early.
  constexpr double kTimeSlack_s = 1e-9;
  const bool arriving =
      last_arrival_s_ && now_s - *last_arrival_s_ <= options_.line_lost_hold_s + kTimeSlack_s;
  const bool recent_good =
      last_good_ && arriving &&
      (!line_lost_ || now_s - last_good_->stamp_s <= options_.line_lost_hold_s + kTimeSlack_s);
  if (recent_good) {
    if (stopped_tracking_) controller_->reset();
    stopped_tracking_ = false;
    const bool late = now_s - *last_arrival_s_ > options_.ts_s + kTimeSlack_s;
    if (line_lost_ || late) out.flags |= kHolding;
    TrackingEstimate estimate{last_good_->e_theta_rad, last_good_->e_d_m, last_good_->curvature_1_m,
                              now_s - last_good_->stamp_s, last_good_->path_remaining_m};
    if (options_.latency_compensation) {
      const TrackingError predicted = history_.predict(
          {estimate.e_theta_rad, estimate.e_d_m},
          CurvatureProfile{last_good_->curvature_1_m, last_good_->curvature_change_m,
                           last_good_->curvature_ahead_1_m},
          last_good_->stamp_s, now_s);
      estimate.e_theta_rad = predicted.e_theta_rad;
      estimate.e_d_m = predicted.e_d_m;
    }
    // The speed along the path: down as fast as the vehicle may brake, up at the braking rate
    // used for curves.
    const double target_m_s = curve_speed_m_s(*last_good_, now_s);
    const double dv_m_s = limits_.a_max_m_s2 * options_.ts_s;
    speed_m_s_ = std::clamp(target_m_s, speed_m_s_ - dv_m_s,
                            speed_m_s_ + options_.curve_decel_fraction * dv_m_s);
    if (speed_m_s_ < options_.path_speed_m_s) out.flags |= kSlowForCurve;
    estimate.curvature_1_m = coming_curvature_1_m(*last_good_, now_s);
    estimate.curvature_change_m = change_ahead_m(*last_good_, now_s);
    estimate.curvature_ahead_1_m = last_good_->curvature_ahead_1_m;
    const ControlContext context{options_.ts_s, speed_m_s_, previous_command_, limits_};
    const ControllerOutput controlled = controller_->update(estimate, context);
    desired = controlled.command;
    out.horizon_steps = controlled.horizon_steps;
    if (controlled.no_feasible_horizon) out.flags |= kNoFeasibleHorizon;
    out.has_estimate = true;
    out.estimate = estimate;
  } else if (!last_good_ && now_s - *first_step_s_ <= options_.line_lost_hold_s + kTimeSlack_s) {
    out.flags |= kNoMeasurementYet;
    desired = previous_command_;
  } else {
    out.flags |= kStopping;
    stopped_tracking_ = true;
    desired = BodyTwist{};
  }

  out.command = limit_command(desired, previous_command_, limits_, options_.ts_s);
  if (differs(out.command, desired)) out.flags |= kSaturated;
  record(now_s, out.command);
  previous_command_ = out.command;
  return out;
}

TrackerOutput LineTracker::brake(double now_s) {
  TrackerOutput out;
  out.flags = kStopping;
  out.command = limit_command(BodyTwist{}, previous_command_, limits_, options_.ts_s);
  if (differs(out.command, BodyTwist{})) out.flags |= kSaturated;
  record(now_s, out.command);
  previous_command_ = out.command;
  return out;
}

void LineTracker::record(double now_s, const BodyTwist& command) {
  if (drive_.immediate()) {
    history_.record(now_s, command);
    return;
  }
  double t_s = now_s;
  drive_.step(command, options_.ts_s, [&](double h_s, const BodyTwist& twist) {
    history_.record(t_s, twist);
    t_s += h_s;
  });
}

}  // namespace agv::control
