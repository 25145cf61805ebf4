#include "control/finite_step_plan.h"

#include <cassert>
#include <cmath>

namespace agv::control {

FiniteStepPlan plan_finite_step(int steps, const PlanErrors& start, double path_speed_m_s,
                                double ts_s) {
  assert(steps >= 1 && ts_s > 0.0);
  const double n = steps;
  const double e0 = start.e_theta_rad;
  const double e0_sq = e0 * e0;
  // Eq. 20. The sums over j = 1..N of j^2 and j^4 give the closed forms below.
  const double c1 = (n + 1.0) * (2.0 * n + 1.0) * (3.0 * n * n + 3.0 * n - 1.0) /
                    (30.0 * n * n * n) * e0_sq * e0_sq;
  const double denominator =
      ts_s * ts_s * (c1 + n + (n + 1.0) * (2.0 * n + 1.0) / (3.0 * n) * e0_sq);
  const double numerator = start.e_d_m + ts_s * path_speed_m_s * (n + 1.0) / 2.0 * e0;

  FiniteStepPlan plan;
  plan.steps = steps;
  plan.c = numerator / denominator;
  plan.lateral_m_s.resize(steps);
  for (int k = 0; k < steps; ++k) {
    const double remaining = (n - k) / n;  // e_theta(k) / e_theta(0), eq. 16
    plan.lateral_m_s[k] = plan.c * ts_s * (remaining * remaining * e0_sq + 1.0);  // eq. 21
  }
  plan.turn_rate_rad_s = e0 / (n * ts_s);
  plan.eq22_accel_m_s2 = std::abs(plan.c) * e0_sq * (2.0 * n - 1.0) / (n * n);
  return plan;
}

PlanErrors eq12_step(const PlanErrors& now, double lateral_m_s, double turn_rate_rad_s,
                     double path_speed_m_s, double ts_s) {
  return {now.e_theta_rad - turn_rate_rad_s * ts_s,
          now.e_d_m - ts_s * lateral_m_s + ts_s * path_speed_m_s * now.e_theta_rad -
              ts_s * lateral_m_s * now.e_theta_rad * now.e_theta_rad};
}

}  // namespace agv::control
