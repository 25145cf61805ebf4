#include "control/line_tracker.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/angles.h"
#include "control/finite_step_controller.h"

namespace agv::control {
namespace {

constexpr double kTs = 0.1;
const VehicleLimits kLimits{1.0, 0.5, 0.5, 1.0, 4.0};

LineTracker make_tracker(double hold_s) {
  LineTracker::Options options;
  options.ts_s = kTs;
  options.path_speed_m_s = 0.3;
  options.line_lost_hold_s = hold_s;
  return LineTracker(std::make_unique<FiniteStepController>(FiniteStepController::Options{}),
                     kLimits, options, {0.3, 0.0, 0.0});
}

LineMeasurement seen(double stamp_s, double e_theta_rad = 0.0, double e_d_m = 0.0) {
  LineMeasurement m;
  m.stamp_s = stamp_s;
  m.line_found = true;
  m.e_theta_rad = e_theta_rad;
  m.e_d_m = e_d_m;
  m.confidence = 1.0;
  return m;
}

LineMeasurement lost(double stamp_s) {
  LineMeasurement m;
  m.stamp_s = stamp_s;
  return m;
}

// A law that always asks for the same twist, whatever the error.
class FixedCommand : public PathController {
 public:
  explicit FixedCommand(const BodyTwist& command, bool feeds_forward = true)
      : command_(command), feeds_forward_(feeds_forward) {}
  ControllerOutput update(const TrackingEstimate&, const ControlContext&) override {
    return {command_, 1, false};
  }
  void reset() override {}
  std::string name() const override { return "fixed"; }
  bool feeds_curvature_forward() const override { return feeds_forward_; }

 private:
  BodyTwist command_;
  bool feeds_forward_;
};

DriveResponse::Options dual_steer_drive() {
  DriveResponse::Options drive;
  drive.dual_steer = DualSteerGeometry{};  // both wheels steer, 1 m apart, 1 rad/s
  return drive;
}

// Dual steering wheels told at t = 0 to move sideways at 0.05 m/s: by t = 0.1 s they have turned
// only 0.1 of the 0.165 rad they need, and the vehicle has moved 1.6 mm sideways, not the 5 mm
// the command alone would give. The error predicted from a frame taken at t = 0 (on the line)
// says so: within 0.3 mm of the wheels' own integral (DriveResponseTest: 1.51 mm exactly), far
// from 5 mm. A Mecanum vehicle (at once) is predicted at the command's 5 mm.
TEST(LineTracker, PredictsTheLatencyWithHowTheDriveResponds) {
  for (bool steered : {true, false}) {
    LineTracker::Options options;
    options.ts_s = kTs;
    options.path_speed_m_s = 0.3;
    if (steered) options.drive = dual_steer_drive();
    LineTracker tracker(std::make_unique<FixedCommand>(BodyTwist{0.3, 0.05, 0.0}), kLimits, options,
                        {0.3, 0.0, 0.0});
    tracker.step(seen(0.0), 0.0);
    const TrackerOutput out = tracker.step(std::nullopt, kTs);  // the same frame, 0.1 s on
    ASSERT_TRUE(out.has_estimate);
    EXPECT_NEAR(out.estimate.e_d_m, steered ? 0.00151 : 0.005, steered ? 3e-4 : 1e-9)
        << (steered ? "dual steer" : "at once");
  }
}

// A curvature change 50 mm ahead at 0.3 m/s: a drive that follows at once gets it fed forward in
// the period it reaches it (not this one: 30 mm of travel); dual steering wheels, which take
// atan(0.5 * 1 1/m) / 1 rad/s = 0.46 s to steer into the arc, get it half of that, 0.23 s or
// 70 mm, early: in this period already. A law that plans on the path's geometry itself (DWA)
// gets the curvature where the vehicle is.
TEST(LineTracker, SteeredWheelsGetACurvatureAheadFedForwardEarly) {
  for (bool planner : {false, true}) {
    LineTracker::Options options;
    options.ts_s = kTs;
    options.path_speed_m_s = 0.3;
    options.curve_turn_fraction = 0.0;
    options.drive = dual_steer_drive();
    LineTracker tracker(std::make_unique<FixedCommand>(BodyTwist{0.3, 0.0, 0.0}, !planner), kLimits,
                        options, {0.3, 0.0, 0.0});
    LineMeasurement m = seen(0.0);
    m.curvature_change_m = 0.05;
    m.curvature_ahead_1_m = 1.0;
    const TrackerOutput out = tracker.step(m, 0.0);
    ASSERT_TRUE(out.has_estimate);
    EXPECT_DOUBLE_EQ(out.estimate.curvature_1_m, planner ? 0.0 : 1.0) << "planner " << planner;
  }
  for (bool steered : {true, false}) {
    LineTracker::Options options;
    options.ts_s = kTs;
    options.path_speed_m_s = 0.3;
    options.curve_turn_fraction = 0.0;
    if (steered) options.drive = dual_steer_drive();
    LineTracker tracker(std::make_unique<FixedCommand>(BodyTwist{0.3, 0.0, 0.0}), kLimits, options,
                        {0.3, 0.0, 0.0});
    LineMeasurement m = seen(0.0);
    m.curvature_change_m = 0.05;
    m.curvature_ahead_1_m = 1.0;
    const TrackerOutput out = tracker.step(m, 0.0);
    ASSERT_TRUE(out.has_estimate);
    EXPECT_DOUBLE_EQ(out.estimate.curvature_1_m, steered ? 1.0 : 0.0)
        << (steered ? "dual steer" : "at once");
  }
}

// The line is lost at t = 0.5 s: the tracker holds the last good estimate for 0.3 s, then
// brakes at no more than a_max to a stop, and resumes when the line is seen again.
TEST(LineTracker, HoldsThenStopsWithinTheAccelerationLimitThenResumes) {
  LineTracker tracker = make_tracker(0.3);
  BodyTwist previous{0.3, 0.0, 0.0};
  int k = 0;
  for (; k < 5; ++k) previous = tracker.step(seen(k * kTs, deg_to_rad(1), 0.002), k * kTs).command;
  double stopped_at_s = -1.0;
  double distance_m = 0.0;
  for (; k < 40; ++k) {
    const double t = k * kTs;
    const TrackerOutput out = tracker.step(lost(t), t);
    EXPECT_EQ(check_limits(out.command, previous, kLimits, kTs), 0u) << "t=" << t;
    EXPECT_TRUE(out.flags & kLineLost);
    if (t - 0.4 <= 0.3 + 1e-9) {
      EXPECT_TRUE(out.flags & kHolding) << "t=" << t;
    } else {
      EXPECT_TRUE(out.flags & kStopping) << "t=" << t;
      distance_m += out.command.vx_m_s * kTs;
    }
    if (stopped_at_s < 0 && std::abs(out.command.vx_m_s) + std::abs(out.command.vy_m_s) < 1e-12)
      stopped_at_s = t;
    previous = out.command;
  }
  // Braking starts at 0.8 s; from 0.3 m/s in steps of a_max * Ts = 0.05 m/s the commands are
  // 0.25, 0.20, ..., 0 m/s: zero at 1.3 s after (0.25 + 0.20 + ... + 0.05) * 0.1 = 0.075 m.
  EXPECT_NEAR(stopped_at_s, 1.3, 1e-9);
  EXPECT_NEAR(distance_m, 0.075, 1e-9);
  // Seen again: speed builds up again within the limits.
  for (int i = 0; i < 10; ++i, ++k) {
    const TrackerOutput out = tracker.step(seen(k * kTs), k * kTs);
    EXPECT_EQ(check_limits(out.command, previous, kLimits, kTs), 0u);
    EXPECT_FALSE(out.flags & kStopping);
    previous = out.command;
  }
  EXPECT_NEAR(previous.vx_m_s, 0.3, 1e-9);
}

// Without any measurement at all the tracker keeps the last command for the hold time, then stops.
TEST(LineTracker, NoMeasurementEverMeansStop) {
  LineTracker tracker = make_tracker(0.2);
  BodyTwist command;
  for (int k = 0; k < 20; ++k) command = tracker.step(std::nullopt, k * kTs).command;
  EXPECT_NEAR(command.vx_m_s, 0.0, 1e-12);
}

// Measurements that stop arriving (a stalled camera or perception, not a lost line) are treated
// like a lost line: hold for the hold time after the last arrival, then brake within a_max; the
// same 0.075 m as above, braking from 0.3 m/s at 0.5 m/s^2 in 0.1 s steps.
TEST(LineTracker, MeasurementsThatStopArrivingMeanStop) {
  LineTracker tracker = make_tracker(0.3);
  BodyTwist previous{0.3, 0.0, 0.0};
  int k = 0;
  for (; k < 5; ++k) previous = tracker.step(seen(k * kTs), k * kTs).command;
  double distance_m = 0.0;
  for (; k < 30; ++k) {
    const double t = k * kTs;
    const TrackerOutput out = tracker.step(std::nullopt, t);
    EXPECT_EQ(check_limits(out.command, previous, kLimits, kTs), 0u) << "t=" << t;
    EXPECT_TRUE(out.flags & kNoMeasurements);
    if (t - 0.4 <= 0.3 + 1e-9) {
      EXPECT_FALSE(out.flags & kStopping) << "t=" << t;
    } else {
      EXPECT_TRUE(out.flags & kStopping) << "t=" << t;
      distance_m += out.command.vx_m_s * kTs;
    }
    previous = out.command;
  }
  EXPECT_NEAR(previous.vx_m_s, 0.0, 1e-12);
  EXPECT_NEAR(distance_m, 0.075, 1e-9);
}

// Whatever the measurements say, the command never breaks a limit.
TEST(LineTracker, NeverCommandsBeyondTheLimits) {
  LineTracker tracker = make_tracker(0.3);
  BodyTwist previous{0.3, 0.0, 0.0};
  for (int k = 0; k < 100; ++k) {
    const double t = k * kTs;
    const double e_d = (k % 7 < 3 ? 0.05 : -0.08);
    const double e_theta = deg_to_rad(k % 5 < 2 ? 20.0 : -15.0);
    const TrackerOutput out = tracker.step(k % 11 == 0 ? lost(t) : seen(t, e_theta, e_d), t);
    EXPECT_EQ(check_limits(out.command, previous, kLimits, kTs), 0u) << "k=" << k;
    previous = out.command;
  }
}

// A curve of R 0.1 m previewed 0.4 m ahead at 0.3 m/s: turning through it at 0.3 m/s would take
// 3 rad/s, three times the yaw-rate limit. The vehicle must reach it at no more than
// 0.8 * w_max * R = 0.08 m/s (the rest of w_max left for corrections), drive it no faster, and
// speed up again once the path is straight.
TEST(LineTracker, SlowsInTimeForASharpCurveAheadAndSpeedsUpAfter) {
  LineTracker tracker = make_tracker(0.3);
  constexpr double kChange_m = 0.4, kCurveEnd_m = 0.55, kCurvature_1_m = 10.0;
  const double v_curve_m_s = 0.8 * kLimits.w_max_rad_s / kCurvature_1_m;
  BodyTwist previous{0.3, 0.0, 0.0};
  double travelled_m = 0.0;
  bool slowed = false;
  double fastest_on_curve_m_s = 0.0, last_speed_m_s = 0.0;
  for (int k = 0; k < 60; ++k) {
    const double t = k * kTs;
    LineMeasurement m = seen(t);
    if (travelled_m < kChange_m) {
      m.curvature_change_m = kChange_m - travelled_m;
      m.curvature_ahead_1_m = kCurvature_1_m;
    } else if (travelled_m < kCurveEnd_m) {
      m.curvature_1_m = kCurvature_1_m;
    }
    const TrackerOutput out = tracker.step(m, t);
    EXPECT_EQ(check_limits(out.command, previous, kLimits, kTs), 0u) << "k=" << k;
    if (k == 0) {
      EXPECT_NEAR(out.command.vx_m_s, 0.3, 1e-9) << "braking began too early";
    }
    slowed = slowed || (out.flags & kSlowForCurve);
    const double next_m = travelled_m + out.command.vx_m_s * kTs;
    // This period's travel reaches into the curve: it is driven at the curve's speed.
    if (next_m > kChange_m && travelled_m < kCurveEnd_m)
      fastest_on_curve_m_s = std::max(fastest_on_curve_m_s, out.command.vx_m_s);
    travelled_m = next_m;
    previous = out.command;
    last_speed_m_s = out.command.vx_m_s;
  }
  EXPECT_TRUE(slowed);
  EXPECT_GT(fastest_on_curve_m_s, 0.0) << "the curve was never reached";
  // 2 %: the turn-rate share is a design margin, the braking curve is met to rounding.
  EXPECT_LE(fastest_on_curve_m_s, 1.02 * v_curve_m_s);
  EXPECT_NEAR(last_speed_m_s, 0.3, 1e-9) << "not back to path speed on the straight after";
}

// With the curve speed off (curve_turn_fraction 0) the path speed is kept on any curve.
TEST(LineTracker, CurveSpeedOffKeepsThePathSpeed) {
  LineTracker::Options options;
  options.ts_s = kTs;
  options.path_speed_m_s = 0.3;
  options.curve_turn_fraction = 0.0;
  LineTracker tracker(std::make_unique<FiniteStepController>(FiniteStepController::Options{}),
                      kLimits, options, {0.3, 0.0, 0.0});
  LineMeasurement m = seen(0.0);
  m.curvature_1_m = 10.0;
  const TrackerOutput out = tracker.step(m, 0.0);
  EXPECT_NEAR(out.command.vx_m_s, 0.3, 1e-9);
  EXPECT_FALSE(out.flags & kSlowForCurve);
}

}  // namespace
}  // namespace agv::control
