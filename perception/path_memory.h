#pragma once

#include <Eigen/Core>
#include <Eigen/Dense>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/line_measurement.h"
#include "common/pose2.h"
#include "perception/curve_fit.h"
#include "perception/line_estimator.h"

namespace agv::perception {

// Where the odometry's motion since the last frame came from.
enum class OdometryKind { wheels, frames, guess };

struct PathMemoryOptions {
  double keep_behind_m = 0.25;  // tape remembered behind the vehicle origin
  // Evidence seen at most this far back along the way is kept (the camera may see the tape
  // 0.45 m ahead, which stays needed until keep_behind_m behind), and of at most this many frames
  // (a vehicle standing still).
  double keep_travel_m = 0.8;
  int keep_frames = 120;
  // Remembered tape ahead of the vehicle farther than way_gate_m across the followed line's
  // course, where that course carried back agrees with the course last measured under the
  // vehicle (within way_agreement_m across and way_agreement_rad in direction, last measured
  // within way_recent_m driven), is a way not taken (off_the_way_ahead). Over 1 deg the tape
  // between may turn (a joint's arc); within it and 2 mm at the origin, tape between the two
  // that runs on into the line in view lies within about 1 mm of its course.
  double way_gate_m = 0.005;
  double way_agreement_m = 0.002;
  double way_agreement_rad = 0.0175;
  double way_recent_m = 0.03;
  // Going straight on, tape remembered on the side the line in view turns away from by more than
  // this curvature is kept (the line in view may be the branch).
  double way_straight_turn_1_m = 0.2;
  // The branch's stretch within way_gate_m of the way (its first 7 cm at R 0.5 m, which the fit
  // at the origin followed, 6 frames up to 3.6 mm / 6.9 deg off), found from where the branch
  // leaves the way, worked out from its next way_stub_fit_m, is forgotten too where more than
  // way_stub_min_m off.
  double way_stub_fit_m = 0.04;
  double way_stub_min_m = 0.0001;
  // Each frame's evidence point is fused into the remembered point nearest to it within fuse_m
  // (their mean, each observation counting alike up to fuse_max_observations, after which newer
  // ones count for more), or added where none is that near: the memory holds each stretch of
  // tape about once, not once per frame that saw it (agv bench: 312 points, not 1969, the memory
  // 2.3x faster), and a point counts in the registration, the coverage tests and the fits as the
  // observations it is the mean of. 0: every frame's evidence kept as it came. agv evaluate
  // seeds 1-8, RMS after 0.5 m: 0.586 mm / 0.591 deg kept as it came, 0.593 / 0.600 fused at 2 mm,
  // 0.603 / 0.730 at 1 mm (forks' few frames on the other leg move either way).
  double fuse_m = 0.002;
  int fuse_max_observations = 20;
  double window_m = 0.05;        // the tape this far either side of the origin gives the errors
  double min_cover_m = 0.025;    // ... and must reach at least this far on both sides, or on
                                 //     one side, and on the other at least to one_side_reach_m
                                 //     short of the origin (see at_origin)
  double one_side_reach_m = 0.005;
  double window_across_m = 0.1;  // ... and lie no further than this across it
  // ... and turn the tape's direction there from the one last measured by no more than this
  // plus max_curvature_1_m times the distance driven since (R 0.1 m). 0.2 rad let a fit through
  // a fork's two legs under the vehicle read 15.5 deg off in one frame (agv evaluate seed 4,
  // sequence 3: 0.98 -> 0.10 deg RMS at 0.1 rad; no other sequence or example changed by more
  // than 0.01 mm / 0.01 deg).
  double max_turn_rad = 0.1;
  double max_curvature_1_m = 10.0;
  // ... and put the tape no further across from both the line in view carried back and the
  // course last measured carried forward than a tape width (at least 10 mm) and this: another
  // stretch of the path passing beside the vehicle fills the window where the tape under it was
  // never seen (agv evaluate seed 3, sequence 11: a frame 91 mm off; seeds 1-8 RMS after 0.5 m
  // 1.49 -> 1.45 mm).
  double max_offset_jump_m = 0.01;
  // Where the remembered tape starts ahead of the origin with none behind it (the stretch after a
  // corner that the camera, turned away, never saw under it): the errors from the remembered tape
  // nearest ahead, if it starts within ahead_max_gap_m, over ahead_span_m, one arc fitted with a
  // residual under ahead_max_rms_m, flagged extrapolated, rather than from the line in view
  // carried back 0.2-0.4 m (agv evaluate seed 5, sequence 8: a fork's branch in view carried back
  // 96 mm off, now 0.1 mm; seeds 1-8 RMS after 0.5 m 1.45 -> 1.19 mm).
  double ahead_max_gap_m = 0.1;
  double ahead_span_m = 0.1;
  double ahead_max_rms_m = 0.0005;
  double ahead_min_kept = 0.95;  // ... keeping this fraction of the points (no other tape there)
  // ... and agreeing with the course last measured under the vehicle carried forward to within
  // these, plus what its curvature turns over the distance driven since.
  double ahead_course_offset_m = 0.003;
  double ahead_course_turn_rad = 0.05;
  int min_points = 12;
  int side_points = 5;                  // points that must lie beyond min_cover_m on each side
  // ... and fitted with a residual under this (the tape's centre line: agv evaluate seeds 1-3
  // and 12, 12 766 fits: median 0.012 mm, 99.9 % under 0.7 mm; 11 over 3 mm, where a fork's
  // branch remembered beside the way taken, or another leg, shares the window: the fit through
  // both ran off by up to 64 deg, seed 12 sequence 4 five frames up to 62 mm off). A fit over it
  // is done again with only the points within a tape width of the course last measured carried
  // forward, and refused if still over (seeds 1-12: RMS after the warm-up 2.03 -> 1.93 mm, 1.32
  // -> 1.07 deg; 18 frames 3-62 mm off now within 0.2 mm, none worse by 1 mm or 0.5 deg). 1 mm,
  // not 2: where a fork's legs part under the vehicle, fits through points of both kept 1.2-1.3
  // mm (scenarios/fork_left.yaml started 0.50 m along at 0.32 m/s: a frame 9.6 mm off, the run
  // 1.141 -> 0.049 mm RMS; agv evaluate seeds 1-12: no sequence changed by 0.001 mm).
  double max_fit_rms_m = 0.001;
  // Read from one side, the window's tape is fitted with two joined arcs only where their
  // residual is less than one arc's by this factor: a joint fitted to the scatter of the points
  // left the origin on a piece of a few points beyond it, whose curvature was anyone's guess
  // (agv evaluate seed 43, sequence 9: 0.5 1/m read in a corner of R 0.28 m, 3.6 1/m the frame
  // before; the arc then not carried on past the tape seen, and the corner's outgoing leg
  // carried back read up to 51 mm off). A real joint there (a corner's arc running into the line
  // after it) fits over 3 times better. 0 keeps every joint.
  double one_side_joint_gain = 1.5;
  double chord_width_tolerance = 0.06;  // evidence: chords this near the tape's median width
  // Where a fork's legs still overlap and no other leg is seen apart (a branch leaving
  // tangentially), their chords are wider than the tape and none is evidence: the memory had a
  // hole there, just where the vehicle leaves for the branch it takes (scenarios/fork_left.yaml
  // and fork_right.yaml with the start moved by up to 4 cm or the speed by 0.02 m/s: 14 and 17 of
  // 18 runs 1.1-7.8 mm RMS). A chord of the followed line that is not clean, wider than the tape
  // by more than chord_width_tolerance along the normals of both the course last measured
  // (carried forward) and the line in view, narrower than two tapes, with one edge within
  // overlap_edge_tolerance tape widths of the course's edge and the other beyond the course's
  // other edge, spans the tape running on and a leg leaving on that side. Where that is the side
  // taken (BranchChoice left or right), the leaving leg's centre is half a width in from its outer
  // edge; where the leg leaving is the other one (the way taken runs on along the course), the
  // way taken's centre is half a width in from the chord's edge on the course's edge (agv
  // evaluate seed 44 sequence 4, a fork of 88 mm tape taken right, its branch leaving left: those
  // chords gave no evidence, the slightly wider ones their middles, and the branch was followed,
  // 7.1 mm RMS over the fork; now 0.065 mm). Taken only where such chords agree:
  // overlap_same_side of them, at least 3, leave on one side, and their leaving edges run off the
  // course as they go (correlation of the offset with the distance along it at least
  // overlap_min_correlation); not a blotchy floor widening chords on either side (agv evaluate
  // seed 9, sequence 6, 84 mm tape on a dark floor: 0.6 -> 4.6 mm RMS without these two tests).
  // The way straight on (BranchChoice straight) is read the same way: every leg leaving is the
  // other one, and the chords taken are those leaving on the side most of them leave on (agv
  // evaluate seeds 1-48: forks taken straight on, seed 31 sequence 4 3.08 -> 0.17 mm RMS, seed 25
  // sequence 11 4.11 -> 1.26 mm). There, a course bending less than straight_course_line_below_1_m
  // is taken as the line straight on: fitted over a few centimetres of straight tape it reads
  // curvatures of up to 0.1 1/m where the vehicle weaves, 4.5 mm at 0.3 m ahead, more than the
  // edge tolerance, and the tape running on looked like a leg leaving on the branch's other side
  // (scenarios/dataset_yellow_junction.yaml: a frame 2.2 deg off). A course bending more than
  // straight_course_arc_from_1_m (an arc just before the fork) is carried on round the arc, and
  // legs leaving on the outside of its bend are not read: the course may run into a branch
  // bending the same way, and the way straight on then looks like the leg leaving (seed 15
  // sequence 2, an S-bend's arc of R 0.66 m ending at a fork whose branch bends the same way: the
  // branch remembered, 40-60 mm off). Straight on is also the way on every path without a
  // junction: there the agreeing chords must be at least straight_min_coverage of the followed
  // line's chords across the stretch they span, as where a leg leaves (every scan across the
  // overlap is wide); 14 mm tape on a light floor widened 3-10 mm at a few scan lines in a
  // row, here and there, made 2-17 % of them (seed 18 sequence 7: 13 frames more without a line).
  // The overlap's first stretch: a clean chord (both edges on the line in view) wider than the
  // tape by more than overlap_slightly_wider tape widths (and overlap_slightly_wider_m), whose
  // edge nearer the course's edge lies on it and whose other edge lies beyond the other edge,
  // counts as such a chord too (its midpoint, evidence otherwise, ran at half the leaving leg's
  // offset: a preview of half the branch's curvature before the split, and the tape under the
  // vehicle read straight there for a frame or two; the fork sweep, runs settled within 1 s: left
  // 2 -> 5 of 18, right 2 -> 8). 1 or more turns this off.
  double overlap_slightly_wider = 0.02;
  double overlap_slightly_wider_m = 0.0005;
  double overlap_edge_tolerance = 0.1;
  double overlap_same_side = 0.9;
  double overlap_min_correlation = 0.7;
  double straight_course_line_below_1_m = 0.15;  // R 6.7 m
  double straight_course_arc_from_1_m = 0.6;     // R 1.7 m
  double straight_min_coverage = 0.5;
  int relatch_frames = 20;  // ... or the line's width, where it shows one other, no chord taken,
                            //     on this many frames more than those showing a third width
  double gate_m = 0.003;           // remembered points this near the tape in view are the same tape
  double neighbourhood_m = 0.008;  // the tape's local direction from its evidence this near
  int min_overlap_points = 20;     // registration needs this many of them
  // ... over at least this much of the tape (the diagonal of their bounding box): the chords of a
  // short stretch, near a joint or where the tape leaves the view, share a bias (1.8 mm across
  // 25 mm of 54 mm tape just past a corner in agv evaluate) that would stay in the memory.
  double min_overlap_span_m = 0.04;
  double max_jump_m = 0.3;  // odometry that moves further between frames restarts the memory
  // Across a gap in the remembered tape under the vehicle: the tape within gap_end_m of its
  // last point before the gap and of its first after it, the gap no longer than max_gap_m.
  double gap_end_m = 0.04;
  double max_gap_m = 0.3;
  // ... the tape's directions at its two ends this near, else the line through the end ahead,
  // passing this near the end behind.
  double max_gap_turn_rad = 0.5;
  double max_gap_offset_m = 0.005;
  double bridge_after_corner_m = 0.5;  // ... within this travel of a corner (remembered only)
  // ... or of a turn the vehicle drove with the tape in view (its heading turned by more than
  // bridge_after_turn_rad within bridge_after_corner_m), once it runs straight again (less than
  // bridge_steady_turn_rad over the last bridge_steady_m): a tight corner's outgoing tape lies in
  // the camera's blind stretch there too. Only tape within bridge_band_m across the vehicle's
  // heading counts then (other stretches of the path beside it would fill the gap: agv evaluate
  // seed 3 sequence 11, a third tape at a fork just past a corner of R 0.21 m, read 86 mm off).
  double bridge_after_turn_rad = 0.5;
  double bridge_steady_m = 0.05;
  double bridge_steady_turn_rad = 0.1;
  double bridge_band_m = 0.03;
  // ... or, at neither, inside a corner whose arc the camera never saw whole (a tight corner seen
  // as two legs meeting: their chords near the corner are neither leg's), approached on a line
  // (tape within window_across_m across the vehicle's heading counts): where the tape's
  // directions at the gap's two ends differ by more than max_gap_turn_rad, the end behind lies on
  // the course measured before the corner and the end ahead on the line in view (each within
  // corner_gap_view_offset_m, turned from it by at most corner_gap_view_turn_rad), the arc
  // tangent to the two (corner_fillet). Without, the line in view (the way out) or the course
  // before it (the way in) was carried to the vehicle inside the corner: agv evaluate seed 45,
  // sequence 9 (R 0.11 m, 50 deg) 13.1 mm / 28.9 deg off (with it 0.93 mm / 2.5 deg). The course
  // checked, a fork's stem whose last centres the overlap pulled aside was taken for a way in
  // turned 0.5 rad from the leg straight on: seed 15, sequence 2, 52 deg off. 0 turns this off.
  double corner_gap_view_turn_rad = 0.1;
  double corner_gap_view_offset_m = 0.005;
  // ... the tape behind a corner's arc (curvature above 1 1/m) whose last stretch the turned
  // camera never saw: carried on at its curvature to the direction of the end ahead, where that
  // arc ends within this of the line through the end ahead, behind the origin, the tape under the
  // vehicle is that line (the cubic bends over the whole gap instead: agv evaluate seed 7,
  // sequence 4, 7.6 -> 0.2 mm past a corner of R 0.15 m; seeds 1-8 RMS after 0.5 m 1.16 -> 1.15
  // mm). The arc's curvature from the end's last 40 mm is rough (R 0.11 m read for that corner,
  // its end then 5.6 mm off the line): 6 mm; 0 turns this off.
  double bridge_arc_meets_m = 0.006;
  // The arc carried on into the line ahead: where the circle tangent to the course last measured
  // on it and to that line touches the line behind the tape seen on it, with a curvature within
  // a third of the course's, that circle (an arc carried on drifts off by the odometry's error
  // and its curvature's, read from a short stretch: agv evaluate seed 23, sequence 2, a corner
  // of R 0.30 m turning 129 deg read 4.4 mm off at its end). False carries the arc on as
  // measured.
  bool corner_into_line = true;
  // Inside a sharp corner the camera sees another leg or a crossing tape, not the arc the vehicle
  // is on. Where the remembered tape no longer reaches the origin, the tape last measured under
  // the vehicle bent at least this much (a corner's arc, not a fork's stem: there the line in
  // view is the way chosen), and the line in view, carried back, passes neither within a tape
  // width of where that was nor within half a tape width of that arc carried forward to the
  // origin, in the arc's direction there: that arc carried forward, for at most carry_forward_m.
  // The same where the camera has passed a corner and sees no tape, beyond the tape remembered
  // (agv evaluate seeds 1-8 99.23 -> 99.38 % found, RMS unchanged: seed 5's R 0.27 m corner 88.7
  // -> 95.0 % of its frames, the arc carried within 1 mm).
  double carry_forward_min_curvature_1_m = 2.0;  // R 0.5 m
  double carry_forward_m = 0.2;
  // ... the tape width in those two tests at most this: the line that runs on from an arc's end
  // passes through it within millimetres, and the width of 100 mm tape took a corner's outgoing
  // leg, carried back 40 mm off the arc under the vehicle, for that tape (agv evaluate seed 4,
  // sequence 10: 97 mm tape, a corner of R 0.27 m, up to 45 mm off once that leg was found).
  double carry_forward_max_width_m = 0.03;
  // ... and, there, runs in the arc's direction within its curvature times the distance driven
  // since (where it left the arc it was its tangent) and this much: mid-corner, the outgoing leg
  // of a tight corner of wide tape passes the arc's last foot point within 12 mm, turned half the
  // corner from it (agv evaluate seed 8, sequence 11: R 0.11 m, 53 deg, 84 mm tape: that leg
  // carried back read 10.5 mm / 26 deg off). Only where that arc ran on from the course before
  // it within the same margin: at a fork one reading off by 30 deg (both legs in the window)
  // read an arc of R 0.15 m, and carried forward it was 33 mm off where the line in view was 10
  // (scenarios/fork_left.yaml started 0.50 m along at 0.28 m/s).
  double carry_forward_turn_margin_rad = 0.05;
  // The arc carried forward (carry_forward_min_curvature_1_m), when first carried on, is the
  // circle fitted to the tape remembered along it (within a tape width of it, back from its foot
  // point over the stretch the vehicle drove on the arc, at most arc_fit_reach_m: not the tape
  // before the arc; Cauchy weights beyond arc_fit_inlier_m), where that tape spans at least
  // arc_fit_min_span_m and the circle's curvature is within a third of the arc's: the course
  // comes from the last fit at the origin, over the window's few centimetres of one side, whose
  // curvature is good to a few per cent, and carried on over up to 0.2 m such an error grows
  // into millimetres (agv evaluate seed 27, sequence 9: R 0.27 m read 2.5 % too sharp, 0.3 ->
  // 2.7 mm over 0.18 m; fitted to 0.2 m of the arc, 0.3 mm throughout). 0 turns this off.
  double arc_fit_reach_m = 0.2;
  double arc_fit_inlier_m = 0.0005;
  double arc_fit_min_span_m = 0.05;
  // A line in view that would only be carried back (nothing remembered reads the tape under the
  // vehicle) is refused where its width differs from the tape remembered by more than this
  // fraction of it, while tape is remembered: a strip of wide tape whose other edge lies beyond
  // the view's border or is lost in the lens's shading, on a corner's outgoing leg (agv evaluate
  // seed 36, sequence 5: 85 mm tape read 33-69 mm wide, up to 25 mm off). Not in the warm-up (no
  // course measured under the vehicle yet), where the width remembered may be a first frame's
  // strip (seed 18, sequence 4: 97 mm tape remembered 24 mm wide; the right lines were refused
  // for 30 frames). 0 turns this off.
  double carried_back_width_tolerance = 0.3;
  // Across a corner's stretch never seen (around_corner): the two ends within this of the last
  // course carried on (or a tape width), one circle through both within corner_max_rms_m. A
  // band of 0 turns this off.
  double corner_band_m = 0.02;
  double corner_max_rms_m = 0.0008;
  // ... after a course measured on an arc at least this curved (R 0.67 m): the end of a wider
  // arc than a corner's is read so too (agv evaluate seed 5, sequence 2: a R 0.52 m arc left by
  // a camera 0.12 m up, the line after it carried back up to 4.4 mm / 7.5 deg off).
  double corner_min_curvature_1_m = 1.5;
  // Across a gap the course last measured runs on through (through_gap): each end over this,
  // the curve through both holding its points within through_inlier_m (a fork's overlap pulls
  // the stem's last centres towards the branch by millimetres: they are left out), its
  // curvature within through_max_bend_1_m of the course's (a branch's arc beyond is no way
  // straight on). Where a fork of wide tape is taken straight on, its legs overlap for up to
  // 0.3 m and the line in view carried back across that was up to 9.4 mm off (agv evaluate seed
  // 6, sequence 9, 91 mm tape: 0.981 -> 0.441 mm RMS after the warm-up). A span of 0 turns this
  // off.
  double through_end_m = 0.1;
  double through_inlier_m = 0.0005;
  double through_max_bend_1_m = 0.5;
  // Where no remembered tape gives the errors and the line in view, carried back, lies more than
  // hold_course_offset_m across from the course measured under the vehicle at most hold_course_m
  // ago: that course carried forward, flagged extrapolated (a fork's other way or another leg
  // taken for the line in a frame or two: agv evaluate seed 1, sequence 6, two frames 60 and 118
  // mm off; seeds 1-8 RMS after 0.5 m 0.545 mm, against 0.711 mm with a tape width + 10 mm for
  // hold_course_offset_m and 0.755 mm without the hold, the other way at forks found as a line
  // of its own).
  double hold_course_m = 0.05;
  double hold_course_offset_m = 0.01;
  // Likewise, where the reading before came less than hold_reading_m ago (from the memory, the
  // view or a hold of the course) and agreed with the one before it, and the line in view,
  // carried back, lies more than hold_course_offset_m across from it carried forward: that
  // reading carried forward, flagged extrapolated, not renewed (a band of a shadow's edge or one
  // tape edge taken for the line in one frame: agv evaluate seed 18, sequence 4, 261 mm off;
  // 21.9 -> 3.8 mm RMS). Seeds 1-48: 7 sequences better, 6 worse, pooled 1.155 -> 0.784 mm: a
  // reading already off and drifting (a branch followed) is put right up to 3 frames later
  // (seed 25, sequence 11: two frames 37-40 mm off, read right without the hold).
  double hold_reading_m = 0.03;
  // ... and on, up to hold_unsteady_view_m, while the line in view jumps from frame to frame
  // too (carried back, more than hold_course_offset_m across from the last frame's carried
  // forward): no tape seen steadily elsewhere, but a shadow's edge or a stray band each frame
  // (agv evaluate seed 18, sequence 4: a third such frame read 30 mm off, the sequence 3.66 ->
  // 3.08 mm RMS; of seeds 1-60 only two other sequences moved, 36/5 3.38 -> 3.34 mm and 53/4,
  // already lost on the floor beside its tape, 37.8 -> 38.1 mm).
  double hold_unsteady_view_m = 0.1;
  // After confirm_after_blind_m driven without a line reported (a frame or more gave none), a
  // line carried back from the view alone (no remembered tape under the vehicle gives the
  // errors) is reported only once the next frame's, carried back too, agrees with it carried
  // forward: within confirm_offset_m across and confirm_heading_rad in direction (the first tape
  // seen past a corner the camera lost is often a leg the vehicle has not reached, carried back
  // across the corner: agv evaluate seed 27, sequence 9, 84 mm / 35 deg off, the frame after
  // 2.2 mm). A frame refused for it gives no line, its reason in refused_because(); what the
  // memory holds is the same. Frames far apart with a line in each are no blind stretch.
  double confirm_after_blind_m = 0.05;
  double confirm_offset_m = 0.005;
  double confirm_heading_rad = 0.05;
  // Past a corner the camera loses the tape before the vehicle reaches it: it counts as passed
  // (the remembered tape then gives the errors with no line in view) when the tape last seen
  // turns by more than 45 deg from the vehicle's heading where its evidence ends, or would this
  // much further on at the curvature there. A corner of R 0.27 m turning 113 deg left a 0.1 m
  // deep view at 34 deg (agv evaluate seed 5, sequence 8: 80.7 % of its frames found without
  // the lookahead, 88.7 % with; seeds 1-8 99.08 -> 99.23 %, their RMS unchanged).
  double corner_lookahead_m = 0.1;
  // A frame whose line perception refused still shows the tape where it is remembered when at
  // least min_points of its chords have their centres this near remembered centre-line points,
  // spread over this much of the view.
  double seen_again_gate_m = 0.002;
  double seen_again_span_m = 0.05;
  double seen_again_width_tolerance = 0.3;  // ... and about as wide as the tape (a fraction)
  // Registration: how well a centre-line point is known. Not its own noise (0.1 mm) but the
  // bias it shares with its neighbours in one frame (0.05-0.1 mm over 0.1 m of wide tape), which
  // hundreds of points do not average out: at 0.1 mm the registration turned the memory by 0.5
  // deg over 20 frames of an S-bend seen ahead. With 1 mm: agv evaluate's gentle sequences 0.12-
  // 0.20 mm RMS (0.18-0.51 at 0.1 mm), the sample datasets' worst 0.58 -> 0.26 mm; the default
  // run 0.022 -> 0.097 mm (its 10 frames/s leave the odometry more to drift between frames).
  double point_sigma_m = 0.001;
  // ... and a residual beyond this counts less (Cauchy weights): where glare beside the tape or
  // wear on it moves one edge of a few chords by 1-2 mm, their centres pass the width test and
  // the gate, and fitted as they were they turned the memory frame after frame (agv evaluate
  // seed 11, sequence 8, its straight stretches: 0.62 mm RMS, 0.25 mm without any registration,
  // 0.008 mm without it on perfect odometry; 0.24 mm with these weights). Seeds 1-12: the median
  // sequence 0.140 -> 0.135 mm, the RMS without the 5 worst sequences 0.354 -> 0.311 mm. At
  // 0.2 mm: 0.121 and 0.278 mm, but scenarios/fork_right.yaml 7.4 mm RMS instead of 0.04 (its
  // junction's legs missed in two frames of a drive that differed by a fraction of a millimetre;
  // 0.3 mm the same; see PathMemory.GlareOnAFewChordsInViewTurnsTheMemoryLess). 0: plain least
  // squares.
  double registration_residual_scale_m = 0.0005;
  // What the odometry may have got wrong between two frames: a constant by kind of odometry
  // (wheels; motion read from the frames, which turns less surely; a guess, the last motion
  // again) and a part per metre driven.
  // Wheels shift the vehicle only as far as they roll: no constant shift, only 0.2 % per metre
  // (wheels_shift_per_m; motion read from the frames or guessed 2 %), the random part of their
  // error; what they report too far or too short every metre is the distance error, estimated
  // apart (below). Before it was, 2 % per metre (four times the default scenario's distance
  // error) let the registration follow it frame by frame; with the estimate and 0.2 %: agv
  // evaluate seeds 1-12, the median sequence 0.125 -> 0.087 mm, p95
  // 0.49 -> 0.36 mm (2 % with the estimate: 0.120 mm; 0.5 % without it: 0.102 mm, but 3 %
  // wheels then 0.33 deg off in PathMemory.RegistrationRemovesOdometryDrift). With 0.2 mm a frame
  // more, at 30 frames/s the memory could move 0.4 mm a frame, which a corner's evidence (its
  // chords read a little differently from each place in the view) used: on exact odometry the
  // registration moved the tape under the vehicle by 0.3-1 mm a frame through a corner of 86 mm
  // tape, 3.5 mm in all (agv evaluate seed 11, sequence 7: 0.82 -> 0.44 mm RMS; seeds 1-8 0.297 ->
  // 0.264 mm, 0.328 -> 0.317 deg, 28 sequences better by over 10 %, 3 worse). The turn keeps its
  // constant (a quarter of it read seed 10 sequence 2 1.04 -> 1.13 mm).
  struct Prior {
    double shift_m, turn_rad;
  };
  Prior wheels_prior{0.0, 0.0002}, frames_prior{0.001, 0.003}, guess_prior{0.005, 0.03};
  double prior_shift_per_m = 0.02, prior_turn_rad_per_m = 0.01;
  double wheels_shift_per_m = 0.002;  // the shift's part per metre on wheels (above)
  double max_correction_m = 0.01;     // a registration that needs more than this (or the angle)
  double max_correction_rad = 0.035;  //   means the memory is not this tape: it restarts
  // Wheel odometry's heading drifts by much the same per metre for metres (a wheel a little
  // larger than the other): estimated with the misalignment (a fourth state of its Kalman
  // filter, the rotation it adds per metre), and taken out of each frame's motion before the
  // registration. Without it the registration corrected the drift a few frames late, always the
  // same way: the default run (0.2 deg per metre, 10 frames/s) 0.115 mm RMS, 0.032 mm without
  // the drift, 0.047 mm with it estimated; agv evaluate seeds 1-12, the median sequence 0.136 ->
  // 0.129 mm. A bias that stays in the view (glare beside the tape) is learnt as drift too:
  // PathMemory.GlareOnAFewChordsInViewTurnsTheMemoryLess 0.57 -> 0.92 mm.
  // Its prior (about 0.6 deg per metre) and how fast it may change (per metre driven); a prior
  // of 0 leaves it out.
  double yaw_drift_sigma_rad_per_m = 0.01;
  double yaw_drift_walk_rad_per_m_per_sqrt_m = 0.002;
  // Wheel odometry also reports a distance a little off (a wheel radius not quite the one
  // configured): estimated the same way (a fifth state, the fraction of each distance reported
  // that was not driven) and taken out of each frame's motion. Each frame's error moves the whole
  // memory along the vehicle's motion, which along a line or an arc no registration sees: a
  // joint carried from the view to the vehicle (0.3 m, 1.5 mm at 0.5 %) arrives misplaced along
  // the tape, and turns the direction read under the vehicle by that times the change of
  // curvature (0.57 deg where a line meets an arc of R 0.15 m). Its prior and how fast it may
  // change (per metre driven); a prior of 0 leaves it out. With a prior of 2 % the memory's
  // shift along the tape, coupled to it, was loose enough for a fork's branch in view to drag
  // the memory onto itself (PathMemory.GoingStraightOnTheTapeBesideABranchFollowedIsKept: 22 mm).
  double distance_error_sigma = 0.005;
  double distance_error_walk_per_sqrt_m = 0.001;
  // ... and the most its estimate may move per metre driven: what one registration attributes
  // to it may be a corner's evidence, biased along the tape (a test corner of R 0.1 m: 0.36 %
  // in one frame, its bridge then 1.1 mm off instead of 0.5), or another tape's. The corner's
  // bias was the registration's local course bent by the line in view's curvature, now the
  // evidence's own; a fork's overlap still pulls the estimate: at 2 % a metre agv evaluate seeds
  // 1-48 read the median sequence 0.076 -> 0.072 mm but seed 43 sequence 9 0.58 -> 1.81 mm (the
  // estimate 0.77 % where the wheels' error is 0.50 %) and seed 25 sequence 11 0.61 -> 4.0 mm.
  double distance_error_rate_per_m = 0.005;
  // Preview: the tape ahead is fitted in windows of this half-length every step; a curvature
  // this far from the one at the origin, in two windows running, is a change.
  double preview_half_window_m = 0.03;
  double preview_step_m = 0.02;
  double preview_change_1_m = 0.15;
  double preview_change_sigmas = 3.0;  // ... and this many of the window's standard deviations
  // A window is fitted with one piece, and with joined arcs (fit_joined_arcs' breakpoint search)
  // only where that piece's curvature differs from the origin's by this fraction of
  // preview_change_1_m (a window across a joint reads about the mean of its two pieces').
  double preview_suspect_fraction = 0.5;
};

// The tape the camera has seen, remembered in the frame of the vehicle's odometry, so that e_d
// and e_theta at the vehicle origin (DESIGN.md) come from the tape under the vehicle, not from
// the line in view carried back to it. Each frame: the remembered centre-line points are moved
// into the vehicle frame with the odometry's motion; where they overlap the line in view they
// are registered to it (a small rotation and shift: the odometry's drift), the frame's evidence
// is fused into them (fuse_m) and what lies far behind is dropped; then the points around the
// origin are fitted with one arc or two joined arcs (fit_joined_arcs: a joint under the vehicle
// is not smoothed over). Until the remembered tape reaches both sides of the origin (the vehicle
// has not yet driven onto tape it saw), the measurement is the line in view carried back, flagged
// `extrapolated`.
// The private functions that take `in_vehicle` take the remembered points in the vehicle frame in
// the order of points_ (each counts as its observations).
class PathMemory {
 public:
  explicit PathMemory(const PathMemoryOptions& options = {}) : options_(options) {
    reset_misalignment();
  }

  // One frame: `in_view` is the measurement of the line in view (carried back to the origin),
  // `detection` what perception saw (its followed line's chords are the evidence), `odometry`
  // the vehicle's odometry pose (any origin) when the frame was taken, `kind` where its motion
  // since the last frame came from. A frame without a line adds
  // nothing and is returned as it is; without odometry the memory restarts. A line found again
  // after a blind stretch may be returned as none until the next frame confirms it
  // (PathMemoryOptions::confirm_after_blind_m; refused_because() says so).
  LineMeasurement update(const LineMeasurement& in_view, const LineDetection& detection,
                         const std::optional<Pose2>& odometry,
                         OdometryKind kind = OdometryKind::wheels);
  void reset();
  // Why the last update gave no line where the line in view was found (empty otherwise).
  const std::string& refused_because() const { return refused_because_; }

  // The remembered centre-line points in the vehicle frame of the last update (for tests and
  // pictures).
  std::vector<Eigen::Vector2d> points_in_vehicle_frame() const;
  // How many centre-line points it holds (what its per-frame cost grows with).
  size_t size() const { return points_.size(); }
  // The rotation per metre driven that the registrations have found the wheel odometry to add
  // (taken out of its motion; PathMemoryOptions::yaw_drift_sigma_rad_per_m).
  double yaw_drift_rad_per_m() const { return yaw_drift_rad_per_m_; }
  // The fraction of the distance the wheel odometry reports that the registrations have found
  // was not driven (taken out of its motion; PathMemoryOptions::distance_error_sigma).
  double distance_error() const { return distance_error_; }

 private:
  struct Point {
    Eigen::Vector2d p;       // in the memory frame
    int frame = 0;           // which frame saw it
    double seen_at_m = 0.0;  // the odometer then
    int observations = 1;    // how many evidence points it is the mean of (at most
                             // fuse_max_observations)
  };
  // Fuses this frame's evidence (vehicle frame) into the remembered points, whose positions in
  // the vehicle frame `in_vehicle` holds and keeps up to date.
  void add_evidence(const std::vector<Eigen::Vector2d>& evidence,
                    std::vector<Eigen::Vector2d>* in_vehicle);
  std::vector<Eigen::Vector2d> evidence_of(const LineDetection& detection);
  // Where the legs of a junction in view still overlap (a Y fork's branch leaving tangentially),
  // a chord spans both: from the other leg's far edge to the followed leg's outer edge. The
  // followed leg's centre is that outer edge moved half a tape width inwards. `used` marks the
  // chords read so (wider than the tape by more than kOverlapMin_m, narrower than two).
  static constexpr double kOverlapMin_m = 0.0005;
  std::vector<Eigen::Vector2d> overlap_centres(const LineDetection& detection,
                                               std::vector<bool>* used) const;
  // Where the legs of a fork overlap and the other leg is not seen apart (PathMemoryOptions'
  // overlap_* say how): the chosen leg's centres from the chords across both, which `used`
  // marks.
  std::vector<Eigen::Vector2d> overlap_centres_along_course(const LineDetection& detection,
                                                            std::vector<bool>* used) const;
  // The centres of the followed line's chords within chord_width_tolerance of tape_width_m_, not
  // near another line and not `overlapping` (their widths in *widths).
  std::vector<Eigen::Vector2d> chord_centres(const LineDetection& detection,
                                             const std::vector<bool>& overlapping,
                                             std::vector<double>* widths) const;
  // For each point (vehicle frame): whether it lies on a line in view other than the followed
  // one, and not on that, nor nearer the vehicle than their junction (without one, not on a line
  // that ends before the followed one begins): tape remembered there is the way not taken at a
  // fork (forgotten); the way the vehicle came is kept.
  static std::vector<bool> on_other_lines(const LineDetection& detection,
                                          const std::vector<Eigen::Vector2d>& points);
  // For each point (vehicle frame): whether it lies between the origin and the followed line's
  // far end but off that line's course, on the side of the way not taken (detection.branch),
  // where the course last measured under the vehicle runs on into the followed line carried back
  // (way_agreement_m, way_agreement_rad): a way not taken remembered ahead of the vehicle
  // (forgotten), also where the detection shows no other line; with the branch's stretch inside
  // way_gate_m from where it leaves the way at a tangent.
  std::vector<bool> off_the_way_ahead(const LineDetection& detection,
                                      const std::vector<Eigen::Vector2d>& points) const;
  // The misalignment's uncertainty after travelled_m more of the odometry's kind, the vehicle
  // having moved by moved_m in its own frame now (on wheels, the rotation's also growing with the
  // yaw drift estimate's error and the shift's with the distance error estimate's; update takes
  // the estimates' own rotation and shift out of vehicle_).
  void grow_misalignment(double travelled_m, const Eigen::Vector2d& moved_m, OdometryKind kind);
  // Registers the remembered points (in_vehicle) to the evidence of the line in view, moving
  // both them and vehicle_ by the correction found, travelled_m after the last frame.
  void register_to(const std::vector<Eigen::Vector2d>& evidence, const CurveModel& line,
                   double travelled_m, std::vector<Eigen::Vector2d>* in_vehicle);
  std::optional<LineMeasurement> at_origin(const LineMeasurement& in_view,
                                           const std::vector<Eigen::Vector2d>& in_vehicle) const;
  // Where no tape was seen under the vehicle but some behind it and some ahead, just past a
  // corner or a turn (the camera looked beyond the tape that then came under the vehicle): the
  // errors at the origin from a cubic joining the two ends with their values and directions (the
  // gap at most max_gap_m), or from the line through the end ahead where their directions differ
  // by more than max_gap_turn_rad and that line passes within max_gap_offset_m of the end behind.
  // With corner_in_gap, only elsewhere: inside a corner never seen whole whose way out is the
  // line in view (corner_gap_view_turn_rad), the arc tangent to the way in and the way out.
  std::optional<LineMeasurement> across_gap(const LineMeasurement& in_view,
                                            const std::vector<Eigen::Vector2d>& in_vehicle,
                                            bool corner_in_gap = false) const;
  // Where no tape was seen under the vehicle but the course last measured runs on through the
  // gap (a fork taken straight on: where its legs overlap no chord is one tape wide): the tape
  // remembered within a tape width of that course, the nearest behind the origin and ahead of
  // it over through_end_m each (the gap at least 10 mm, at most max_gap_m along it), fitted
  // with one curve (inliers within through_inlier_m); where that curve holds both ends
  // (min_points observations each, over at least 20 mm) and bends like the course (within
  // through_max_bend_1_m), and agrees with it carried forward, it is the tape under the vehicle.
  std::optional<LineMeasurement> through_gap(const LineMeasurement& in_view,
                                             const std::vector<Eigen::Vector2d>& in_vehicle) const;
  // Inside a corner, whose stretch under the vehicle the camera (looking along the vehicle's
  // heading, outside the arc) never saw: the tape remembered nearest behind the origin and
  // nearest ahead of it (each over gap_end_m, within a tape width or corner_band_m of the last
  // course carried on, the gap at most max_gap_m along it) fitted with one circle (from that
  // course); where the circle holds both ends (corner_max_rms_m, nine in ten of their points),
  // it is the tape under the vehicle. Else, where the corner ends in the gap, its arc carried on
  // into the line of the tape ahead (line_after_arc): that tape within the band, or, where none
  // is (the way out of a tight corner leaves the band at once), the tape nearest ahead of the
  // vehicle (within max_gap_m ahead and window_across_m across, over gap_end_m); where no tape
  // is remembered along the course within max_gap_m behind (a low camera saw the arc only in
  // glimpses: agv evaluate seed 5, sequence 8), the course alone, measured within max_gap_m
  // driven, runs into that tape. Only after a course of an arc (corner_min_curvature_1_m), or
  // where the last frame's errors came from here (the line after the arc: the course then that
  // line) within max_gap_m driven since the arc's course (agv evaluate seed 3, sequence 0: a
  // crossing tape hid the way out, the line in view, an arc beyond, carried back 15.9 mm off).
  std::optional<LineMeasurement> around_corner(
      const LineMeasurement& in_view, const std::vector<Eigen::Vector2d>& in_vehicle) const;
  // around_corner's other case, the corner ending in the gap: the points `ahead` (vehicle frame)
  // on one line (within 3 corner_max_rms_m) that touches `arc` carried on (its centre that
  // line's distance from it within bridge_arc_meets_m) behind them. The tape under the vehicle
  // is then the arc up to the tangent point, the line beyond; nullopt where they do not meet so.
  std::optional<CurveModel> line_after_arc(const CurveModel& arc,
                                           const std::vector<Eigen::Vector2d>& ahead) const;
  // The corner's arc from the course last measured on it (last_corner_course_, its point and
  // direction) into the line through line_point along line_direction (vehicle frame): the circle
  // tangent to both there, where it touches the line behind line_point and its curvature lies
  // within a third of the course's; the piece of that corner under the vehicle (corner_fillet).
  std::optional<CurveModel> arc_into_line(const Eigen::Vector2d& line_point,
                                          const Eigen::Vector2d& line_direction) const;
  // After the memory's warm-up (a course measured under the vehicle before), where the remembered
  // tape reaches no further back than the origin (fewer than side_points points within window_m
  // behind it) but starts within ahead_max_gap_m ahead of it: `in_view` with its errors from one
  // arc fitted to the remembered tape over ahead_span_m from its nearest point (at least 3
  // min_points points, over half that span, ahead_min_kept of them kept, residual under
  // ahead_max_rms_m, curvature under max_curvature_1_m, agreeing with the last course carried
  // forward: ahead_course_*), flagged extrapolated; else nothing. Looked for along the tape ahead
  // read so the frame before (ahead_before_rad, memory frame), else along the line in view
  // (which, its evidence further ahead, may run off another way: a corner's arc fitted beyond the
  // straight tape remembered).
  std::optional<LineMeasurement> from_tape_ahead(const LineMeasurement& in_view,
                                                 const std::vector<Eigen::Vector2d>& in_vehicle,
                                                 std::optional<double> ahead_before_rad) const;
  // A frame without a line in view, after tape that turned out of the view or with the tape
  // still seen where remembered: the errors from the remembered tape alone, where it lies under
  // the vehicle; else `in_view` as it is.
  LineMeasurement remembered_only(const LineMeasurement& in_view, const LineDetection& detection);
  // Whether at least min_points of the frame's chords, as wide as the remembered tape, have their
  // centres within seen_again_gate_m of remembered centre-line points (vehicle frame) or of the
  // course last measured carried on, over seen_again_span_m.
  bool tape_seen_where_remembered(const LineDetection& detection,
                                  const std::vector<Eigen::Vector2d>& in_vehicle) const;
  // Whether the followed tape turns away by more than 45 deg from the vehicle's heading where
  // its evidence ends farthest ahead, or corner_lookahead_m beyond (a corner the camera is
  // passing), or its evidence ends there at the image's left or right border (an arc leaving a
  // narrow view sideways: agv evaluate seed 5, sequence 2, R 0.52 m seen from 0.12 m up, 83.3 ->
  // 92.3 % of its frames found).
  bool turns_out_of_view(const LineDetection& detection) const;
  // Keeps the tape's direction under the vehicle (memory frame) from a measurement at the origin,
  // and the course there.
  void remember_heading(const LineMeasurement& m);
  // `carried_back` with its errors from the course last measured under the vehicle carried
  // forward to the origin (an arc goes on as an arc), flagged extrapolated, where the
  // options_.carry_forward_* above say so; else nothing.
  std::optional<LineMeasurement> carried_forward(const LineMeasurement& carried_back) const;
  // `carried_back` with its errors from the course last measured under the vehicle carried
  // forward, flagged extrapolated, where options_.hold_course_* say so; else nothing.
  std::optional<LineMeasurement> course_held(const LineMeasurement& carried_back) const;
  // `carried_back` with its errors from the last reading carried forward, flagged extrapolated,
  // where options_.hold_reading_m (or hold_unsteady_view_m) says so; else nothing.
  std::optional<LineMeasurement> reading_held(const LineMeasurement& carried_back) const;
  // How far m lies across from last_reading_ carried forward, where that was taken at most
  // hold_reading_m ago; else nothing.
  std::optional<double> offset_from_recent_reading_m(const LineMeasurement& m) const;
  // update's work; update records its reading (last_reading_).
  LineMeasurement read(const LineMeasurement& in_view, const LineDetection& detection,
                       const std::optional<Pose2>& odometry, OdometryKind kind);
  // `m` with its errors from the course last measured under the vehicle carried forward to the
  // origin (last_course_ set), flagged extrapolated.
  LineMeasurement with_course(const LineMeasurement& m) const;
  // `m` with its errors from the course last measured under the vehicle carried forward to the
  // origin, flagged extrapolated, while that course is curved (at least
  // carry_forward_min_curvature_1_m: a corner's arc) and at most carry_forward_m behind; else
  // nothing.
  std::optional<LineMeasurement> course_carried_on(const LineMeasurement& m) const;
  // Before the course last measured is first carried on, while it is a corner's arc: that arc
  // fitted to the tape remembered along it (in_vehicle: the points in the vehicle frame; see
  // arc_fit_reach_m), where the fit holds.
  void fit_course_to_its_arc(const std::vector<Eigen::Vector2d>& in_vehicle);
  // The course last measured under the vehicle, moved to this frame's origin (last_course_ set).
  CurveModel last_course_now() const;
  // How far the tape turns along the course last measured over the distance driven since
  // (its curvature times that distance; last_course_ set).
  double turn_since_last_course_rad() const;
  // Whether `fitted` (vehicle frame) lies as near the course last measured, carried forward, as
  // PathMemoryOptions' ahead_course_* allow (false before a course was measured).
  bool near_course_carried_forward(const CurveModel& fitted) const;
  // Where the curvature of the tape ahead of the origin changes, and to what (m's preview
  // fields), from local fits along the remembered and seen tape.
  void add_preview(const std::vector<Eigen::Vector2d>& in_vehicle, LineMeasurement* m) const;

  PathMemoryOptions options_;
  std::vector<Point> points_;
  Pose2 correction_;  // memory frame from odometry frame
  // How far the memory may still be out of line with the vehicle (rotation about the origin,
  // shift x, shift y) and how far off the odometry's yaw drift (rad per metre) and distance
  // error (a fraction) estimates are: it
  // grows with every frame's odometry error and shrinks with every registration (a Kalman filter
  // on the misalignment), so that a drift the odometry keeps making is corrected in full, not
  // held back frame after frame by the prior on one frame's error.
  using Misalignment = Eigen::Matrix<double, 5, 5>;
  Misalignment misalignment_cov_ = Misalignment::Zero();
  double yaw_drift_rad_per_m_ = 0.0;  // the wheel odometry's, as the registrations found it
  double distance_error_ = 0.0;       // the same
  // No misalignment, known exactly, and the odometry's error estimates at their prior (0).
  void reset_misalignment();
  std::optional<Pose2> last_odometry_;
  Pose2 vehicle_;  // the vehicle in the memory frame, at the last update
  int frame_ = 0;
  double tape_width_m_ = 0.0;                 // the width of the evidence remembered (0: none yet)
  int disagreeing_frames_ = 0;        // frames whose line shows another width, no evidence, less
                                      // those showing a third
  double disagreeing_width_m_ = 0.0;  // ... the width they show
  std::optional<double> tape_heading_rad_;    // the tape's direction at the origin, memory frame
  std::optional<double> ahead_heading_rad_;   // this frame's from_tape_ahead, memory frame
  bool turns_out_of_view_ = false;            // the tape last seen turned out of the view
  double odometer_m_ = 0.0;                   // distance driven since the start
  std::optional<double> corner_passed_at_m_;  // odometer when last remembered only past a corner
  // (odometer, vehicle heading in the memory frame) of the frames over the last
  // bridge_after_corner_m driven.
  std::deque<std::pair<double, double>> recent_headings_;
  // Whether the vehicle has turned by bridge_after_turn_rad lately and runs straight now.
  bool straight_after_turn() const;
  // The course last measured under the vehicle: its foot point, direction (memory frame) and
  // curvature, and the odometer then.
  struct Course {
    Eigen::Vector2d foot_m;
    double heading_rad, curvature_1_m, odometer_m;
    // Whether it runs on from the course before it: turned by that one's curvature times the
    // distance driven, within carry_forward_turn_margin_rad.
    bool runs_on = false;
  };
  std::optional<Course> last_course_;
  bool course_fitted_to_arc_ = false;  // fit_course_to_its_arc has run on last_course_
  // The odometer where the courses measured last began to bend one way by at least
  // carry_forward_min_curvature_1_m (the vehicle came onto a corner's arc), while they do.
  std::optional<double> on_arc_from_m_;
  // The last reading update returned with a line, other than reading_held's.
  std::optional<Course> last_reading_;
  // Whether last_reading_ lay within hold_course_offset_m of the reading before it, carried
  // forward, taken at most hold_reading_m before it (a reading after a frame without a line, or
  // after another reading, may be the one that jumped).
  bool last_reading_confirmed_ = false;
  bool reading_held_ = false;  // update's reading this frame is reading_held's
  // The line in view carried back, this frame and the frame before (none where it had no line;
  // reading_held's check that the view keeps jumping).
  std::optional<Course> view_, view_before_;
  // The course of a measurement (vehicle frame now) in the memory frame, with the odometer.
  Course course_of(const LineMeasurement& m) const;
  // How far m (carried back) lies across from `course` carried forward, at the origin.
  double offset_from_m(const LineMeasurement& m, const Course& course) const;
  // `m` as update returns it: refused after a blind stretch until confirmed (options_.confirm_*).
  LineMeasurement confirmed(const LineMeasurement& m);
  std::optional<double> reported_at_m_;  // odometer at the last line update returned
  int frames_without_line_ = 0;          // updates since then that returned none
  std::optional<Course> unconfirmed_;    // the line refused last frame for want of confirmation
  std::string refused_because_;
  // The last such course on an arc (curvature at least corner_min_curvature_1_m).
  std::optional<Course> last_corner_course_;
  bool read_off_corner_ = false;     // the last frame's errors came from around_corner
  bool read_across_corner_ = false;  // ... from across_gap inside a corner never seen whole
  // `course` moved to this frame's origin.
  CurveModel course_now(const Course& course) const;
  OdometryKind odometry_kind_ = OdometryKind::wheels;  // of the last update's motion
  // Scratch for register_to: one row per remembered point on the tape in view, d + j delta = 0
  // (d its distance from the evidence's local course), counting as its observations.
  struct RegistrationRow {
    Eigen::Vector3d j;
    double d, observations;
  };
  std::vector<RegistrationRow> registration_rows_;
};

}  // namespace agv::perception
