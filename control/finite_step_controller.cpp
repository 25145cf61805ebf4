#include "control/finite_step_controller.h"

#include <algorithm>
#include <cmath>

namespace agv::control {
namespace {

constexpr double kTolerance = 1e-9;

bool within(double value, double limit) { return std::abs(value) <= limit * (1.0 + kTolerance); }

}  // namespace

std::string FiniteStepController::name() const {
  return options_.mode == HorizonMode::kShrinking ? "finite_step (shrinking horizon)"
                                                  : "finite_step (fixed horizon)";
}

bool FiniteStepController::plan_is_feasible(const FiniteStepPlan& plan,
                                            const ControlContext& context, double curvature_1_m,
                                            bool check_rates) const {
  const double ts = context.ts_s;
  // Eq. 22 (the paper's own bounds, inside the plan).
  if (!within(plan.lateral_m_s.front(), options_.v_x_max_m_s)) return false;
  if (!within(plan.eq22_accel_m_s2, options_.a_max_m_s2)) return false;
  // Vehicle limits on every step (DIGEST erratum 2). The paper's v_x is -v_y.
  const VehicleLimits& limits = context.limits;
  double previous_m_s = -context.previous_command.vy_m_s;
  for (double lateral_m_s : plan.lateral_m_s) {
    if (!within(lateral_m_s, limits.v_lateral_max_m_s)) return false;
    if (check_rates && !within((lateral_m_s - previous_m_s) / ts, limits.a_max_m_s2)) return false;
    previous_m_s = lateral_m_s;
  }
  const double feed_forward_rad_s = curvature_1_m * context.path_speed_m_s;
  const double turn_rad_s = -plan.turn_rate_rad_s + feed_forward_rad_s;
  if (!within(turn_rad_s, limits.w_max_rad_s)) return false;
  if (!check_rates) return true;
  if (!within(previous_m_s / ts, limits.a_max_m_s2)) return false;  // back to zero at the end
  if (!within((turn_rad_s - context.previous_command.wz_rad_s) / ts, limits.alpha_max_rad_s2)) {
    return false;
  }
  return within(plan.turn_rate_rad_s / ts, limits.alpha_max_rad_s2);
}

ControllerOutput FiniteStepController::update(const TrackingEstimate& estimate,
                                              const ControlContext& context) {
  const PlanErrors start{estimate.e_theta_rad, estimate.e_d_m};
  int n_lowest = options_.n_min;
  if (options_.mode == HorizonMode::kFixed) {
    n_lowest = std::max(n_lowest, options_.n_fixed);
  } else if (steps_left_ > 0) {
    n_lowest = std::max(n_lowest, steps_left_);  // keep shrinking the manoeuvre under way
  }
  n_lowest = std::min(n_lowest, options_.n_max);

  ControllerOutput out;
  FiniteStepPlan plan;
  bool found = false;
  for (int n = n_lowest; n <= options_.n_max && !found; ++n) {
    plan = plan_finite_step(n, start, context.path_speed_m_s, context.ts_s);
    found = plan_is_feasible(plan, context, estimate.curvature_1_m);
  }
  if (!found) {
    // No N meets the acceleration limits. Take the fastest plan within the speed limits whose
    // lateral speed the vehicle can still brake to zero within half the remaining error
    // (v^2 / 2a <= |e_d| / 2); the caller ramps the command at the vehicle's limits. Failing
    // even that, the gentlest plan.
    out.no_feasible_horizon = true;
    const double stoppable_m_s = std::sqrt(context.limits.a_max_m_s2 * std::abs(estimate.e_d_m)) +
                                 context.limits.a_max_m_s2 * context.ts_s;
    for (int n = n_lowest; n <= options_.n_max && !found; ++n) {
      plan = plan_finite_step(n, start, context.path_speed_m_s, context.ts_s);
      found = plan_is_feasible(plan, context, estimate.curvature_1_m, /*check_rates=*/false) &&
              std::abs(plan.lateral_m_s.front()) <= stoppable_m_s;
    }
    if (!found)
      plan = plan_finite_step(options_.n_max, start, context.path_speed_m_s, context.ts_s);
  }
  // A saturated plan is not followed step by step, so there is nothing to shrink: the next
  // period chooses N afresh.
  steps_left_ =
      (options_.mode == HorizonMode::kShrinking && !out.no_feasible_horizon) ? plan.steps - 1 : 0;
  out.horizon_steps = plan.steps;
  out.command.vx_m_s = context.path_speed_m_s;
  out.command.vy_m_s = -plan.lateral_m_s.front();
  out.command.wz_rad_s = -plan.turn_rate_rad_s + estimate.curvature_1_m * context.path_speed_m_s;
  return out;
}

}  // namespace agv::control
