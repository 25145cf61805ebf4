#include "perception/nearest_piece.h"

#include <gtest/gtest.h>

#include <cmath>

namespace agv::perception {
namespace {

// A chord across tape of width_m whose centre line passes `centre` along `tangent`.
Chord across(const Eigen::Vector2d& centre, const Eigen::Vector2d& tangent, double width_m) {
  const Eigen::Vector2d n(-tangent.y(), tangent.x());
  return {centre + 0.5 * width_m * n, centre - 0.5 * width_m * n};
}

DetectedLine line_of_all(const std::vector<Chord>& chords, double residual_rms_m) {
  DetectedLine line;
  for (int i = 0; i < static_cast<int>(chords.size()); ++i) line.clean_chords.push_back(i);
  line.residual_rms_m = residual_rms_m;
  return line;
}

// A straight 0.1 m long at y = 10 mm running into an arc of R 0.3 m turning left: the piece
// nearest the vehicle is that straight, whatever one curve fitted to both says (geometry alone
// is the oracle: the piece passes through the straight's points along +x, unbent).
TEST(NearestPiece, IsTheStraightBeforeAnArc) {
  std::vector<Chord> chords;
  for (double x = 0.15; x < 0.25; x += 0.002)
    chords.push_back(across({x, 0.01}, {1.0, 0.0}, 0.025));
  const Eigen::Vector2d centre(0.25, 0.31);
  for (double a = 0.0; a < 0.5; a += 0.002 / 0.3) {
    const Eigen::Vector2d p = centre + 0.3 * Eigen::Vector2d(std::sin(a), -std::cos(a));
    chords.push_back(across(p, {std::cos(a), std::sin(a)}, 0.025));
  }
  // What one arc through all of it would read: about the straight's direction, bent.
  const CurveModel whole{-0.008, 0.05, 1.5};
  const std::optional<CurveModel> piece = nearest_piece(chords, line_of_all(chords, 0.002), whole);
  ASSERT_TRUE(piece.has_value());
  // Exact points: the straight's fit is exact to rounding; 0.1 mm allows the breakpoint's
  // placement to leave a point or two of the arc in it.
  for (double x : {0.16, 0.2, 0.24}) EXPECT_NEAR(piece->signed_distance({x, 0.01}), 0.0, 1e-4);
  EXPECT_GT(piece->tangent_at(piece->arc_position({0.2, 0.01})).x(), 0.9999);
  // Unbent but for those points: 0.01 1/m moves the line carried back 0.25 m by 0.3 mm.
  EXPECT_NEAR(piece->curvature_1_m, 0.0, 0.01);
}

// At a fork of 94 mm tape (agv evaluate seed 7, sequence 3, frame 283, as the estimator saw it):
// 29 chords across the tape 0.35-0.40 m ahead and one that ran 0.15 m along its edge. The joined
// fit turned by 58, 84 and 80 deg in its three passes and ended reversed; the line then read
// 180 deg off. Whatever the piece, it must run the line's way there (or be none).
TEST(NearestPiece, NeverRunsAgainstTheLine) {
  const std::vector<Chord> chords = {
      {{0.283950, 0.046536}, {0.129742, 0.049881}},  {{0.402874, 0.047465}, {0.404422, -0.046229}},
      {{0.402291, 0.047467}, {0.403831, -0.046240}}, {{0.401707, 0.047441}, {0.403240, -0.046248}},
      {{0.401124, 0.047407}, {0.402649, -0.046241}}, {{0.400540, 0.047413}, {0.402057, -0.046249}},
      {{0.399956, 0.047454}, {0.401465, -0.046214}}, {{0.395867, 0.047446}, {0.397323, -0.046221}},
      {{0.395283, 0.047425}, {0.396732, -0.046235}}, {{0.394699, 0.047412}, {0.396140, -0.046233}},
      {{0.394114, 0.047450}, {0.395548, -0.046252}}, {{0.392945, 0.047429}, {0.394364, -0.046252}},
      {{0.374211, 0.047413}, {0.375393, -0.046276}}, {{0.373038, 0.047394}, {0.374206, -0.046279}},
      {{0.372452, 0.047397}, {0.373611, -0.046236}}, {{0.371865, 0.047388}, {0.373017, -0.046231}},
      {{0.371279, 0.047401}, {0.372424, -0.046272}}, {{0.368345, 0.047384}, {0.369453, -0.046252}},
      {{0.364235, 0.047364}, {0.365293, -0.046295}}, {{0.362472, 0.047418}, {0.363509, -0.046277}},
      {{0.361884, 0.047393}, {0.362914, -0.046293}}, {{0.361297, 0.047368}, {0.362319, -0.046290}},
      {{0.360709, 0.047368}, {0.361724, -0.046292}}, {{0.360121, 0.047352}, {0.361129, -0.046296}},
      {{0.359533, 0.047354}, {0.360534, -0.046286}}, {{0.358945, 0.047366}, {0.359939, -0.046318}},
      {{0.358357, 0.047382}, {0.359344, -0.046291}}, {{0.353061, 0.047407}, {0.353985, -0.046364}},
      {{0.350706, 0.047387}, {0.351600, -0.046362}}, {{0.350116, 0.047400}, {0.351004, -0.046348}}};
  const CurveModel line_model{-0.000506, 0.000203, 0.0};
  const std::optional<CurveModel> piece =
      nearest_piece(chords, line_of_all(chords, 4.93e-5), line_model);
  if (piece) {
    EXPECT_GT(piece->tangent_at(piece->arc_position({0.37, 0.0})).x(), 0.0);
  }
}

}  // namespace
}  // namespace agv::perception
