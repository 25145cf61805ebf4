#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "perception/contrast_axis.h"
#include "perception/line_set.h"
#include "perception/tape_width_memory.h"

namespace agv::perception {

// Which way to go where lines meet, as industrial line sensors offer it.
enum class BranchChoice { kLeft, kStraight, kRight };

BranchChoice parse_branch_choice(const std::string& word);  // "left" | "straight" | "right"
const char* branch_choice_name(BranchChoice choice);

// A piece of a line leaving a junction.
struct Branch {
  int line = 0;
  double heading_rad = 0.0;  // direction away from the junction to its end, vehicle frame
  double length_m = 0.0;     // evidence along it from the junction
  Eigen::Vector2d end_m = Eigen::Vector2d::Zero();  // where its evidence ends
};

// Where two lines meet within their evidence, and the branches leaving that point.
struct Junction {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  std::vector<Branch> branches;
  int incoming = -1;  // index in branches of the one the vehicle arrives on, if any
};

// Where lines meet, if any pair crosses within their evidence (plus `margin_m`, a tape width) or
// one, continued for up to 0.15 m beyond an end of its evidence that is not at the image border,
// overlaps the other there (a Y fork's branch, seen as a line of its own only once clear of the
// tape it leaves; a stem stopping at the tape it joins): meetings within margin_m of each other are
// one junction (pieces of tape laid end to end); the junction with most meetings (then the nearest)
// is returned, with the pieces of the lines meeting there that leave it. A branch counts when at
// least min_branch_m of evidence leaves the point, or, where the evidence runs into the image
// border, min_open_branch_m.
std::optional<Junction> find_junction(const std::vector<DetectedLine>& lines, double margin_m,
                                      double min_branch_m, double min_open_branch_m);

// What the frames before chose, to keep to it through a junction: the direction (vehicle frame)
// of the branch chosen there, and the line followed in the last frame (oriented).
struct FollowHistory {
  std::optional<double> branch_heading_rad;
  int frames_without_branches = 0;  // frames since one showed a junction or several lines
  std::optional<CurveModel> followed;
  TapeWidthMemory width;  // the width of the tape followed so far
  // The colour axis the tape followed was last found on (the full search tries it first: on a
  // blotchy floor the axis chosen afresh can be the blotches'), forgotten after
  // kForgetAxisAfterFrames frames without a line.
  std::optional<ContrastAxis> axis;
  int frames_without_line = 0;
  // Record one frame's choice (line: nullopt when no line was found; width_m: its width; axis:
  // the colour axis it was found on).
  void update(const std::optional<double>& branch_heading, const std::optional<CurveModel>& line,
              std::optional<double> width_m = std::nullopt,
              const std::optional<ContrastAxis>& line_axis = std::nullopt);
  // The vehicle turned by yaw_rad (anticlockwise) since the frame before: the direction held,
  // in the vehicle frame, turns the other way (through a fork on a bend the legs' directions move
  // by degrees a frame; a direction held unturned came nearer the other leg).
  void vehicle_turned(double yaw_rad);
  static constexpr int kForgetAfterFrames = 5;  // the junction is behind: choose anew
  static constexpr int kForgetAxisAfterFrames = 30;
};

// The line to follow and its direction: without a junction, the best line; at a junction the
// outgoing branch the choice names (left: most counter-clockwise, right: most clockwise,
// straight: nearest the direction the tape followed before has where the legs meet, when they
// meet in view, else nearest the vehicle's heading) when it leaves within max_turn_rad of straight
// ahead; a sharper branch is taken once the vehicle gets there, so until then the incoming line is
// followed. With a history, the branch chosen in the frames before is kept to while one leaves
// within 0.5 rad of its direction (the choice decides once per junction, and a leg seen in some
// frames only does not make the choice swing; straight on, a frame whose nearest way is more than
// 0.05 rad from the one held does not move the direction held, and no way is held before one is
// nearer straight than another by 0.05 rad: where the legs first show they run nearly alike),
// and a line not chosen as a branch keeps the direction it was followed in (no 180 deg flips of
// a line across the view). A tape crossing the one followed (an X: its halves leave the point
// opposite each other, at least 0.5 rad across, and the tape followed goes on through it) is no
// junction: its halves are not offered, the way on is straight through. Where a line in view runs
// nearer the way held than the branch the junction offers (by 0.2 rad), that line is followed (a
// fork's wide legs overlapping: the way held may be a line of its own). Returns an index into
// `lines`, the model oriented along the travel direction and the chosen branch's heading (when
// there was a choice to make).
struct FollowedLine {
  int line = -1;
  CurveModel model;
  std::optional<double> branch_heading_rad;
};
FollowedLine choose_line(const std::vector<DetectedLine>& lines,
                         const std::optional<Junction>& junction, BranchChoice choice,
                         double max_turn_rad, const FollowHistory* history = nullptr);

}  // namespace agv::perception
