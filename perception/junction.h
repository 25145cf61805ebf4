#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "perception/line_set.h"

namespace agv::perception {

// Which way to go where lines meet, as industrial line sensors offer it.
enum class BranchChoice { kLeft, kStraight, kRight };

BranchChoice parse_branch_choice(const std::string& word);  // "left" | "straight" | "right"
const char* branch_choice_name(BranchChoice choice);

// A piece of a line leaving a junction.
struct Branch {
  int line = 0;
  double heading_rad = 0.0;  // direction away from the junction, vehicle frame
  double length_m = 0.0;     // evidence along it from the junction
};

// Where two lines meet within their evidence, and the branches leaving that point.
struct Junction {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  std::vector<Branch> branches;
  int incoming = -1;  // index in branches of the one the vehicle arrives on, if any
};

// Where lines meet, if any pair crosses within their evidence (plus `margin_m`): crossings
// within margin_m of each other are one junction (pieces of tape laid end to end); the
// junction with most crossings (then the nearest) is returned, with the pieces of every line
// through it that leave it. A branch counts when at least min_branch_m of evidence leaves the
// point, or, where the evidence runs into the image border, min_open_branch_m.
std::optional<Junction> find_junction(const std::vector<DetectedLine>& lines, double margin_m,
                                      double min_branch_m, double min_open_branch_m);

// The line to follow and its direction: without a junction, the best line; at a junction the
// outgoing branch the choice names (left: most counter-clockwise, right: most clockwise,
// straight: nearest the vehicle's heading) when it leaves within max_turn_rad of straight
// ahead; a sharper branch is taken once the vehicle gets there, so until then the incoming line
// is followed. Returns an index into `lines` and the model oriented along the travel direction.
struct FollowedLine {
  int line = -1;
  CurveModel model;
};
FollowedLine choose_line(const std::vector<DetectedLine>& lines,
                         const std::optional<Junction>& junction, BranchChoice choice,
                         double max_turn_rad);

}  // namespace agv::perception
