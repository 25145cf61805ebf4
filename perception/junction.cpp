#include "perception/junction.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/angles.h"
#include "common/input_error.h"

namespace agv::perception {
namespace {

// Direction of a curve at arc position s.
double heading_at(const CurveModel& m, double s) {
  const Eigen::Vector2d d = m.point_at(s + 1e-4) - m.point_at(s - 1e-4);
  return std::atan2(d.y(), d.x());
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
  // Where pairs of lines cross within their evidence.
  std::vector<Eigen::Vector2d> crossings;
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      const DetectedLine& a = lines[i];
      const DetectedLine& b = lines[j];
      const std::optional<double> s_a =
          crossing(a.model, b.model, a.s_min_m - margin_m, a.s_max_m + margin_m);
      if (!s_a) continue;
      const Eigen::Vector2d point = a.model.point_at(*s_a);
      const double s_b = b.model.arc_position(point);
      if (s_b < b.s_min_m - margin_m || s_b > b.s_max_m + margin_m) continue;
      crossings.push_back(point);
    }
  }
  if (crossings.empty()) return std::nullopt;
  // Crossings within a margin of each other are one junction (tape laid in pieces crosses
  // another tape in several nearby points); the one with most crossings, then nearest, wins.
  Eigen::Vector2d point = crossings.front();
  int most = 0;
  for (const Eigen::Vector2d& candidate : crossings) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (const Eigen::Vector2d& other : crossings) {
      if ((other - candidate).norm() <= margin_m) {
        sum += other;
        ++count;
      }
    }
    const Eigen::Vector2d centre = sum / count;
    if (count > most || (count == most && centre.norm() < point.norm())) {
      most = count;
      point = centre;
    }
  }
  Junction junction;
  junction.point_m = point;
  // Every line through the junction contributes the pieces of evidence leaving it.
  for (int index = 0; index < static_cast<int>(lines.size()); ++index) {
    const DetectedLine& line = lines[index];
    if (std::abs(line.model.signed_distance(point)) > margin_m) continue;
    const double s = line.model.arc_position(point);
    if (s < line.s_min_m - margin_m || s > line.s_max_m + margin_m) continue;
    if (line.s_max_m - s >= (line.open_end ? min_open_branch_m : min_branch_m)) {
      junction.branches.push_back({index, heading_at(line.model, s), line.s_max_m - s});
    }
    if (s - line.s_min_m >= (line.open_start ? min_open_branch_m : min_branch_m)) {
      junction.branches.push_back(
          {index, wrap_angle_rad(heading_at(line.model, s) + M_PI), s - line.s_min_m});
    }
  }
  // Two pieces leaving in nearly the same direction are one branch: keep the longer.
  constexpr double kSameDirection_rad = 0.35;
  std::vector<Branch> merged;
  for (const Branch& branch : junction.branches) {
    bool absorbed = false;
    for (Branch& kept : merged) {
      if (std::abs(wrap_angle_rad(kept.heading_rad - branch.heading_rad)) < kSameDirection_rad) {
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

FollowedLine choose_line(const std::vector<DetectedLine>& lines,
                         const std::optional<Junction>& junction, BranchChoice choice,
                         double max_turn_rad) {
  FollowedLine followed;
  if (lines.empty()) return followed;
  // Without a junction: the most confident line.
  auto best_line = [&] {
    int best = 0;
    for (int i = 1; i < static_cast<int>(lines.size()); ++i) {
      if (lines[i].confidence > lines[best].confidence) best = i;
    }
    return best;
  };
  if (!junction || junction->branches.size() < 2) {
    // Several lines that do not meet in view (a fork whose split point is out of view or
    // merged): the choice applies to their directions at their near ends; one line: that one.
    followed.line = best_line();
    if (lines.size() > 1) {
      double best_score = -std::numeric_limits<double>::infinity();
      for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
        const double h = heading_at(lines[i].model, lines[i].s_min_m);
        const double score = choice == BranchChoice::kLeft ? h
                             : choice == BranchChoice::kRight
                                 ? -h
                                 : -std::abs(h) - std::abs(lines[i].model.e_d_m) / 0.05;
        if (score > best_score) {
          best_score = score;
          followed.line = i;
        }
      }
    }
    followed.model = lines[followed.line].model;
    return followed;
  }
  int chosen = -1;
  double best_score = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < static_cast<int>(junction->branches.size()); ++k) {
    if (k == junction->incoming) continue;
    const double h = junction->branches[k].heading_rad;
    const double score = choice == BranchChoice::kLeft    ? h
                         : choice == BranchChoice::kRight ? -h
                                                          : -std::abs(h);
    if (score > best_score) {
      best_score = score;
      chosen = k;
    }
  }
  const Branch* branch = chosen >= 0 ? &junction->branches[chosen] : nullptr;
  if (branch && (std::abs(branch->heading_rad) <= max_turn_rad || junction->incoming < 0)) {
    // Follow the branch, in its direction away from the junction.
    followed.line = branch->line;
    const CurveModel& m = lines[branch->line].model;
    const double s = m.arc_position(junction->point_m);
    const double along = std::cos(wrap_angle_rad(heading_at(m, s) - branch->heading_rad));
    followed.model = along >= 0.0 ? m : m.reversed();
    return followed;
  }
  // A sharp turn ahead: keep to the incoming line (oriented forward) until it is reached.
  followed.line =
      junction->incoming >= 0 ? junction->branches[junction->incoming].line : best_line();
  followed.model = lines[followed.line].model;
  return followed;
}

}  // namespace agv::perception
