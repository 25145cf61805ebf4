#include "perception/corner_fillet.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/angles.h"
#include "common/pose2.h"
#include "control/path.h"

namespace agv::perception {
namespace {

// A line 0.6 m long, an arc of R 0.11 m turning `turn_deg`, a line: control::Path lays it (its
// own geometry, the oracle). The fillet is given the points `in_back_m` before the arc's start
// and `out_on_m` past its end, with the path's directions there, in the frame of a vehicle
// `s_m` along the path, 4 mm left of it and turned 3 deg left; it is compared with the path's
// tracking errors for that vehicle.
struct Reading {
  std::optional<CurveModel> model;
  control::TrackingError truth;
};
Reading fillet_read(double turn_deg, double s_m, double in_back_m, double out_on_m) {
  constexpr double kLine_m = 0.6, kRadius_m = 0.11;
  const double arc_m = kRadius_m * deg_to_rad(std::abs(turn_deg));
  const control::Path path = control::Path::starting_at({0.0, 0.0, 0.0})
                                 .add_line(kLine_m)
                                 .add_arc(kRadius_m, deg_to_rad(turn_deg))
                                 .add_line(1.0);
  const double heading = path.heading_at(s_m);
  const Eigen::Vector2d left(-std::sin(heading), std::cos(heading));
  const Eigen::Vector2d at = path.point_at(s_m) + 0.004 * left;
  const Pose2 vehicle{at.x(), at.y(), heading + deg_to_rad(3.0)};
  const Pose2 to_vehicle = vehicle.inverse();
  const double s_in = kLine_m - in_back_m, s_out = kLine_m + arc_m + out_on_m;
  Reading r;
  r.model = corner_fillet(
      to_vehicle.transform(path.point_at(s_in)), path.heading_at(s_in) - vehicle.yaw_rad,
      to_vehicle.transform(path.point_at(s_out)), path.heading_at(s_out) - vehicle.yaw_rad);
  r.truth = path.tracking_error(vehicle, path.project(vehicle.translation(), s_m, 0.05));
  return r;
}

// Points at the arc's two ends, or one of them further along its line (the tape seen up to the
// arc on that side, a straight stretch unseen on the other): the arc is the path's, and the
// errors at the vehicle, before, on and past the arc, are the path's (to rounding: 1 nm, 1 urad),
// left and right, for corners of 50, 90 and 120 deg.
TEST(CornerFillet, TheArcTangentToTheWayInAndTheWayOutIsTheCornersArc) {
  for (double turn_deg : {50.0, -50.0, 90.0, -90.0, 120.0}) {
    const double arc_m = 0.11 * deg_to_rad(std::abs(turn_deg));
    for (auto [in_back_m, out_on_m] : {std::pair{0.0, 0.0}, {0.03, 0.0}, {0.0, 0.05}}) {
      for (double s_m = 0.57; s_m <= 0.6 + arc_m + 0.03; s_m += 0.01) {
        const Reading r = fillet_read(turn_deg, s_m, in_back_m, out_on_m);
        ASSERT_TRUE(r.model.has_value()) << turn_deg << " " << s_m;
        EXPECT_NEAR(r.model->e_d_m, r.truth.e_d_m, 1e-9) << turn_deg << " " << s_m;
        EXPECT_NEAR(wrap_angle_rad(-r.model->heading_rad - r.truth.e_theta_rad), 0.0, 1e-6)
            << turn_deg << " " << s_m;
        const bool on_arc = s_m > 0.6 + 1e-9 && s_m < 0.6 + arc_m - 1e-9;
        EXPECT_NEAR(r.model->curvature_1_m, on_arc ? std::copysign(1.0 / 0.11, turn_deg) : 0.0,
                    1e-6)
            << turn_deg << " " << s_m;
      }
    }
  }
}

// Both points further along their lines than the arc's ends (neither side seen up to the arc),
// 10 mm and 20 mm, round a 90 deg corner: the tangent length is 10 mm too long, the arc R 0.12 m
// for 0.11, its middle (sqrt(2) - 1) x 10 mm = 4.14 mm further out than the corner's (worked
// out from the geometry): the worst reading lies between 2 and 5 mm off (measured 4.14 mm).
TEST(CornerFillet, EndsShortOfTheArcWidenIt) {
  double worst_m = 0.0;
  for (double s_m = 0.57; s_m <= 0.6 + 0.11 * M_PI / 2.0 + 0.04; s_m += 0.005) {
    const Reading r = fillet_read(90.0, s_m, 0.01, 0.02);
    ASSERT_TRUE(r.model.has_value()) << s_m;
    worst_m = std::max(worst_m, std::abs(r.model->e_d_m - r.truth.e_d_m));
  }
  EXPECT_GT(worst_m, 0.002);  // the arc is not the corner's
  EXPECT_LT(worst_m, 0.005);
}

// Lines that meet behind the point in (the points past each other), hardly turn, or meet at the
// point in all but a micrometre (no arc worth the name, whose centre the origin could lie on):
// none.
TEST(CornerFillet, NoneWhereTheLinesDoNotMeetBetweenThePoints) {
  EXPECT_FALSE(corner_fillet({-1e-6, 0.0}, 0.0, {0.0, 0.1}, M_PI / 2.0).has_value());
  EXPECT_FALSE(corner_fillet({0.1, 0.0}, 0.0, {0.0, 0.1}, M_PI / 2.0).has_value());
  EXPECT_FALSE(corner_fillet({0.0, 0.0}, 0.0, {0.2, 0.001}, deg_to_rad(0.5)).has_value());
  EXPECT_FALSE(corner_fillet({0.0, 0.0}, 0.0, {-0.1, 0.0}, M_PI).has_value());
  EXPECT_TRUE(corner_fillet({0.0, 0.0}, 0.0, {0.1, 0.1}, M_PI / 2.0).has_value());
}

// Two lines at right angles meeting at (1, 0): 1 m ahead of the point in and 1 m behind the
// point out; with the point out moved to x = -1, the meeting point lies behind the point in
// (d_in -1 m); parallel lines meet nowhere.
TEST(CornerFillet, WhereTwoLinesMeet) {
  const std::optional<LinesMeet> ahead = where_lines_meet({0.0, 0.0}, 0.0, {1.0, 1.0}, M_PI / 2.0);
  ASSERT_TRUE(ahead.has_value());
  EXPECT_NEAR(ahead->d_in_m, 1.0, 1e-12);
  EXPECT_NEAR(ahead->d_out_m, 1.0, 1e-12);
  const std::optional<LinesMeet> behind =
      where_lines_meet({0.0, 0.0}, 0.0, {-1.0, 2.0}, M_PI / 2.0);
  ASSERT_TRUE(behind.has_value());
  EXPECT_NEAR(behind->d_in_m, -1.0, 1e-12);
  EXPECT_NEAR(behind->d_out_m, 2.0, 1e-12);
  EXPECT_FALSE(where_lines_meet({0.0, 0.0}, 0.0, {1.0, 1.0}, 0.0).has_value());
}

}  // namespace
}  // namespace agv::perception
