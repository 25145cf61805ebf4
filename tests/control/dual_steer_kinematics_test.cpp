#include "control/dual_steer_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/angles.h"

namespace agv::control {
namespace {

DualSteerGeometry geometry(DriveForm form) {
  DualSteerGeometry g;
  g.form = form;
  g.wheelbase_m = 1.0;
  return g;
}

TEST(DualSteerKinematics, WheelPositionsOfEachForm) {
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kBothSteer).front_x_m(), 0.5);
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kBothSteer).rear_x_m(), -0.5);
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kRearDriveFront).front_x_m(), 1.0);
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kRearDriveFront).rear_x_m(), 0.0);
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kFrontDriveRear).front_x_m(), 0.0);
  EXPECT_DOUBLE_EQ(geometry(DriveForm::kFrontDriveRear).rear_x_m(), -1.0);
}

// Hand-worked: form 1 turning at 0.2 rad/s while driving 0.5 m/s: the front wheel at +0.5 m
// moves (0.5, 0.1), steer atan(0.2) = 11.31 deg, speed sqrt(0.26); the rear mirrors it.
TEST(DualSteerKinematics, BothSteerTurningHandValues) {
  const DualSteerGeometry g = geometry(DriveForm::kBothSteer);
  const DualSteerWheels w = dual_steer_inverse(g, {0.5, 0.0, 0.2});
  EXPECT_NEAR(w.front_steer_rad, std::atan(0.2), 1e-12);
  EXPECT_NEAR(w.rear_steer_rad, -std::atan(0.2), 1e-12);
  EXPECT_NEAR(w.front_speed_m_s, std::sqrt(0.26), 1e-12);
  EXPECT_NEAR(w.rear_speed_m_s, std::sqrt(0.26), 1e-12);
  const BodyTwist back = dual_steer_forward(g, w);
  EXPECT_NEAR(back.vx_m_s, 0.5, 1e-12);
  EXPECT_NEAR(back.vy_m_s, 0.0, 1e-12);
  EXPECT_NEAR(back.wz_rad_s, 0.2, 1e-12);
  // Crabbing sideways and backwards: both wheels point the same way, reversed past 90 deg.
  const DualSteerWheels crab = dual_steer_inverse(g, {-0.3, 0.3, 0.0});
  EXPECT_NEAR(crab.front_steer_rad, -kPi / 4, 1e-12);
  EXPECT_NEAR(crab.front_speed_m_s, -std::sqrt(0.18), 1e-12);
  const BodyTwist crab_back = dual_steer_forward(g, crab);
  EXPECT_NEAR(crab_back.vx_m_s, -0.3, 1e-12);
  EXPECT_NEAR(crab_back.vy_m_s, 0.3, 1e-12);
}

// Forms 2 and 3: the fixed wheel is the reference point; it cannot move sideways, so a
// commanded vy is not made, and the turn comes from the other wheel's steer: tan(d) = w L / v.
TEST(DualSteerKinematics, FixedWheelFormsAreBicycles) {
  const DualSteerGeometry rear = geometry(DriveForm::kRearDriveFront);
  DualSteerWheels w = dual_steer_inverse(rear, {0.4, 0.0, 0.2});
  EXPECT_NEAR(w.rear_steer_rad, 0.0, 1e-15);
  EXPECT_NEAR(w.rear_speed_m_s, 0.4, 1e-12);
  EXPECT_NEAR(w.front_steer_rad, std::atan2(0.2 * 1.0, 0.4), 1e-12);
  BodyTwist back = dual_steer_forward(rear, w);
  EXPECT_NEAR(back.vx_m_s, 0.4, 1e-12);
  EXPECT_NEAR(back.vy_m_s, 0.0, 1e-12);
  EXPECT_NEAR(back.wz_rad_s, 0.2, 1e-12);
  back = dual_steer_forward(rear, dual_steer_inverse(rear, {0.4, 0.1, 0.0}));
  EXPECT_NEAR(back.vy_m_s, 0.0, 1e-12);  // the rear wheel cannot slide sideways

  const DualSteerGeometry front = geometry(DriveForm::kFrontDriveRear);
  w = dual_steer_inverse(front, {0.4, 0.0, 0.2});
  EXPECT_NEAR(w.front_steer_rad, 0.0, 1e-15);
  EXPECT_NEAR(w.rear_steer_rad, std::atan2(-0.2 * 1.0, 0.4), 1e-12);  // rear swings out
  back = dual_steer_forward(front, w);
  EXPECT_NEAR(back.wz_rad_s, 0.2, 1e-12);
  EXPECT_NEAR(back.vy_m_s, 0.0, 1e-12);
}

TEST(DualSteerKinematics, SteerRateAngleAndWheelSpeedLimits) {
  DualSteerGeometry g = geometry(DriveForm::kBothSteer);
  g.max_steer_rate_rad_s = 0.5;
  g.max_wheel_speed_m_s = 0.5;
  g.max_steer_rad = 0.6;
  const DualSteerWheels target = dual_steer_inverse(g, {0.6, 0.0, 2.0});  // wants 63 deg, 1.17 m/s
  EXPECT_NEAR(target.front_steer_rad, 0.6, 1e-12);  // clamped to the steer range
  const DualSteerWheels next = advance_dual_steer(g, DualSteerWheels{}, target, 0.1);
  EXPECT_NEAR(next.front_steer_rad, 0.05, 1e-12);  // 0.5 rad/s for 0.1 s
  EXPECT_NEAR(next.rear_steer_rad, -0.05, 1e-12);
  EXPECT_NEAR(std::max(std::abs(next.front_speed_m_s), std::abs(next.rear_speed_m_s)), 0.5, 1e-12);
  EXPECT_NEAR(next.front_speed_m_s / next.rear_speed_m_s,
              target.front_speed_m_s / target.rear_speed_m_s, 1e-12);
}

}  // namespace
}  // namespace agv::control
