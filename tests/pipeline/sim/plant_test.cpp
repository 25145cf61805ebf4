#include "pipeline/sim/plant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/angles.h"

namespace agv::pipeline {
namespace {

// Driving forward at v while turning at w traces a circle of radius v / w: after a quarter turn
// the vehicle is at (R, R) from a start at the origin facing +x, facing +y.
TEST(Plant, ConstantTwistFollowsTheExactCircle) {
  const double v = 0.3, w = 0.6, radius = v / w;
  const Pose2 p = integrate_twist({0.0, 0.0, 0.0}, {v, 0.0, w}, (kPi / 2) / w);
  EXPECT_NEAR(p.x_m, radius, 1e-12);
  EXPECT_NEAR(p.y_m, radius, 1e-12);
  EXPECT_NEAR(p.yaw_rad, kPi / 2, 1e-12);
  // Many small steps of the exact map give the same point as one big step.
  Pose2 stepped{0.0, 0.0, 0.0};
  for (int i = 0; i < 1000; ++i)
    stepped = integrate_twist(stepped, {v, 0.0, w}, (kPi / 2) / w / 1000);
  EXPECT_NEAR(stepped.x_m, radius, 1e-12);
  EXPECT_NEAR(stepped.y_m, radius, 1e-12);
}

// Sliding sideways at u while turning at w: the world velocity (-u sin wt, u cos wt) integrates,
// over half a turn, to (-2u/w, 0).
TEST(Plant, SidewaysMotionWhileTurning) {
  const double u = 0.1, w = 1.0;
  const Pose2 p = integrate_twist({0.0, 0.0, 0.0}, {0.0, u, w}, kPi / w);
  EXPECT_NEAR(p.x_m, -2.0 * u / w, 1e-12);
  EXPECT_NEAR(p.y_m, 0.0, 1e-12);
}

TEST(Plant, StraightMotionWithoutTurning) {
  const Pose2 p = integrate_twist({1.0, 2.0, kPi / 2}, {0.3, 0.1, 0.0}, 2.0);
  EXPECT_NEAR(p.x_m, 1.0 - 0.2, 1e-12);
  EXPECT_NEAR(p.y_m, 2.0 + 0.6, 1e-12);
  // Continuous at w -> 0: a turn rate of 1e-12 gives the same pose to 1e-12.
  const Pose2 q = integrate_twist({1.0, 2.0, kPi / 2}, {0.3, 0.1, 1e-12}, 2.0);
  EXPECT_NEAR(q.x_m, p.x_m, 1e-12);
  EXPECT_NEAR(q.y_m, p.y_m, 1e-12);
}

// First-order lag: after one time constant the twist has covered 1 - 1/e of the step.
TEST(Plant, ActuatorLagIsFirstOrder) {
  Plant plant({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, Plant::Options{0.05, std::nullopt});
  plant.step({0.0, 0.1, 0.0}, 0.05);
  EXPECT_NEAR(plant.twist().vy_m_s, 0.1 * (1.0 - std::exp(-1.0)), 1e-12);
  // Distance covered is the integral of 0.1 (1 - exp(-t / tau)) over one tau: 0.1 tau / e.
  EXPECT_NEAR(plant.pose().y_m, 0.1 * 0.05 / std::exp(1.0), 1e-9);
}

}  // namespace
}  // namespace agv::pipeline
