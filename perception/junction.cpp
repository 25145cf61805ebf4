#include "perception/junction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/angles.h"
#include "common/input_error.h"

namespace agv::perception {
namespace {

// Direction of a curve at arc position s.
double heading_at(const CurveModel& m, double s) {
  const Eigen::Vector2d t = m.tangent_at(s);
  return std::atan2(t.y(), t.x());
}

// Arc position on `a` where it crosses `b`, searched over [s0, s1]; nullopt if it does not.
std::optional<double> crossing(const CurveModel& a, const CurveModel& b, double s0, double s1) {
  constexpr double kStep = 0.002;
  double previous_s = s0, previous_d = b.signed_distance(a.point_at(s0));
  for (double s = s0 + kStep; s <= s1 + 1e-12; s += kStep) {
    const double d = b.signed_distance(a.point_at(s));
    if ((d <= 0.0) != (previous_d <= 0.0)) {
      return previous_s + kStep * previous_d / (previous_d - d);  // linear in between
    }
    previous_s = s;
    previous_d = d;
  }
  return std::nullopt;
}

// Where `a`, continued from arc position s_end in direction `way` (+1 or -1) for up to
// kReach_m, first overlaps `b` (centre lines within half a tape width): a branch that leaves a
// tape tangentially shows as a line of its own only once clear of it. Nullopt if it does not.
std::optional<double> overlap_before(const CurveModel& a, const CurveModel& b, double s_end,
                                     double way, double width_m) {
  constexpr double kReach_m = 0.15, kStep_m = 0.002;
  const CurveModel::Prepared other = b.prepared();
  for (double t = 0.0; t <= kReach_m; t += kStep_m) {
    const double s = s_end + way * t;
    if (std::abs(other.signed_distance(a.point_at(s))) <= 0.5 * width_m) return s;
  }
  return std::nullopt;
}

// The branches that are halves of a tape crossing the one followed: where the tape the vehicle
// arrives on goes on straight through the point (a branch opposite the incoming one), two other
// branches opposite each other, each at least kCrossing_rad across the tape followed, are the
// crossing tape's halves (a fork's branch, its line running back through the point along the
// stem, leaves nearly tangentially). A tape crossing is no junction: the way on is straight
// through (agv evaluate seed 27, sequence 11: a path crossing itself after a fork taken left;
// its crossing half 52 deg to the left was the way left, and followed).
std::vector<bool> crossing_halves(const Junction& junction) {
  constexpr double kOpposite_rad = 0.2;  // the tapes' curvature over a branch's length
  constexpr double kCrossing_rad = 0.5;
  const std::vector<Branch>& b = junction.branches;
  std::vector<bool> halves(b.size(), false);
  if (junction.incoming < 0) return halves;
  auto opposite = [](double a_rad, double b_rad) {
    return std::abs(wrap_angle_rad(a_rad - b_rad - M_PI)) < kOpposite_rad;
  };
  const double incoming_rad = b[junction.incoming].heading_rad;
  bool goes_through = false;
  for (size_t k = 0; k < b.size(); ++k)
    goes_through = goes_through || (static_cast<int>(k) != junction.incoming &&
                                    opposite(b[k].heading_rad, incoming_rad));
  if (!goes_through) return halves;
  for (size_t k = 0; k < b.size(); ++k) {
    if (static_cast<int>(k) == junction.incoming ||
        std::abs(std::sin(b[k].heading_rad - incoming_rad)) < std::sin(kCrossing_rad))
      continue;
    for (size_t j = 0; j < b.size(); ++j) {
      if (j != k && static_cast<int>(j) != junction.incoming &&
          opposite(b[k].heading_rad, b[j].heading_rad))
        halves[k] = true;
    }
  }
  return halves;
}

}  // namespace

BranchChoice parse_branch_choice(const std::string& word) {
  if (word == "left") return BranchChoice::kLeft;
  if (word == "straight") return BranchChoice::kStraight;
  if (word == "right") return BranchChoice::kRight;
  throw InputError("branch '" + word + "': expected left, straight or right");
}

const char* branch_choice_name(BranchChoice choice) {
  return choice == BranchChoice::kLeft    ? "left"
         : choice == BranchChoice::kRight ? "right"
                                          : "straight";
}

std::optional<Junction> find_junction(const std::vector<DetectedLine>& lines, double margin_m,
                                      double min_branch_m, double min_open_branch_m) {
  // Where pairs of lines meet within their evidence: where they cross, or where one, continued
  // beyond an end of its evidence, overlaps the other (a branch leaving tangentially, as at a Y
  // fork, shows as a separate line only once clear of the tape it leaves; a stem that stops at
  // the tape it joins). Each meeting remembers its two lines.
  struct Meeting {
    Eigen::Vector2d point;
    int a, b;
  };
  std::vector<Meeting> meetings;
  const int n = static_cast<int>(lines.size());
  auto within_evidence = [&](const DetectedLine& line, double s) {
    return s >= line.s_min_m - margin_m && s <= line.s_max_m + margin_m;
  };
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const DetectedLine& a = lines[i];
      const DetectedLine& b = lines[j];
      const std::optional<double> s_a =
          crossing(a.model, b.model, a.s_min_m - margin_m, a.s_max_m + margin_m);
      if (!s_a) continue;
      const Eigen::Vector2d point = a.model.point_at(*s_a);
      if (within_evidence(b, b.model.arc_position(point))) meetings.push_back({point, i, j});
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const DetectedLine& a = lines[i];
      const DetectedLine& b = lines[j];
      for (const bool start : {true, false}) {
        if (start ? a.open_start : a.open_end) continue;  // the tape goes on out of view
        const std::optional<double> s_a =
            start ? overlap_before(a.model, b.model, a.s_min_m, -1.0, margin_m)
                  : overlap_before(a.model, b.model, a.s_max_m, 1.0, margin_m);
        if (!s_a) continue;
        const double s_b = b.model.arc_position(a.model.point_at(*s_a));
        if (within_evidence(b, s_b)) meetings.push_back({b.model.point_at(s_b), i, j});
      }
    }
  }
  if (meetings.empty()) return std::nullopt;
  // Meetings within a margin of each other are one junction (tape laid in pieces crosses
  // another tape in several nearby points); the one with most meetings, then nearest, wins.
  Eigen::Vector2d point = meetings.front().point;
  std::vector<bool> involved(n, false);
  int most = 0;
  for (const Meeting& candidate : meetings) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    std::vector<bool> lines_here(n, false);
    for (const Meeting& other : meetings) {
      if ((other.point - candidate.point).norm() <= margin_m) {
        sum += other.point;
        ++count;
        lines_here[other.a] = lines_here[other.b] = true;
      }
    }
    const Eigen::Vector2d centre = sum / count;
    if (count > most || (count == most && centre.norm() < point.norm())) {
      most = count;
      point = centre;
      involved = lines_here;
    }
  }
  Junction junction;
  junction.point_m = point;
  // Every line meeting there contributes the pieces of evidence leaving the junction.
  for (int index = 0; index < n; ++index) {
    if (!involved[index]) continue;
    const DetectedLine& line = lines[index];
    const double s = line.model.arc_position(point);
    // A branch's direction: from the junction to where its evidence ends (at a Y fork the
    // branch leaves tangentially: its tangent at the junction is the tape's it leaves).
    auto branch_to = [&](double s_end) {
      const Eigen::Vector2d end = line.model.point_at(s_end);
      const Eigen::Vector2d way = end - point;
      return Branch{index, std::atan2(way.y(), way.x()), std::abs(s_end - s), end};
    };
    if (line.s_max_m - s >= (line.open_end ? min_open_branch_m : min_branch_m))
      junction.branches.push_back(branch_to(line.s_max_m));
    if (s - line.s_min_m >= (line.open_start ? min_open_branch_m : min_branch_m))
      junction.branches.push_back(branch_to(line.s_min_m));
  }
  // Two pieces of one tape leaving the same way (tape laid in pieces) are one branch: keep
  // the longer. Pieces of two tapes (a fork) end apart, however near their directions.
  constexpr double kSameDirection_rad = 0.35;
  std::vector<Branch> merged;
  for (const Branch& branch : junction.branches) {
    bool absorbed = false;
    for (Branch& kept : merged) {
      const Branch& shorter = branch.length_m < kept.length_m ? branch : kept;
      const Branch& longer = branch.length_m < kept.length_m ? kept : branch;
      const bool one_tape =
          std::abs(lines[longer.line].model.signed_distance(shorter.end_m)) < 0.3 * margin_m;
      if (std::abs(wrap_angle_rad(kept.heading_rad - branch.heading_rad)) < kSameDirection_rad &&
          one_tape) {
        if (branch.length_m > kept.length_m) kept = branch;
        absorbed = true;
        break;
      }
    }
    if (!absorbed) merged.push_back(branch);
  }
  junction.branches = merged;
  if (junction.branches.size() < 2) return std::nullopt;
  // The vehicle arrives on the branch pointing most nearly back at it.
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < junction.branches.size(); ++k) {
    const Eigen::Vector2d direction(std::cos(junction.branches[k].heading_rad),
                                    std::sin(junction.branches[k].heading_rad));
    const double towards = direction.dot(point.normalized());  // -1: straight back at us
    if (towards < best) {
      best = towards;
      junction.incoming = static_cast<int>(k);
    }
  }
  if (best > -0.5) junction.incoming = -1;  // nothing comes from the vehicle's side
  return junction;
}

void FollowHistory::update(const std::optional<double>& branch_heading,
                           const std::optional<CurveModel>& line, std::optional<double> width_m,
                           const std::optional<ContrastAxis>& line_axis) {
  width.update(line ? width_m : std::nullopt);
  if (line) {
    frames_without_line = 0;
    if (line_axis) axis = line_axis;
  } else if (++frames_without_line > kForgetAxisAfterFrames) {
    axis.reset();
  }
  if (branch_heading) {
    branch_heading_rad = branch_heading;
    frames_without_branches = 0;
  } else if (++frames_without_branches > kForgetAfterFrames) {
    branch_heading_rad.reset();
  }
  if (line) followed = line;
}

void FollowHistory::vehicle_turned(double yaw_rad) {
  if (branch_heading_rad) branch_heading_rad = wrap_angle_rad(*branch_heading_rad - yaw_rad);
}

FollowedLine choose_line(const std::vector<DetectedLine>& lines,
                         const std::optional<Junction>& junction, BranchChoice choice,
                         double max_turn_rad, const FollowHistory* history) {
  FollowedLine followed;
  if (lines.empty()) return followed;
  constexpr double kHoldTolerance_rad = 0.5;
  const bool holding = history && history->branch_heading_rad.has_value();
  const double held_rad = holding ? *history->branch_heading_rad : 0.0;
  // Straight on, the way held does not jump: a way farther from it than 0.05 rad (the held
  // direction turns with the vehicle, FollowHistory::vehicle_turned; what is left is the fits'
  // noise) is this frame's line to follow, but the direction held stays (the way held may be
  // missed in a frame: a leg too close to the other to be a line of its own; a poor fit between
  // the legs would carry it towards the branch a few degrees a frame: agv evaluate seed 33,
  // sequence 7).
  constexpr double kStraightJump_rad = 0.05;
  auto held_again = [&](double h) -> std::optional<double> {
    if (holding && choice == BranchChoice::kStraight &&
        std::abs(wrap_angle_rad(h - held_rad)) > kStraightJump_rad)
      return std::nullopt;
    return h;
  };
  // Straight on, a first choice between ways that differ from straight by nearly the same turn
  // is not yet held: where the legs of a Y fork first show, still one band, which is straight
  // is noise (agv evaluate seed 21, sequence 3: held by 0.8 deg for the branch, which was then
  // kept to); a later frame, the legs apart, decides.
  constexpr double kClearStraight_rad = 0.05;
  // The best and second best scores of the ways offered; offer() says whether a way is the best
  // so far.
  struct TopTwo {
    double best = -std::numeric_limits<double>::infinity(), second = best;
    bool offer(double score) {
      if (!(score > best)) {
        second = std::max(second, score);
        return false;
      }
      second = best;
      best = score;
      return true;
    }
  };
  auto clear_choice = [&](const TopTwo& scores) {
    return holding || choice != BranchChoice::kStraight ||
           scores.best - scores.second >= kClearStraight_rad;
  };
  // Straight on from a junction in view: the direction of the tape followed before, there
  // (where the tape comes in on a bend, its direction at the fork, not the vehicle's heading: a
  // fork's way straight on is the one that continues the incoming tape); without one, the
  // vehicle's heading, as for legs that do not meet in view (they part near the vehicle).
  auto straight_on_rad = [&](const Eigen::Vector2d& point) {
    if (!history || !history->followed) return 0.0;
    return heading_at(*history->followed, history->followed->arc_position(point));
  };
  // The score of leaving in direction h: a way near the held branch first (of those, the
  // leftmost for left, the rightmost for right, the nearest the held one for straight: at a Y
  // fork the first frames see both ways nearly straight ahead), then the choice (straight: the
  // way nearest straight_on_rad, where it was seen).
  // h_side: the direction left or right is judged by (h where not given).
  auto score_of = [&](double h, double offset_m, double straight_rad,
                      std::optional<double> h_side = std::nullopt) {
    const double from_held = std::abs(wrap_angle_rad(h - held_rad));
    const double held_bonus = holding && from_held < kHoldTolerance_rad ? 10.0 : 0.0;
    if (held_bonus > 0.0 && choice == BranchChoice::kStraight) return held_bonus - from_held;
    const double side = h_side.value_or(h);
    return held_bonus +
           (choice == BranchChoice::kLeft ? side
            : choice == BranchChoice::kRight
                ? -side
                : -std::abs(wrap_angle_rad(h - straight_rad)) - std::abs(offset_m) / 0.05);
  };
  // A line followed as it is: in the direction it was followed in the frame before, compared
  // where the line is seen (at the origin's foot point, far from it, a tight curve's tangent may
  // point either way).
  auto as_before = [&](const DetectedLine& line) {
    const CurveModel& m = line.model;
    if (!history || !history->followed) return m;
    return m.oriented_like(*history->followed, m.point_at(0.5 * (line.s_min_m + line.s_max_m)));
  };
  // Line i's direction (as followed before) at its near end.
  auto near_heading = [&](int i) {
    const CurveModel m = as_before(lines[i]);
    const double near_s = std::min(m.arc_position(lines[i].model.point_at(lines[i].s_min_m)),
                                   m.arc_position(lines[i].model.point_at(lines[i].s_max_m)));
    return heading_at(m, near_s);
  };
  auto best_line = [&] {
    int best = 0;
    for (int i = 1; i < static_cast<int>(lines.size()); ++i) {
      if (lines[i].confidence > lines[best].confidence) best = i;
    }
    return best;
  };
  if (!junction || junction->branches.size() < 2) {
    // Several lines that do not meet in view (a fork whose split point is out of view or
    // merged): the choice applies to their directions (near their near ends the way held, at
    // their far ends left or right); one line: that one.
    followed.line = best_line();
    if (lines.size() > 1) {
      TopTwo scores;
      for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
        const CurveModel m = as_before(lines[i]);
        const double near_s = m.arc_position(lines[i].model.point_at(lines[i].s_min_m));
        const double far_s = m.arc_position(lines[i].model.point_at(lines[i].s_max_m));
        const double h = heading_at(m, std::min(near_s, far_s));
        // Left or right by the direction at the far end: near the split of a Y fork both legs
        // run within a few degrees of each other, which way by noise (agv evaluate seed 3,
        // sequence 11: its branch taken three times for the way left).
        const double h_far = heading_at(m, std::max(near_s, far_s));
        if (scores.offer(score_of(h, lines[i].model.e_d_m, 0.0, h_far))) {
          followed.line = i;
          followed.branch_heading_rad = held_again(h);
        }
      }
      if (!clear_choice(scores)) followed.branch_heading_rad.reset();
    }
    followed.model = as_before(lines[followed.line]);
    return followed;
  }
  int chosen = -1;
  TopTwo scores;
  const std::vector<bool> crossing = crossing_halves(*junction);
  for (int k = 0; k < static_cast<int>(junction->branches.size()); ++k) {
    if (k == junction->incoming || crossing[k]) continue;
    if (scores.offer(
            score_of(junction->branches[k].heading_rad, 0.0, straight_on_rad(junction->point_m))))
      chosen = k;
  }
  const Branch* branch = chosen >= 0 ? &junction->branches[chosen] : nullptr;
  // The only way out of a corner is followed but not held as the way chosen: a fork whose other
  // leg is not yet a line of its own shows as a corner for a frame or two (agv evaluate seed 5,
  // sequence 6, with other edges: the branch held for the way right, and kept to once both legs
  // showed). A crossing tape's halves count as ways: the way through a crossing is held.
  const int ways = static_cast<int>(junction->branches.size()) - (junction->incoming >= 0 ? 1 : 0);
  if (branch && ways >= 2 && clear_choice(scores))
    followed.branch_heading_rad = held_again(branch->heading_rad);
  // Straight on, a way held that a line in view runs along, nearer than the way the junction
  // offers by kNearerHeld_rad: that line (where a fork's wide legs overlap, the junction found may
  // offer only the branch, the way held a line of its own beside it: agv evaluate seed 36,
  // sequence 1 followed the branch there and remembered it as the tape under the vehicle). Not a
  // crossing tape's line.
  constexpr double kNearerHeld_rad = 0.2;
  if (holding && branch && choice == BranchChoice::kStraight) {
    std::vector<bool> offered(lines.size(), true);
    offered[branch->line] = false;
    for (size_t k = 0; k < junction->branches.size(); ++k)
      if (crossing[k]) offered[junction->branches[k].line] = false;
    int nearer = -1;
    double nearest_rad = std::abs(wrap_angle_rad(branch->heading_rad - held_rad)) - kNearerHeld_rad;
    for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
      if (!offered[i]) continue;
      const double off_rad = std::abs(wrap_angle_rad(near_heading(i) - held_rad));
      if (off_rad < nearest_rad) {
        nearest_rad = off_rad;
        nearer = i;
      }
    }
    if (nearer >= 0) {
      followed.line = nearer;
      followed.model = as_before(lines[nearer]);
      followed.branch_heading_rad = held_again(near_heading(nearer));
      return followed;
    }
  }
  // Line i oriented so that it leaves the junction in direction h.
  auto leaving = [&](int i, double h) {
    const CurveModel& m = lines[i].model;
    const double s = m.arc_position(junction->point_m);
    const double along = std::cos(wrap_angle_rad(heading_at(m, s) - h));
    return along >= 0.0 ? m : m.reversed();
  };
  if (branch && (std::abs(branch->heading_rad) <= max_turn_rad || junction->incoming < 0)) {
    // Follow the branch, in its direction away from the junction.
    followed.line = branch->line;
    followed.model = leaving(branch->line, branch->heading_rad);
    return followed;
  }
  // A sharp turn ahead: keep to the incoming line, towards the junction, until it is reached.
  if (junction->incoming >= 0) {
    const Branch& incoming = junction->branches[junction->incoming];
    followed.line = incoming.line;
    followed.model = leaving(incoming.line, wrap_angle_rad(incoming.heading_rad + M_PI));
  } else {
    followed.line = best_line();
    followed.model = as_before(lines[followed.line]);
  }
  return followed;
}

}  // namespace agv::perception
