#include "perception/one_edge_line.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "perception/curve_fit.h"

namespace agv::perception {
namespace {

constexpr double kOneEdgeWidthM = 0.09;

// The tape's centre line: an arc of R 0.5 m turning left, through (0.3 m, 0.02 m) heading 0.1
// rad (vehicle frame), so that it is seen 0.25-0.35 m ahead.
CurveModel centre_line() { return curve_through_point({0.3, 0.02}, 0.1, 2.0); }

// Chords of a tape whose edge on `seen_side` (+1: left of the centre line, -1: right) is in view
// and whose other edge lies beyond the image border: a is on the seen edge, b where the tape
// leaves the image, `reach` (a fraction of the width) across from a towards the tape. Exact
// geometry: the centre line's point at s moved along its normal there.
std::vector<Chord> one_edge_chords(int seen_side, double reach) {
  const CurveModel centre = centre_line();
  const double s0 = centre.arc_position({0.25, 0.0});
  std::vector<Chord> chords;
  for (int i = 0; i < 50; ++i) {
    const double s = s0 + 0.002 * i;
    const Eigen::Vector2d t = centre.tangent_at(s);
    const Eigen::Vector2d n(-t.y(), t.x());  // left of the centre line
    const Eigen::Vector2d edge = centre.point_at(s) + seen_side * 0.5 * kOneEdgeWidthM * n;
    // Not every row leaves the same part of the tape in view.
    const double across = reach * kOneEdgeWidthM * (0.7 + 0.3 * ((i % 5) / 4.0));
    chords.push_back({edge, edge - seen_side * across * n});
  }
  return chords;
}

OneEdgeOptions options() {
  OneEdgeOptions o;
  o.scan_spacing_m = 0.002;
  return o;
}

// Either edge of an arc of tape, with the width known, gives the tape's centre line: the same
// e_d, heading and curvature as the centre line itself (exact points: 1 micrometre, 1e-4 rad,
// 1e-3 1/m). The edge is an arc of R 0.5 -+ 0.045 m; moving it by the half-width towards the
// tape is what brings it onto the centre (a shift the wrong way, or the edge's own curvature
// kept, is off by 90 um or 0.2 1/m). The chords come back completed: each a tape width across.
TEST(OneEdgeLine, EitherEdgeAndTheWidthGiveTheCentreLine) {
  const CurveModel truth = centre_line();
  for (int seen_side : {1, -1}) {
    SCOPED_TRACE(seen_side > 0 ? "left edge seen" : "right edge seen");
    std::vector<Chord> completed;
    std::string why;
    const auto line = line_from_one_edge(one_edge_chords(seen_side, 0.6), kOneEdgeWidthM,
                                         Eigen::Vector2d::UnitX(), options(), &completed, &why);
    ASSERT_TRUE(line.has_value()) << why;
    EXPECT_NEAR(line->model.e_d_m, truth.e_d_m, 1e-6);
    EXPECT_NEAR(line->model.heading_rad, truth.heading_rad, 1e-4);
    EXPECT_NEAR(line->model.curvature_1_m, truth.curvature_1_m, 1e-3);
    EXPECT_EQ(line->width_m, kOneEdgeWidthM);
    ASSERT_EQ(line->clean_chords.size(), 50u);
    for (int index : line->clean_chords) {
      EXPECT_NEAR((completed[index].a - completed[index].b).norm(), kOneEdgeWidthM, 1e-9);
      EXPECT_NEAR(truth.signed_distance(completed[index].centre()), 0.0, 1e-5);
    }
  }
}

// What is no tape of the width known: more of it in view beside the edge than the tape is wide
// (another, wider strip; a shadow), the tape on both sides of the edge, no width at all.
TEST(OneEdgeLine, RefusesWhatIsNoTapeOfTheWidthKnown) {
  std::vector<Chord> completed;
  std::string why;
  EXPECT_FALSE(line_from_one_edge(one_edge_chords(1, 1.5), kOneEdgeWidthM, Eigen::Vector2d::UnitX(),
                                  options(), &completed, &why));
  EXPECT_NE(why.find("more tape in view"), std::string::npos) << why;

  std::vector<Chord> both_sides = one_edge_chords(1, 0.6);
  for (size_t i = 0; i < both_sides.size(); i += 2)
    both_sides[i].b = 2.0 * both_sides[i].a - both_sides[i].b;  // mirrored across the edge
  EXPECT_FALSE(line_from_one_edge(both_sides, kOneEdgeWidthM, Eigen::Vector2d::UnitX(), options(),
                                  &completed, &why));
  EXPECT_NE(why.find("both sides"), std::string::npos) << why;

  EXPECT_FALSE(line_from_one_edge(one_edge_chords(1, 0.6), 0.0, Eigen::Vector2d::UnitX(), options(),
                                  &completed, &why));
  EXPECT_NE(why.find("no tape width"), std::string::npos) << why;
}

}  // namespace
}  // namespace agv::perception
