#include "control/drive_response.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

DualSteerGeometry both_steer() {
  DualSteerGeometry g;
  g.form = DriveForm::kBothSteer;
  g.wheelbase_m = 1.0;
  g.max_steer_rate_rad_s = 1.0;
  g.max_wheel_speed_m_s = 1.0;
  return g;
}

// The sideways displacement (m) of a vehicle whose two wheels, pointing straight ahead at 0.3 m/s,
// are told to make (0.3, 0.05, 0) m/s: both turn at 1 rad/s towards atan(0.05 / 0.3), and while
// turning each drives its target speed's part along where it points, |v| cos(target - angle),
// whose sideways part is that times sin(angle). Simpson's rule over [0, t_s].
double turning_sideways_m(double t_s) {
  const double target_rad = std::atan2(0.05, 0.3), speed_m_s = std::hypot(0.3, 0.05);
  auto vy = [&](double t) {
    const double angle = std::min(t, target_rad);
    return speed_m_s * std::cos(target_rad - angle) * std::sin(angle);
  };
  constexpr int kIntervals = 200;
  const double h = t_s / kIntervals;
  double sum = vy(0.0) + vy(t_s);
  for (int i = 1; i < kIntervals; ++i) sum += (i % 2 ? 4.0 : 2.0) * vy(i * h);
  return sum * h / 3.0;
}

// A drive without lag moves with the command at once, in one move.
TEST(DriveResponse, WithoutLagTheTwistIsTheCommand) {
  DriveResponse drive({0.3, 0.0, 0.0}, {});
  EXPECT_TRUE(drive.immediate());
  int moves = 0;
  drive.step({0.2, 0.1, 0.3}, 0.1, [&](double h_s, const BodyTwist& twist) {
    ++moves;
    EXPECT_DOUBLE_EQ(h_s, 0.1);
    EXPECT_DOUBLE_EQ(twist.wz_rad_s, 0.3);
  });
  EXPECT_EQ(moves, 1);
  EXPECT_DOUBLE_EQ(drive.half_response_s({0.3, 0.0, 0.0}, {0.3, 0.1, 0.5}), 0.0);
}

// A first-order lag of 0.2 s: after one time constant the twist has made 1 - 1/e of a step, and
// the distance moved is tau / e (the integral of 1 - exp(-t / tau) over [0, tau]); to 1e-9.
TEST(DriveResponse, AFirstOrderLagFollowsTheExponential) {
  DriveResponse::Options options;
  options.actuator_lag_s = 0.2;
  DriveResponse drive({0.0, 0.0, 0.0}, options);
  double moved_m = 0.0;
  drive.step({1.0, 0.0, 0.0}, 0.2,
             [&](double h_s, const BodyTwist& twist) { moved_m += h_s * twist.vx_m_s; });
  EXPECT_NEAR(drive.twist().vx_m_s, 1.0 - std::exp(-1.0), 1e-9);
  EXPECT_NEAR(moved_m, 0.2 * std::exp(-1.0), 1e-9);
  EXPECT_DOUBLE_EQ(drive.half_response_s({}, {1.0, 0.0, 0.0}), 0.2);
}

// Dual steering wheels told to move sideways: in the first 0.1 s the vehicle moves sideways only
// as far as its turning wheels take it (1.5 mm; the command alone would say 5 mm), within 8 %
// (the drive moves in 5 ms sub-steps with the angle at each sub-step's end, 2.5 ms ahead on
// average: 5 % ahead of the exact integral, whose angle is 50 ms on average); once the wheels have
// turned (0.165 s at 1 rad/s), the twist is the command. Half the time the wheels take to turn is
// what the drive reports as its response.
TEST(DriveResponse, DualSteerWheelsTurnAtTheirRateBeforeTheVehicleMovesSideways) {
  DriveResponse::Options options;
  options.dual_steer = both_steer();
  DriveResponse drive({0.3, 0.0, 0.0}, options);
  EXPECT_FALSE(drive.immediate());
  const BodyTwist sideways{0.3, 0.05, 0.0};
  double moved_m = 0.0;
  drive.step(sideways, 0.1, [&](double h_s, const BodyTwist& twist) {
    moved_m += h_s * twist.vy_m_s;
    EXPECT_NEAR(twist.wz_rad_s, 0.0, 1e-12);  // both wheels at one angle: no turn
  });
  const double exact_m = turning_sideways_m(0.1);
  EXPECT_GT(exact_m, 0.0014);
  EXPECT_LT(exact_m, 0.0016);
  EXPECT_NEAR(moved_m, exact_m, 0.08 * exact_m);
  drive.step(sideways, 0.1, [](double, const BodyTwist&) {});
  EXPECT_NEAR(drive.twist().vy_m_s, 0.05, 1e-9);
  EXPECT_NEAR(drive.twist().vx_m_s, 0.3, 1e-9);
  EXPECT_NEAR(drive.half_response_s({0.3, 0.0, 0.0}, sideways), 0.5 * std::atan2(0.05, 0.3), 1e-9);
  // A turn: the wheels 0.5 m ahead and behind steer opposite ways, atan(0.5 w / v) each.
  EXPECT_NEAR(drive.half_response_s({0.3, 0.0, 0.0}, {0.3, 0.0, 0.3}), 0.5 * std::atan(0.5), 1e-9);
}

}  // namespace
}  // namespace agv::control
