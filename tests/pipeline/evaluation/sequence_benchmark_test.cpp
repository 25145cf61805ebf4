#include "pipeline/evaluation/sequence_benchmark.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>

#include "common/angles.h"

namespace agv::pipeline {
namespace {

// Lines joined to arcs and S-bends, tape 10-100 mm wide with no width configured, perception as
// the loop runs it: once the vehicle drives over tape it saw, the errors at its origin come from
// the remembered tape and meet issue 4's bar for single clean frames (RMS 0.2 mm / 0.1 deg; the
// sequences' own goal, 0.1 mm / 0.05 deg, is not met on every draw: see the README). Seed 1's
// draws (printed on failure) measured 0.10 mm / 0.06 deg. Every frame has its line, none is
// followed the wrong way round, and the drive without tape gives no line.
TEST(SequenceBenchmark, JoinedArcsAndSBendsMeetTheSingleFrameBarAfterTheWarmUp) {
  SequenceBenchmarkOptions options;
  options.sequences = 3;
  options.empty_sequences = 1;
  options.path_length_m = 1.5;
  options.pieces = {PathPiece::kLine, PathPiece::kArc, PathPiece::kSBend};
  options.seed = 1;
  const SequenceBenchmarkResult result = run_sequence_benchmark(options);
  const nlohmann::json& j = result.summary;
  std::string draws;
  for (const std::string& text : result.sequence_texts) draws += "\n  " + text;
  SCOPED_TRACE("draws:" + draws + "\nsummary: " + j.dump());
  ASSERT_EQ(result.frames.size(), 3u * 150 + 100);
  EXPECT_GE(j["found_fraction"].get<double>(), 0.99);
  const nlohmann::json& after = j["after_warm_up"];
  EXPECT_GT(after["frames"].get<int>(), 3 * 90);  // 1.0 of the 1.5 m, less a lost frame or two
  EXPECT_LE(after["rms_e_d_m"].get<double>(), 0.0002);
  EXPECT_LE(rad_to_deg(after["rms_e_theta_rad"].get<double>()), 0.1);
  EXPECT_EQ(j["direction_flips"].get<int>(), 0);
  EXPECT_EQ(j["frames_without_tape"].get<int>(), 100);
  EXPECT_EQ(j["lines_reported_without_tape"].get<int>(), 0);
  // The figures are those of the frames: the RMS recomputed here from the per-frame errors.
  double sum = 0.0;
  int counted = 0;
  for (const SequenceFrame& f : result.frames) {
    if (!f.has_tape || !f.line_found || f.travelled_m < options.warm_up_m) continue;
    sum += f.error_e_d_m * f.error_e_d_m;
    ++counted;
  }
  EXPECT_EQ(counted, after["frames"].get<int>());
  EXPECT_NEAR(std::sqrt(sum / counted), after["rms_e_d_m"].get<double>(), 1e-12);
}

// One sequence of `agv evaluate --seed SEED` driven again (--only-sequence), its draw traced on
// failure.
SequenceBenchmarkResult one_drive(std::uint64_t seed, int sequence) {
  SequenceBenchmarkOptions options;
  options.seed = seed;
  options.empty_sequences = 0;
  options.only_sequence = sequence;
  return run_sequence_benchmark(options);
}

// agv evaluate --seed 12, sequence 4 (a corner of R 0.26 m turning 135 deg, then a fork taken
// left, camera 0.24 m up): past the corner one frame's reading from the remembered tape ran 148
// deg against the vehicle (a fit whose foot point lay round the bend), a direction flip. A
// reading that runs more than 90 deg from the vehicle's heading is no measurement: no flip.
TEST(SequenceBenchmark, NoReadingRunsAgainstTheVehiclePastATightCorner) {
  const SequenceBenchmarkResult result = one_drive(12, 4);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(4));
  EXPECT_EQ(result.summary["direction_flips"].get<int>(), 0);
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
}

// agv evaluate --seed 23, sequence 5 (88 mm tape, camera 0.12 m up; a corner of R 0.12 m
// turning 74 deg, then a fork taken right): approaching the corner, the line in view is its arc
// (R 0.13 m) at one frame, a short straight fit at the next. The model fitted to the nearer
// half of the evidence was oriented by its direction at the origin's foot point, which on so
// tight an arc may point either way: reversed, and the line in view was then kept reversed,
// frame after frame, to the end of the sequence. Where the memory had no tape under the vehicle,
// the line in view carried back ran 180 deg against the vehicle (130 direction flips). Compared
// where the evidence lies: no flip, and the whole sequence within 1.5 mm / 1.5 deg RMS after the
// warm-up (measured 0.68 mm / 0.62 deg; reversed, 4.9 mm / 132 deg).
TEST(SequenceBenchmark, ATightArcsNearModelRunsTheLinesWay) {
  const SequenceBenchmarkResult result = one_drive(23, 5);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(5));
  EXPECT_EQ(result.summary["direction_flips"].get<int>(), 0);
  const nlohmann::json& after = result.summary["after_warm_up"];
  EXPECT_LE(after["rms_e_d_m"].get<double>(), 0.0015);
  EXPECT_LE(rad_to_deg(after["rms_e_theta_rad"].get<double>()), 1.5);
}

// agv evaluate --seed 21, sequence 3 (19 mm tape; a corner of R 0.26 m turning -84 deg, 0.35 m
// of line, then a fork taken straight on, its branch bending right at R 0.73 m): the legs first
// showed as one band at the far edge of the view while the vehicle still turned out of the
// corner, the branch 0.8 deg nearer straight than the way straight on, and that choice was held:
// the branch was followed, 21.5 mm RMS and 112 mm off by the end. Held once the legs are apart:
// the sequence within 1 mm RMS after the warm-up, the fork's frames within 3 mm (measured 0.26 mm,
// 1.1 mm at worst).
TEST(SequenceBenchmark, AForksWayStraightOnIsChosenOnceTheLegsPart) {
  const SequenceBenchmarkResult result = one_drive(21, 3);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(3));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(result.summary["by_piece"]["fork"]["max_abs_e_d_m"].get<double>(), 0.003);
}

// agv evaluate --seed 18, sequence 11 (38 mm tape; an S-bend of R 0.70 m into a fork taken
// straight on, its branch bending left at R 0.87 m): the way straight on was chosen, then held as
// a direction in the vehicle frame while the vehicle turned 5 deg on the bend, which brought the
// branch nearer the direction held: the branch was followed, 9.2 mm RMS and 58 mm off by the end.
// Turned with the wheel odometry's yaw: within 1 mm RMS after the warm-up, the fork's frames
// within 3 mm (measured 0.25 mm, 1.2 mm at worst).
TEST(SequenceBenchmark, TheWayHeldAtAForkOnABendTurnsWithTheVehicle) {
  const SequenceBenchmarkResult result = one_drive(18, 11);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(11));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.98);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(result.summary["by_piece"]["fork"]["max_abs_e_d_m"].get<double>(), 0.003);
}

// agv evaluate --seed 30, sequence 3 (18 mm tape; a fork taken straight on, its branch bending
// left at R 0.64 m, then lines and S-bends): the first frame of the fork showed the branch as
// the one way out and it was held; the frames after renewed it with fits 3-6 deg apart, and the
// branch was kept to through the fork (its frames 64 mm RMS, 267 mm off). Renewed only by ways
// within 0.05 rad of it, it is forgotten five frames on and the way straight on taken: the fork's
// frames within 10 mm RMS, the pieces after it within 0.2 mm (measured 4.3 mm, 20 mm at worst
// where the branch was followed; 0.03 mm on the lines, 0.06 mm on the S-bends).
TEST(SequenceBenchmark, ABranchHeldAloneIsLetGoForTheWayStraightOn) {
  const SequenceBenchmarkResult result = one_drive(30, 3);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(3));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["by_piece"]["fork"]["rms_e_d_m"].get<double>(), 0.010);
  EXPECT_LE(result.summary["by_piece"]["line"]["rms_e_d_m"].get<double>(), 0.0002);
  EXPECT_LE(result.summary["by_piece"]["s-bend"]["rms_e_d_m"].get<double>(), 0.0002);
}

// agv evaluate --seed 33, sequence 7 (31 mm tape, camera 0.13 m up; a fork taken straight on,
// its branch bending right at R 0.49 m): the way held straight on moved frame by frame with poor
// fits between the legs (3, 1, 7, 2 deg) until it lay nearer the branch, which was then followed
// (31 mm RMS, 157 mm off). Moving at most 0.05 rad a frame: within 0.5 mm RMS after the warm-up,
// the fork's frames within 3 mm (measured 0.085 mm, 0.97 mm at worst).
TEST(SequenceBenchmark, TheWayHeldStraightOnIsNotCarriedToTheBranch) {
  const SequenceBenchmarkResult result = one_drive(33, 7);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(7));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.0005);
  EXPECT_LE(result.summary["by_piece"]["fork"]["max_abs_e_d_m"].get<double>(), 0.003);
}

// agv evaluate --seed 11, sequence 4: 98 mm tape 0.12 m under the camera, more than half the
// view, along arcs of R 1.8 and 1.0 m, no width given. Every bar that fits the view answers to
// it only next to its edges; its plateau is found instead. Bars: issue 17's 99 % found, and the
// single-frame bar of 0.2 mm / 0.1 deg RMS after the warm-up (measured 100 %, 0.098 mm / 0.040
// deg; without the plateau search 29 % found, 52 mm RMS off).
TEST(SequenceBenchmark, TapeFillingMoreThanHalfTheViewIsFollowed) {
  const SequenceBenchmarkResult result = one_drive(11, 4);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(4));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  const nlohmann::json& after = result.summary["after_warm_up"];
  EXPECT_LE(after["rms_e_d_m"].get<double>(), 0.0002);
  EXPECT_LE(rad_to_deg(after["rms_e_theta_rad"].get<double>()), 0.1);
}

// agv evaluate --seed 3, sequence 5: a fork of 71 mm tape (the branch right, R 0.85 m, 36 deg;
// straight on taken) from 0.17 m up. Where the legs still overlap their plateau reads 150 mm
// wide, one band; the line the bars find there is the tape followed. Bars: 99 % found, 0.5 mm
// RMS after the warm-up (measured 100 %, 0.17 mm). With the plateau's line taken wherever the
// bars' line runs inside it (without the strip test's share of the width and direction), 90 %
// and 6.0 mm: the overlap's middle carried back.
TEST(SequenceBenchmark, AForksOverlappingLegsAreNotOneWideTape) {
  const SequenceBenchmarkResult result = one_drive(3, 5);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(5));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.0005);
}

// agv evaluate --seed 11, sequence 7: 86 mm tape 0.18 m under the camera, corners of R 0.10 and
// 0.19 m. The chord centres the memory takes there lie within 0.15 mm on average of the tape's
// centre line, 0.5 mm RMS (measured against the laid tape), but registering each frame's
// evidence, read a little differently from each place in the view, moved the remembered tape
// under the vehicle by up to 1 mm a frame, 3.5 mm in all, while the wheel odometry's prior let
// the memory move 0.4 mm a frame (0.82 mm RMS after the warm-up; 0.44 mm with the prior growing
// only with the distance rolled, PathMemoryOptions::wheels_prior). Bound: 0.6 mm, about what the
// evidence itself carries on these corners.
TEST(SequenceBenchmark, ACornersEvidenceDoesNotDragTheTapeUnderTheVehicle) {
  const SequenceBenchmarkResult result = one_drive(11, 7);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(7));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.0006);
}

// agv evaluate --seed 8, sequence 11: a corner of R 0.11 m turning 53 deg, 84 mm tape, 0.24 m
// up. At its apex the memory held no tape just ahead of the vehicle (no chord one tape wide
// there) and one frame fell back to the line in view: the outgoing leg, which passes the arc's
// last foot point within 12 mm but runs half the corner (26 deg) from it, carried back 10.5 mm /
// 26 deg off. The line in view continues the arc only where it runs in the arc's direction
// (within its curvature times the distance driven); else the arc is carried forward. Bound: the
// corner's frames within 5 mm / 15 deg, half the outgoing leg's error and well under the corner's
// half-turn (measured 2.8 mm / 10.0 deg).
TEST(SequenceBenchmark, MidCornerTheOutgoingLegIsNotTakenForTheArc) {
  const SequenceBenchmarkResult result = one_drive(8, 11);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(11));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  const nlohmann::json& corner = result.summary["by_piece"]["corner"];
  EXPECT_LE(corner["max_abs_e_d_m"].get<double>(), 0.005);
  EXPECT_LE(rad_to_deg(corner["max_abs_e_theta_rad"].get<double>()), 15.0);
}

// agv evaluate --seed 1, sequence 6: a corner of R 0.10 m turning 118 deg, 20 mm tape, then a
// line. The camera never saw the line's first 0.14 m under it; the memory bridges that gap from
// the corner's end behind to the line ahead. The quadratic through the end behind's last 40 mm
// (part arc, part line) overshoots there, 4.4 deg past the line's direction, and the cubic
// between the ends bulged 2.6 mm. The corner had finished turning: the line ahead is the tape
// (PathMemory's line_after_corner_arc). Bound: the line's frames 0.3 mm RMS, 1.2 mm at worst
// (measured 0.16 / 1.0 mm, the first frame past the corner; with the bulge 0.85 / 2.6 mm).
TEST(SequenceBenchmark, TheLineAfterACornerIsNotBentByTheCornersEnd) {
  const SequenceBenchmarkResult result = one_drive(1, 6);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(6));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  const nlohmann::json& line = result.summary["by_piece"]["line"];
  EXPECT_LE(line["rms_e_d_m"].get<double>(), 0.0003);
  EXPECT_LE(line["max_abs_e_d_m"].get<double>(), 0.0012);
}

// agv evaluate --seed 43, sequence 5: a corner of R 0.10 m turning 114 deg, 53 mm tape, then an
// S-bend (R 0.64 m turning back 43 deg). The camera never saw the corner's exit and the bend's
// start: the memory bridges 0.25 m from the corner's end behind to the tape ahead. The end
// behind was the tape within 40 mm along the frame, which past so tight a corner took in its
// whole arc (running across the frame there): the quadratic through it turned the end's
// direction by up to 20 deg from frame to frame, the bridge 14.6 mm / 15.4 deg off (1.90 mm /
// 2.36 deg RMS). Taken within 40 mm of the end's last point: measured 0.49 mm / 0.54 deg RMS,
// 3.6 mm / 3.3 deg at worst (a cubic between the ends' directions does not follow a tape that
// bends both ways across the gap; the arc carried on 80 mm from the end remembered, whose
// direction moved with the registration's local course taking the evidence's own bend: 0.36 mm /
// 0.41 deg, 1.8 mm / 3.6 deg before). Bounds: 0.6 mm / 0.6 deg RMS, 5 mm / 5 deg at worst (a
// third of the whole arc's 14.6 mm / 15.4 deg).
TEST(SequenceBenchmark, AGapPastATightCornerIsBridgedFromTheCornersEndNotItsWholeArc) {
  const SequenceBenchmarkResult result = one_drive(43, 5);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(5));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  const nlohmann::json& after = result.summary["after_warm_up"];
  EXPECT_LE(after["rms_e_d_m"].get<double>(), 0.0006);
  EXPECT_LE(rad_to_deg(after["rms_e_theta_rad"].get<double>()), 0.6);
  EXPECT_LE(after["max_abs_e_d_m"].get<double>(), 0.005);
  EXPECT_LE(rad_to_deg(after["max_abs_e_theta_rad"].get<double>()), 5.0);
}

// Sequence `sequence` of seed `seed` driven again: found on 98 % of its frames, its fork's
// frames within the bounds of a reading from the remembered tape, 0.3 mm RMS (the memory's
// readings over seeds 1-48), 1 mm and 2 deg at worst.
void expect_fork_read_from_the_memory(std::uint64_t seed, int sequence) {
  const SequenceBenchmarkResult result = one_drive(seed, sequence);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(sequence));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.98);
  const nlohmann::json& fork = result.summary["by_piece"]["fork"];
  EXPECT_LE(fork["rms_e_d_m"].get<double>(), 0.0003);
  EXPECT_LE(fork["max_abs_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(rad_to_deg(fork["max_abs_e_theta_rad"].get<double>()), 2.0);
}

// agv evaluate --seed 44, sequence 4: a fork of 88 mm tape, the branch leaving left at a tangent
// (R 0.62 m), the way taken right (straight on); the camera 0.16 m up sees only the legs'
// overlap (0.33 m long) before the vehicle is in it. Its chords, wider than the tape, gave the
// memory no evidence where the leg leaving was not the one taken, and the slightly wider ones
// their middles, half the branch's offset off: the memory under the vehicle bent towards the
// branch, then followed it (the fork's frames 7.1 mm RMS, 28.9 mm at worst). The way taken
// running on along the course, its centre is half a width in from the chords' edge on the
// course's edge: measured 0.065 / 0.173 mm, 0.74 deg at worst.
TEST(SequenceBenchmark, AtAForkTheWayRunningOnIsRememberedFromItsEdgeOnTheCourse) {
  expect_fork_read_from_the_memory(44, 4);
}

// agv evaluate --seed 42, sequence 10: a fork of 62 mm tape (the branch right, R 0.47 m) taken
// straight on, the camera 0.18 m up and tilted 5.5 deg. The legs' overlap gave no evidence (no
// chord one tape wide; the slightly wider ones their middles, bent towards the branch): the
// fork's frames 4.0 mm RMS, 19.5 mm at worst, 28 frames carried back from the view. Every leg
// leaving being the other one, the way straight on is read half a width in from the chords'
// edge on the course's edge: measured 0.087 / 0.226 mm, 0.39 deg at worst, none carried back.
TEST(SequenceBenchmark, AtAForkTakenStraightOnTheWayRunningOnIsRememberedFromItsEdge) {
  expect_fork_read_from_the_memory(42, 10);
}

// agv evaluate --seed 15, sequence 2: an S-bend whose last arc (R 0.66 m) ends at a fork of 85 mm
// tape whose branch bends the same way (right, R 0.85 m), taken straight on. The course carried
// on round the arc runs into the branch, the way straight on looks like the leg leaving: read
// so, the branch was remembered and followed (the fork's frames 14.9 mm RMS, 60 mm at worst).
// Round an arc (PathMemoryOptions::straight_course_arc_from_1_m) legs leaving on the outside of
// its bend are not read: measured 0.85 / 4.5 mm (the line in view follows the branch for a few
// frames: the memory, bending towards it there, is 4.5 mm off before it restarts). Bounds: 1.5 mm
// RMS, 10 mm at worst (the branch is 40 mm away where it was followed).
TEST(SequenceBenchmark, StraightOnPastAnArcBendingLikeTheBranchTheBranchIsNotRemembered) {
  const SequenceBenchmarkResult result = one_drive(15, 2);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(2));
  const nlohmann::json& fork = result.summary["by_piece"]["fork"];
  EXPECT_LE(fork["rms_e_d_m"].get<double>(), 0.0015);
  EXPECT_LE(fork["max_abs_e_d_m"].get<double>(), 0.01);
}

// agv evaluate --seed 45, sequence 9: a corner of R 0.11 m turning 50 deg left, approached on a
// line, 15 mm tape, the camera 0.22 m up: the camera saw the corner as two legs meeting, the memory
// has the way in and the way out and nothing between them. Inside the corner the way out was
// carried back from the view, or the way in carried forward (the corner's frames 3.3 mm RMS, 13.1
// mm and 28.9 deg at worst). The arc tangent to both (PathMemoryOptions::corner_gap_view_turn_rad)
// reads them: measured 0.38 / 0.93 mm, 2.5 deg at worst (the arc from the ends widened by
// what was not seen of the lines next to it). Bounds: 1 mm RMS, 2 mm and 5 deg at worst.
TEST(SequenceBenchmark, InsideATightCornerNeverSeenWholeTheArcJoiningItsLegsIsRead) {
  const SequenceBenchmarkResult result = one_drive(45, 9);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(9));
  const nlohmann::json& corner = result.summary["by_piece"]["corner"];
  EXPECT_LE(corner["rms_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(corner["max_abs_e_d_m"].get<double>(), 0.002);
  EXPECT_LE(rad_to_deg(corner["max_abs_e_theta_rad"].get<double>()), 5.0);
}

// agv evaluate --seed 6, sequence 9: a fork of 91 mm tape (the branch left, R 0.57 m) taken
// straight on, 0.16 m under the camera. Its legs overlap for 0.3 m, where no chord is one tape
// wide: a hole in the memory under the vehicle, across which the line in view carried back was
// up to 9.4 mm off (28 frames carried back, the fork's frames 1.7 mm RMS). The curve through
// the stem behind the hole and the leg past it (PathMemory's through_gap) reads them. Bound:
// the fork's frames 1 mm RMS, 10 frames carried back (measured 0.64 mm, 7 frames).
TEST(SequenceBenchmark, AForkOfWideTapeTakenStraightOnIsReadAcrossItsOverlap) {
  const SequenceBenchmarkResult result = one_drive(6, 9);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(9));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.97);
  EXPECT_LE(result.summary["after_warm_up"]["frames_extrapolated"].get<int>(), 10);
  EXPECT_LE(result.summary["by_piece"]["fork"]["rms_e_d_m"].get<double>(), 0.001);
}

// agv evaluate --seed 36, sequence 0 (72 mm tape, the camera 0.14 m up): after a corner that
// turned out of the view, straight tape remembered from 0.09 m ahead of the vehicle, the next
// corner (R 0.12 m) in view beyond it. The tape ahead was read along the line in view, an arc
// through that corner 70 deg off at the origin, and held too few remembered points: the arc
// carried back, 120-184 mm off for 8 frames (27.7 mm RMS). Read along the tape ahead read the
// frame before: the line pieces within 3 mm (measured 1.2 mm at worst; 1.9 mm RMS after the
// warm-up, most of it the corner's frames carried back with nothing remembered near).
TEST(SequenceBenchmark, TheTapeAheadIsReadAlongItselfNotAlongTheLineInView) {
  const SequenceBenchmarkResult result = one_drive(36, 0);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(0));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.95);
  EXPECT_LE(result.summary["by_piece"]["line"]["max_abs_e_d_m"].get<double>(), 0.003);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.004);
}

// agv evaluate --seed 27, sequence 11 (14 mm tape; a fork taken left, then the path crosses
// itself at 52 deg a metre on): the crossing tape's half to the left was taken as the way left
// and followed, 15.6 mm RMS, 117 mm off. A tape crossing is no junction: straight through, within
// 1 mm RMS after the warm-up and 3 mm at worst (measured 0.30 mm, 1.1 mm).
TEST(SequenceBenchmark, ATapeCrossingIsDrivenStraightThrough) {
  const SequenceBenchmarkResult result = one_drive(27, 11);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(11));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.98);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(result.summary["after_warm_up"]["max_abs_e_d_m"].get<double>(), 0.003);
}

// agv evaluate --seed 36, sequence 1 (60 mm tape; a fork taken straight on, its branch bending
// right at R 0.62 m): where the legs overlapped, the junction found offered only the branch, the
// way straight on a line of its own beside it; the branch was followed, remembered as the tape
// under the vehicle and read there, 6.7 mm RMS and 45 mm off. The line along the way held
// instead: the fork's frames within 3 mm, 1 mm RMS after the warm-up (measured 1.5 mm at worst,
// 0.13 mm).
TEST(SequenceBenchmark, TheWayHeldIsFollowedWhereTheJunctionOffersOnlyTheBranch) {
  const SequenceBenchmarkResult result = one_drive(36, 1);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(1));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.98);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.001);
  EXPECT_LE(result.summary["by_piece"]["fork"]["max_abs_e_d_m"].get<double>(), 0.003);
}

// agv evaluate --seed 18, sequence 2 (92 mm light grey tape on a blotchy floor whose light
// blotches come near the tape's brightness): the walk to each edge crossed the gap of floor
// between the tape and such a blob as a worn spot and put the edge on the blob's rim, and most
// frames gave no line (72 % found, 16.9 mm RMS after the warm-up, 104 mm at worst). Taking the
// edge that lines up with the neighbouring scan lines': issue 17's 99 % found, and 0.5 mm RMS
// after the warm-up (measured 100 %, 0.16 mm, 0.6 mm at worst).
TEST(SequenceBenchmark, LightTapeOnABlotchyFloorIsFound) {
  const SequenceBenchmarkResult result = one_drive(18, 2);
  SCOPED_TRACE("draw: " + result.sequence_texts.at(2));
  EXPECT_GE(result.summary["found_fraction"].get<double>(), 0.99);
  EXPECT_LE(result.summary["after_warm_up"]["rms_e_d_m"].get<double>(), 0.0005);
}

// The paths are laid from the pieces named, after the lead-in line (a corner is followed by
// 0.3 m of line); a fork comes at most once a sequence; the same seed gives the same frames.
TEST(SequenceBenchmark, PathsAreLaidFromTheNamedPiecesAndTheSameSeedRepeats) {
  SequenceBenchmarkOptions options;
  options.sequences = 1;
  options.empty_sequences = 0;
  options.path_length_m = 1.0;
  options.pieces = {PathPiece::kCorner, PathPiece::kFork};
  const SequenceBenchmarkResult first = run_sequence_benchmark(options);
  std::set<std::string> pieces;
  for (const SequenceFrame& f : first.frames) pieces.insert(f.piece);
  for (const std::string& piece : pieces)
    EXPECT_TRUE(piece == "line" || piece == "corner" || piece == "fork") << piece;
  EXPECT_GE(pieces.size(), 2u);
  const std::string& text = first.sequence_texts.front();
  EXPECT_EQ(text.find("fork"), text.rfind("fork")) << text;
  EXPECT_EQ(text.find(" arc "), std::string::npos) << text;
  const SequenceBenchmarkResult again = run_sequence_benchmark(options);
  ASSERT_EQ(again.frames.size(), first.frames.size());
  for (size_t i = 0; i < first.frames.size(); ++i) {
    EXPECT_EQ(again.frames[i].line_found, first.frames[i].line_found) << i;
    EXPECT_EQ(again.frames[i].error_e_d_m, first.frames[i].error_e_d_m) << i;
  }
}

TEST(SequenceBenchmark, PiecesAreNamedOrRefused) {
  for (PathPiece piece :
       {PathPiece::kLine, PathPiece::kArc, PathPiece::kSBend, PathPiece::kCorner, PathPiece::kFork})
    EXPECT_EQ(parse_path_piece(path_piece_name(piece)), piece);
  EXPECT_THROW(parse_path_piece("zigzag"), std::invalid_argument);
  SequenceBenchmarkOptions none;
  none.pieces.clear();
  EXPECT_THROW(run_sequence_benchmark(none), std::invalid_argument);
}

}  // namespace
}  // namespace agv::pipeline
