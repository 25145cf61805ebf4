#include "control/finite_step_plan.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/angles.h"

namespace agv::control {
namespace {

struct Case {
  int steps;
  double e_theta0_rad, e_d0_m, path_speed_m_s;
};

// Eq. 20 was derived from eq. 12 with the sums of j^2 and j^4, so running the eq. 12 model
// under the eq. 21 sequence must land on e_d(N) = 0 and e_theta(N) = 0 up to rounding.
TEST(FiniteStepPlan, Eq20DrivesTheEq12ModelToZeroInNSteps) {
  const double ts = 0.1;
  for (const Case& c : {Case{1, deg_to_rad(5), 0.01, 0.3}, Case{4, deg_to_rad(5), 0.01, 0.3},
                        Case{10, deg_to_rad(5), 0.01, 0.5}, Case{7, deg_to_rad(-8), -0.02, 0.3},
                        Case{3, deg_to_rad(2), -0.015, 0.8}, Case{25, 0.0, 0.005, 0.3},
                        Case{6, deg_to_rad(8), 0.0, 0.0}}) {
    const FiniteStepPlan plan =
        plan_finite_step(c.steps, {c.e_theta0_rad, c.e_d0_m}, c.path_speed_m_s, ts);
    ASSERT_EQ(static_cast<int>(plan.lateral_m_s.size()), c.steps);
    PlanErrors e{c.e_theta0_rad, c.e_d0_m};
    for (int k = 0; k < c.steps; ++k) {
      // Eq. 16: e_theta falls linearly.
      EXPECT_NEAR(e.e_theta_rad, (c.steps - k) * c.e_theta0_rad / c.steps, 1e-14);
      e = eq12_step(e, plan.lateral_m_s[k], plan.turn_rate_rad_s, c.path_speed_m_s, ts);
    }
    EXPECT_NEAR(e.e_d_m, 0.0, 1e-12) << "N=" << c.steps;
    EXPECT_NEAR(e.e_theta_rad, 0.0, 1e-14) << "N=" << c.steps;
  }
}

// For N = 1 the plan solves e_d(1) = 0 directly from eq. 12:
//   0 = e_d0 + Ts v_tau e0 - Ts v0 (1 + e0^2)  =>  v0 = (e_d0 + Ts v_tau e0) / (Ts (1 + e0^2)).
TEST(FiniteStepPlan, SingleStepMatchesHandSolution) {
  const double ts = 0.1, e0 = deg_to_rad(5), e_d0 = 0.01, v_tau = 0.3;
  const FiniteStepPlan plan = plan_finite_step(1, {e0, e_d0}, v_tau, ts);
  EXPECT_NEAR(plan.lateral_m_s[0], (e_d0 + ts * v_tau * e0) / (ts * (1 + e0 * e0)), 1e-15);
  EXPECT_NEAR(plan.turn_rate_rad_s, e0 / ts, 1e-15);
}

// Erratum 1: the turn rate is constant, e_theta(0) / (N Ts), not (N-k)/(N Ts) e_theta(0).
TEST(FiniteStepPlan, TurnRateIsConstantEq16NotThePrintedEq21) {
  const FiniteStepPlan plan = plan_finite_step(4, {deg_to_rad(5), 0.01}, 0.3, 0.1);
  EXPECT_NEAR(plan.turn_rate_rad_s, deg_to_rad(5) / 0.4, 1e-15);
}

// Eq. 22's |a|max is the largest step between consecutive lateral speeds, divided by Ts.
TEST(FiniteStepPlan, Eq22AccelerationIsTheLargestStepInsideThePlan) {
  const double ts = 0.1;
  const FiniteStepPlan plan = plan_finite_step(6, {deg_to_rad(7), 0.012}, 0.3, ts);
  double largest = 0.0;
  for (size_t k = 1; k < plan.lateral_m_s.size(); ++k) {
    largest = std::max(largest, std::abs(plan.lateral_m_s[k] - plan.lateral_m_s[k - 1]) / ts);
  }
  EXPECT_NEAR(plan.eq22_accel_m_s2, largest, 1e-12);
}

}  // namespace
}  // namespace agv::control
