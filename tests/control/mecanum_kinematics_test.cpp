#include "control/mecanum_kinematics.h"

#include <gtest/gtest.h>

namespace agv::control {
namespace {

const MecanumGeometry kGeometry{0.05, 0.20, 0.20};  // r, L1, L2: L1 + L2 = 0.4 m

TEST(MecanumKinematics, ForwardOfInverseIsIdentity) {
  for (const BodyTwist& twist :
       {BodyTwist{0.3, 0.0, 0.0}, BodyTwist{0.0, 0.2, 0.0}, BodyTwist{0.0, 0.0, 1.0},
        BodyTwist{0.3, -0.05, 0.4}, BodyTwist{-0.7, 0.3, -2.0}}) {
    const BodyTwist back = mecanum_forward(kGeometry, mecanum_inverse(kGeometry, twist));
    EXPECT_NEAR(back.vx_m_s, twist.vx_m_s, 1e-12);
    EXPECT_NEAR(back.vy_m_s, twist.vy_m_s, 1e-12);
    EXPECT_NEAR(back.wz_rad_s, twist.wz_rad_s, 1e-12);
  }
}

// Worked by hand from eq. 1 for (vx, vy, wz) = (0.3 m/s, 0.1 m/s, 0.5 rad/s), r = 0.05 m,
// L1 + L2 = 0.4 m:  fl = (0.3 - 0.1 - 0.2) / 0.05 = 0,   fr = (0.3 + 0.1 + 0.2) / 0.05 = 12,
//                   rl = (0.3 + 0.1 - 0.2) / 0.05 = 4,   rr = (0.3 - 0.1 + 0.2) / 0.05 = 8 rad/s.
TEST(MecanumKinematics, InverseMatchesHandComputedWheelSpeeds) {
  const MecanumWheelSpeeds w = mecanum_inverse(kGeometry, {0.3, 0.1, 0.5});
  EXPECT_NEAR(w[0], 0.0, 1e-12);
  EXPECT_NEAR(w[1], 12.0, 1e-12);
  EXPECT_NEAR(w[2], 4.0, 1e-12);
  EXPECT_NEAR(w[3], 8.0, 1e-12);
}

// Sliding left (vy > 0) on X-pattern Mecanum wheels: front-left and rear-right roll backwards,
// front-right and rear-left forwards. Turning left (wz > 0): the left side rolls backwards.
TEST(MecanumKinematics, SignPatternOfPureMotions) {
  const MecanumWheelSpeeds left = mecanum_inverse(kGeometry, {0.0, 0.1, 0.0});
  EXPECT_LT(left[0], 0.0);
  EXPECT_GT(left[1], 0.0);
  EXPECT_GT(left[2], 0.0);
  EXPECT_LT(left[3], 0.0);
  const MecanumWheelSpeeds turn = mecanum_inverse(kGeometry, {0.0, 0.0, 0.5});
  EXPECT_LT(turn[0], 0.0);
  EXPECT_GT(turn[1], 0.0);
  EXPECT_LT(turn[2], 0.0);
  EXPECT_GT(turn[3], 0.0);
}

// Inconsistent wheel speeds (a wheel slipping) give the least-squares twist.
TEST(MecanumKinematics, ForwardIsLeastSquaresForInconsistentSpeeds) {
  const MecanumWheelSpeeds w(6.0, 6.0, 6.0, 10.0);  // forward at 0.3 m/s, rear-right 4 rad/s fast
  const BodyTwist t = mecanum_forward(kGeometry, w);
  EXPECT_NEAR(t.vx_m_s, 0.05 / 4 * 28.0, 1e-12);
  EXPECT_NEAR(t.vy_m_s, 0.05 / 4 * -4.0, 1e-12);
  EXPECT_NEAR(t.wz_rad_s, 0.05 / (4 * 0.4) * 4.0, 1e-12);
}

}  // namespace
}  // namespace agv::control
