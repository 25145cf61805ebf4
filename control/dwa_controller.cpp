#include "control/dwa_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// The local model in the path frame: from the foot point (origin) along +x, with the estimate's
// curvature, long enough for any roll-out (arcs: just under a full circle).
Path local_path(double curvature_1_m) {
  const double circle_m =
      std::abs(curvature_1_m) > 1e-9 ? 1.9 * std::numbers::pi / std::abs(curvature_1_m) : 1e9;
  return Path(
      {{Eigen::Vector2d::Zero(), 0.0, std::min(100.0, circle_m), curvature_1_m, std::nullopt, {}}});
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
  const double w_lo = std::max(-limits.w_max_rad_s, w0 - limits.alpha_max_rad_s2 * ts);
  const double w_hi = std::min(limits.w_max_rad_s, w0 + limits.alpha_max_rad_s2 * ts);

  // The path and the vehicle's pose in its frame; end_s_m: where the path's end lies.
  const bool use_plan = o.planned_path && std::isfinite(remaining_m);
  const Path local = use_plan ? Path() : local_path(estimate.curvature_1_m);
  const Path& path = use_plan ? *o.planned_path : local;
  const double foot_s_m = use_plan ? std::max(0.0, path.length_m() - remaining_m) : 0.0;
  const double end_s_m = use_plan ? path.length_m() : remaining_m;
  const Eigen::Vector2d foot = path.point_at(foot_s_m);
  const double foot_heading_rad = path.heading_at(foot_s_m);
  const Eigen::Vector2d left(-std::sin(foot_heading_rad), std::cos(foot_heading_rad));
  const Eigen::Vector2d at = foot + estimate.e_d_m * left;
  const Pose2 vehicle_in_path{at.x(), at.y(), foot_heading_rad + estimate.e_theta_rad};
  // Roll-outs stay within this much arc length of the foot point.
  const double search_window_m = 2.0 + o.horizon_s * limits.v_forward_max_m_s;
  auto lateral_m = [&](const Eigen::Vector2d& p) {
    return path.project(p, foot_s_m, search_window_m).lateral_m;
  };
  const int steps = std::max(1, static_cast<int>(std::lround(o.horizon_s / ts)));
  std::vector<Candidate> candidates;
  for (int i = 0; i < o.v_samples; ++i) {
    const double v = o.v_samples > 1 ? v_lo + (v_hi - v_lo) * i / (o.v_samples - 1) : v_hi;
    for (int j = 0; j < o.w_samples; ++j) {
      const double w = o.w_samples > 1 ? w_lo + (w_hi - w_lo) * j / (o.w_samples - 1) : 0.0;
      if (o.improved) {  // seed 002's new window limit: what the wheels can do
        const double front_vy = w * o.front_wheel_x_m, rear_vy = w * o.rear_wheel_x_m;
        if (std::hypot(v, front_vy) > o.max_wheel_speed_m_s ||
            std::hypot(v, rear_vy) > o.max_wheel_speed_m_s)
          continue;
        if (o.front_steers && std::atan2(std::abs(front_vy), v) > o.max_steer_rad) continue;
        if (o.rear_steers && std::atan2(std::abs(rear_vy), v) > o.max_steer_rad) continue;
      }
      Candidate c{v, w};
      Pose2 pose = vehicle_in_path;
      for (int k = 0; k < steps; ++k) {
        pose = integrate_twist(pose, {v, 0.0, w}, ts);
        const double front_m = lateral_m(pose.transform({o.front_wheel_x_m, 0.0}));
        const double rear_m = lateral_m(pose.transform({o.rear_wheel_x_m, 0.0}));
        c.area_m2 += (std::abs(front_m) + std::abs(rear_m)) / steps;
      }
      const double s_end = path.project(pose.translation(), foot_s_m, search_window_m).s_m;
      const double target_s = std::min(s_end + o.lookahead_m, std::max(0.0, end_s_m));
      const Eigen::Vector2d to_target = path.point_at(target_s) - pose.translation();
      // At the end of the path: the end's heading instead of the bearing to a point underfoot.
      const double bearing_rad =
          to_target.norm() > 0.05
              ? wrap_angle_rad(std::atan2(to_target.y(), to_target.x()) - pose.yaw_rad)
              : wrap_angle_rad(path.heading_at(target_s) - pose.yaw_rad);
      c.head = std::numbers::pi - std::abs(bearing_rad);
      c.clearance = std::clamp(end_s_m - s_end, 0.0, o.clearance_cap_m);
      c.speed = std::max(0.0, 1.0 - std::abs(v - context.path_speed_m_s) /
                                        std::max(1e-6, limits.v_forward_max_m_s));
      candidates.push_back(c);
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
  double best_score = -std::numeric_limits<double>::infinity();
  for (const Candidate& c : candidates) {
    double score = o.weight_heading * head.scaled(c.head) +
                   o.weight_clearance * clearance.scaled(c.clearance) +
                   o.weight_speed * speed.scaled(c.speed);
    if (o.improved) score += o.weight_area * (1.0 - area.scaled(c.area_m2));
    if (score > best_score) {
      best_score = score;
      out.command = {c.v_m_s, 0.0, c.w_rad_s};
    }
  }
  return out;
}

}  // namespace agv::control
