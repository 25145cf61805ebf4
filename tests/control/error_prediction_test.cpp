#include "control/error_prediction.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::control {
namespace {

// Straight path, heading error 0: a lateral command vy changes e_d by vy * t exactly.
TEST(CommandHistory, LateralCommandShiftsTheLateralError) {
  CommandHistory history;
  history.record(0.0, {0.3, -0.02, 0.0});
  history.record(0.1, {0.3, -0.04, 0.0});
  const TrackingError e = history.predict({0.0, 0.01}, 0.0, 0.0, 0.2);
  EXPECT_NEAR(e.e_d_m, 0.01 - 0.02 * 0.1 - 0.04 * 0.1, 1e-12);
  EXPECT_NEAR(e.e_theta_rad, 0.0, 1e-12);
}

// A constant heading error at speed v drifts e_d by v sin(e_theta) t.
TEST(CommandHistory, HeadingErrorDriftsAtSpeed) {
  CommandHistory history;
  history.record(0.0, {0.5, 0.0, 0.0});
  const TrackingError e = history.predict({0.1, 0.0}, 0.0, 0.0, 0.3);
  EXPECT_NEAR(e.e_d_m, 0.5 * std::sin(0.1) * 0.3, 1e-12);
}

// Turning at w_z for t changes e_theta by w_z t, and e_d follows the exact arc:
// e_d(t) = v (1 - cos(w t)) / w for a vehicle starting on the path.
TEST(CommandHistory, TurningFollowsTheExactArc) {
  CommandHistory history;
  history.record(0.0, {0.3, 0.0, 0.5});
  const TrackingError e = history.predict({0.0, 0.0}, 0.0, 0.0, 0.4);
  EXPECT_NEAR(e.e_theta_rad, 0.2, 1e-12);
  EXPECT_NEAR(e.e_d_m, 0.3 * (1 - std::cos(0.2)) / 0.5, 1e-9);
}

// A measurement taken half-way through a period sees only the remaining half of that command.
TEST(CommandHistory, StartsMidPeriod) {
  CommandHistory history;
  history.record(0.0, {0.3, 0.1, 0.0});
  history.record(0.1, {0.3, 0.0, 0.0});
  const TrackingError e = history.predict({0.0, 0.0}, 0.0, 0.05, 0.2);
  EXPECT_NEAR(e.e_d_m, 0.1 * 0.05, 1e-12);
}

}  // namespace
}  // namespace agv::control
