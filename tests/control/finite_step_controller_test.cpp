#include "control/finite_step_controller.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/angles.h"

namespace agv::control {
namespace {

ControlContext table1_context() {
  ControlContext context;
  context.ts_s = 0.1;
  context.path_speed_m_s = 0.3;
  context.previous_command = {0.3, 0.0, 0.0};
  context.limits = VehicleLimits{1.0, 0.5, 0.5, 1.0, 4.0};
  return context;
}

// Table 1 start (5 deg, 10 mm, 0.3 m/s, Ts 0.1 s) with the vehicle's 0.5 m/s^2 on every step.
// By hand from eq. 20-21: N = 3 gives v_x(0) = 0.05077 m/s, a jump of 0.508 m/s^2 from rest
// (too much); N = 4 gives v_x(0) = 0.041382 m/s (0.414 m/s^2), so N = 4.
TEST(FiniteStepController, PicksTheSmallestFeasibleHorizon) {
  FiniteStepController::Options options;
  options.mode = HorizonMode::kShrinking;
  FiniteStepController controller(options);
  const ControllerOutput out = controller.update({deg_to_rad(5), 0.01, 0.0, 0.0}, table1_context());
  EXPECT_EQ(out.horizon_steps, 4);
  EXPECT_FALSE(out.no_feasible_horizon);
  EXPECT_NEAR(out.command.vy_m_s, -0.041382, 2e-6);                // paper's v_x = -v_y
  EXPECT_NEAR(out.command.wz_rad_s, -deg_to_rad(5) / 0.4, 1e-12);  // paper's dw = -w_z
  EXPECT_DOUBLE_EQ(out.command.vx_m_s, 0.3);
}

TEST(FiniteStepController, ShrinkingHorizonCountsDownFixedHorizonDoesNot) {
  FiniteStepController::Options options;
  options.mode = HorizonMode::kShrinking;
  FiniteStepController shrinking(options);
  ControlContext context = table1_context();
  EXPECT_EQ(shrinking.update({deg_to_rad(5), 0.01, 0.0, 0.0}, context).horizon_steps, 4);
  context.previous_command.vy_m_s = -0.041382;
  EXPECT_EQ(shrinking.update({deg_to_rad(3.75), 0.008, 0.0, 0.0}, context).horizon_steps, 3);
  EXPECT_EQ(shrinking.update({deg_to_rad(2.5), 0.005, 0.0, 0.0}, context).horizon_steps, 2);

  options.mode = HorizonMode::kFixed;
  options.n_fixed = 6;
  FiniteStepController fixed(options);
  context = table1_context();
  EXPECT_EQ(fixed.update({deg_to_rad(5), 0.01, 0.0, 0.0}, context).horizon_steps, 6);
  EXPECT_EQ(fixed.update({deg_to_rad(3), 0.006, 0.0, 0.0}, context).horizon_steps, 6);
}

// Every plan it accepts meets the vehicle limits on every step, the two ends included.
TEST(FiniteStepController, AcceptedPlansMeetEveryLimit) {
  FiniteStepController controller(FiniteStepController::Options{});
  const ControlContext context = table1_context();
  for (double e_theta_deg : {-8.0, -3.0, 0.0, 4.0, 8.0}) {
    for (double e_d_m : {-0.02, -0.005, 0.0, 0.01, 0.02}) {
      controller.reset();
      const ControllerOutput out =
          controller.update({deg_to_rad(e_theta_deg), e_d_m, 0.0, 0.0}, context);
      if (out.no_feasible_horizon) continue;
      const FiniteStepPlan plan =
          plan_finite_step(out.horizon_steps, {deg_to_rad(e_theta_deg), e_d_m}, 0.3, 0.1);
      double previous = 0.0;
      for (double v : plan.lateral_m_s) {
        EXPECT_LE(std::abs(v - previous) / 0.1, 0.5 + 1e-9);
        previous = v;
      }
      EXPECT_LE(std::abs(previous) / 0.1, 0.5 + 1e-9);
      EXPECT_LE(plan.eq22_accel_m_s2, 0.05 + 1e-12);
    }
  }
}

TEST(FiniteStepController, SaysSoWhenNoHorizonIsFeasible) {
  FiniteStepController controller(FiniteStepController::Options{});
  ControlContext context = table1_context();
  context.limits.a_max_m_s2 = 0.01;  // eq. 21's flat profile cannot start within 0.001 m/s
  const ControllerOutput out = controller.update({deg_to_rad(5), 0.01, 0.0, 0.0}, context);
  EXPECT_TRUE(out.no_feasible_horizon);
}

// On an arc the turn rate carries the path's own rate, curvature * v_tau.
TEST(FiniteStepController, FeedsForwardTheCurvature) {
  FiniteStepController controller(FiniteStepController::Options{});
  ControlContext context = table1_context();
  context.previous_command.wz_rad_s = 0.6;
  const ControllerOutput out = controller.update({0.0, 0.0, 2.0, 0.0}, context);
  EXPECT_NEAR(out.command.wz_rad_s, 2.0 * 0.3, 1e-12);
  EXPECT_NEAR(out.command.vy_m_s, 0.0, 1e-12);
}

}  // namespace
}  // namespace agv::control
