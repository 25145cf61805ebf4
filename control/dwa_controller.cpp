#include "control/dwa_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "common/angles.h"
#include "common/pose2.h"
#include "common/twist_motion.h"
#include "control/path.h"

namespace agv::control {
namespace {

struct Candidate {
  double v_m_s = 0.0, w_rad_s = 0.0;
  double head = 0.0, clearance = 0.0, speed = 0.0;
  double area_m2 = 0.0;  // per metre travelled: mean |front offset| + |rear offset|
};

// Appends a piece of `curvature_1_m` and `length_m` (an arc, or a line for zero curvature).
void add_piece(Path* path, double curvature_1_m, double length_m) {
  if (std::abs(curvature_1_m) < 1e-9) {
    path->add_line(length_m);
  } else {
    path->add_arc(1.0 / std::abs(curvature_1_m),
                  std::copysign(length_m * std::abs(curvature_1_m), curvature_1_m));
  }
}

// The perceived path in the path frame: through the foot point (origin) along +x with the
// estimate's curvature, from behind_m behind it (the tape the vehicle has passed, whose
// curvature is taken to be the same: the rear wheel runs there) to ahead_m ahead, and where the
// camera previews a change, on from there with the curvature ahead (arcs: at most three
// quarters of a circle each). The foot point lies at arc length behind_m.
Path local_path(const TrackingEstimate& e, double behind_m, double ahead_m) {
  auto capped = [](double curvature_1_m, double piece_m) {
    return std::abs(curvature_1_m) > 1e-9
               ? std::min(piece_m, 1.5 * std::numbers::pi / std::abs(curvature_1_m))
               : piece_m;
  };
  const double change_m = std::isfinite(e.curvature_change_m) ? e.curvature_change_m : ahead_m;
  const double here_1_m = change_m <= 1e-3 ? e.curvature_ahead_1_m : e.curvature_1_m;
  // Start behind_m back along the arc of that curvature through the origin (heading 0).
  Path path = Path::starting_at(integrate_twist({0.0, 0.0, 0.0}, {1.0, 0.0, here_1_m}, -behind_m));
  if (change_m <= 1e-3) {
    add_piece(&path, here_1_m, capped(here_1_m, behind_m + ahead_m));
    return path;
  }
  const double first_m = std::min(behind_m + change_m, capped(here_1_m, behind_m + ahead_m));
  add_piece(&path, here_1_m, first_m);
  if (first_m == behind_m + change_m && change_m < ahead_m)
    add_piece(&path, e.curvature_ahead_1_m, capped(e.curvature_ahead_1_m, ahead_m - change_m));
  return path;
}

}  // namespace

ControllerOutput DwaController::update(const TrackingEstimate& estimate,
                                       const ControlContext& context) {
  const Options& o = options_;
  const VehicleLimits& limits = context.limits;
  const double ts = context.ts_s;
  const double v0 = context.previous_command.vx_m_s, w0 = context.previous_command.wz_rad_s;
  const double remaining_m = estimate.remaining_m;
  // The dynamic window.
  double v_lo = std::max(0.0, v0 - limits.a_max_m_s2 * ts);
  double v_hi = std::min(limits.v_forward_max_m_s, v0 + limits.a_max_m_s2 * ts);
  // Stopping distance at half the deceleration limit: margin for the period-long steps.
  v_hi = std::min(v_hi, std::sqrt(limits.a_max_m_s2 * std::max(0.0, remaining_m)));
  // Progress floor: slower than this only to stop at the end (a score that rewards small
  // offsets would otherwise stop the vehicle wherever moving on makes them grow).
  v_lo = std::max(v_lo, std::min(v_hi, o.min_speed_fraction * context.path_speed_m_s));
  v_lo = std::min(v_lo, v_hi);
  // The yaw acceleration the vehicle can make: its limit, and with steered wheels what their
  // steer rate allows at the present speed.
  double alpha_rad_s2 = limits.alpha_max_rad_s2;
  if (std::isfinite(o.max_steer_rate_rad_s)) {
    double steered_x_m = 0.0;
    if (o.front_steers) steered_x_m = std::max(steered_x_m, std::abs(o.front_wheel_x_m));
    if (o.rear_steers) steered_x_m = std::max(steered_x_m, std::abs(o.rear_wheel_x_m));
    if (steered_x_m > 0.0)
      alpha_rad_s2 = std::min(alpha_rad_s2,
                              std::max(std::abs(v0), 0.05) * o.max_steer_rate_rad_s / steered_x_m);
  }
  const double w_lo = std::max(-limits.w_max_rad_s, w0 - alpha_rad_s2 * ts);
  const double w_hi = std::min(limits.w_max_rad_s, w0 + alpha_rad_s2 * ts);

  // At least half the time the vehicle needs to bring its yaw rate from the limit back to zero:
  // a shorter roll-out cannot see that a turn started now must be taken back.
  const double horizon_s =
      std::max(o.horizon_s, 0.5 * limits.w_max_rad_s / std::max(1e-9, alpha_rad_s2));
  const int steps = std::max(1, static_cast<int>(std::lround(horizon_s / ts)));
  // The path and the vehicle's pose in its frame; end_s_m: where the path's end lies.
  const bool use_plan = o.planned_path && std::isfinite(remaining_m);
  // Roll-outs stay within this much arc length of the foot point.
  const double search_window_m = 0.5 + horizon_s * limits.v_forward_max_m_s + o.lookahead_m;
  // Behind the foot point: as far as the rear wheel reaches, and a margin.
  const double behind_m = std::max(std::abs(o.front_wheel_x_m), std::abs(o.rear_wheel_x_m)) + 0.2;
  const Path local = use_plan ? Path() : local_path(estimate, behind_m, 2.0 * search_window_m);
  const Path& path = use_plan ? *o.planned_path : local;
  const double foot_s_m = use_plan ? std::max(0.0, path.length_m() - remaining_m) : behind_m;
  const double end_s_m = use_plan ? path.length_m() : remaining_m;
  const Eigen::Vector2d foot = path.point_at(foot_s_m);
  const double foot_heading_rad = path.heading_at(foot_s_m);
  const Eigen::Vector2d left(-std::sin(foot_heading_rad), std::cos(foot_heading_rad));
  const Eigen::Vector2d at = foot + estimate.e_d_m * left;
  const Pose2 vehicle_in_path{at.x(), at.y(), foot_heading_rad + estimate.e_theta_rad};

  // One roll-out at constant (v, w); nullopt where improved DWA's wheels cannot follow it.
  auto roll_out = [&](double v, double w) -> std::optional<Candidate> {
    if (o.improved) {  // seed 002's new window limit: what the wheels can do
      const double front_vy = w * o.front_wheel_x_m, rear_vy = w * o.rear_wheel_x_m;
      if (std::hypot(v, front_vy) > o.max_wheel_speed_m_s ||
          std::hypot(v, rear_vy) > o.max_wheel_speed_m_s)
        return std::nullopt;
      if (o.front_steers && std::atan2(std::abs(front_vy), v) > o.max_steer_rad)
        return std::nullopt;
      if (o.rear_steers && std::atan2(std::abs(rear_vy), v) > o.max_steer_rad) return std::nullopt;
    }
    Candidate c{v, w};
    Pose2 pose;
    // Plain DWA needs the roll-out's end only; improved DWA its wheels at every step.
    for (int k = o.improved ? 1 : steps; k <= steps; ++k) {
      pose = integrate_twist(vehicle_in_path, {v, 0.0, w}, k * ts);
      if (o.improved) {
        const double front_m =
            path.project(pose.transform({o.front_wheel_x_m, 0.0}), foot_s_m, search_window_m)
                .lateral_m;
        const double rear_m =
            path.project(pose.transform({o.rear_wheel_x_m, 0.0}), foot_s_m, search_window_m)
                .lateral_m;
        c.area_m2 += (std::abs(front_m) + std::abs(rear_m)) / steps;
      }
    }
    // Heading: the rolled-out heading against the direction to the next path point, the point
    // lookahead_m beyond the foot of the roll-out's end. The path's own bend between that foot
    // and the point is taken out (the chord of an arc leans by half its angle): on the path
    // and along it, the roll-out scores best whatever the curvature (uncorrected, the roll-outs
    // that cut the curve score best, and the vehicle settles that far inside it).
    const PathProjection end_foot = path.project(pose.translation(), foot_s_m, search_window_m);
    const double target_s = std::min(end_foot.s_m + o.lookahead_m, std::max(0.0, end_s_m));
    const Eigen::Vector2d target = path.point_at(target_s);
    const Eigen::Vector2d to_target = target - pose.translation();
    const Eigen::Vector2d chord = target - end_foot.point;
    double wanted_rad = path.heading_at(target_s);  // at the end of the path
    if (to_target.norm() > 0.05 && chord.norm() > 1e-6) {
      const double bend_rad =
          wrap_angle_rad(std::atan2(chord.y(), chord.x()) - end_foot.heading_rad);
      wanted_rad = std::atan2(to_target.y(), to_target.x()) - bend_rad;
    }
    c.head = std::numbers::pi - std::abs(wrap_angle_rad(wanted_rad - pose.yaw_rad));
    c.clearance = std::clamp(end_s_m - end_foot.s_m, 0.0, o.clearance_cap_m);
    c.speed = std::max(
        0.0, 1.0 - std::abs(v - context.path_speed_m_s) / std::max(1e-6, limits.v_forward_max_m_s));
    return c;
  };

  const int v_samples = std::max(1, o.v_samples), w_samples = std::max(1, o.w_samples);
  auto v_at = [&](int i) {
    return v_samples > 1 ? v_lo + (v_hi - v_lo) * i / (v_samples - 1) : v_hi;
  };
  auto w_at = [&](int j) {
    return w_samples > 1 ? w_lo + (w_hi - w_lo) * j / (w_samples - 1) : std::clamp(0.0, w_lo, w_hi);
  };
  std::vector<Candidate> candidates;
  std::vector<int> grid(v_samples * w_samples, -1);  // candidate index, -1: not admitted
  for (int i = 0; i < v_samples; ++i) {
    for (int j = 0; j < w_samples; ++j) {
      if (const auto c = roll_out(v_at(i), w_at(j))) {
        grid[i * w_samples + j] = static_cast<int>(candidates.size());
        candidates.push_back(*c);
      }
    }
  }
  last_candidates_ = static_cast<int>(candidates.size());
  ControllerOutput out;
  if (candidates.empty()) {  // no wheel can follow anything in the window: brake straight on
    out.command = {v_lo, 0.0, std::clamp(0.0, w_lo, w_hi)};
    out.no_feasible_horizon = true;
    return out;
  }
  // Each term's range over the candidates, for the normalisation.
  struct Range {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    void add(double x) { lo = std::min(lo, x), hi = std::max(hi, x); }
    double scaled(double x) const { return hi - lo > 1e-12 ? (x - lo) / (hi - lo) : 0.0; }
  };
  Range head, clearance, speed, area;
  for (const Candidate& c : candidates) {
    head.add(c.head);
    clearance.add(c.clearance);
    speed.add(c.speed);
    area.add(c.area_m2);
  }
  auto score_of = [&](const Candidate& c) {
    double score = o.weight_heading * head.scaled(c.head) +
                   o.weight_clearance * clearance.scaled(c.clearance) +
                   o.weight_speed * speed.scaled(c.speed);
    if (o.improved) score += o.weight_area * (1.0 - area.scaled(c.area_m2));
    return score;
  };
  int best = -1;
  double best_score = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < static_cast<int>(candidates.size()); ++k) {
    const double score = score_of(candidates[k]);
    if (score > best_score) best_score = score, best = k;
  }
  out.command = {candidates[best].v_m_s, 0.0, candidates[best].w_rad_s};
  // Between samples: the vertex of the parabola through the best sample's score and its two
  // neighbours in w, rolled out and kept where it scores higher. The grid's w step (alpha Ts
  // over the samples) is coarse against the turn that removes a millimetre; without this the
  // command jumps between neighbouring samples and the vehicle weaves by that much.
  const auto where = std::find(grid.begin(), grid.end(), best) - grid.begin();
  const int bi = static_cast<int>(where) / w_samples, bj = static_cast<int>(where) % w_samples;
  if (bj > 0 && bj + 1 < w_samples && grid[where - 1] >= 0 && grid[where + 1] >= 0) {
    const double s_minus = score_of(candidates[grid[where - 1]]);
    const double s_plus = score_of(candidates[grid[where + 1]]);
    const double curvature = s_minus - 2.0 * best_score + s_plus;
    if (curvature < 0.0) {
      const double offset = 0.5 * (s_minus - s_plus) / curvature;  // in samples, |.| <= 0.5
      const double w = w_at(bj) + offset * (w_at(bj + 1) - w_at(bj));
      if (const auto refined = roll_out(v_at(bi), w); refined && score_of(*refined) > best_score)
        out.command = {refined->v_m_s, 0.0, refined->w_rad_s};
    }
  }
  return out;
}

}  // namespace agv::control
