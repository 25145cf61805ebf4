#include "control/error_prediction.h"

#include <algorithm>
#include <cmath>

namespace agv::control {
namespace {

constexpr double kMaxStep_s = 0.005;

// The foot point's speed along the path.
double along_path_m_s(const TrackingError& e, const BodyTwist& u, double curvature_1_m) {
  const double c = std::cos(e.e_theta_rad), s = std::sin(e.e_theta_rad);
  return (u.vx_m_s * c - u.vy_m_s * s) / (1.0 - curvature_1_m * e.e_d_m);
}

TrackingError derivative(const TrackingError& e, const BodyTwist& u, double curvature_1_m) {
  const double c = std::cos(e.e_theta_rad), s = std::sin(e.e_theta_rad);
  return {u.wz_rad_s - curvature_1_m * along_path_m_s(e, u, curvature_1_m),
          u.vx_m_s * s + u.vy_m_s * c};
}

// Classic Runge-Kutta step of the error kinematics under a constant command.
TrackingError rk4(const TrackingError& e, const BodyTwist& u, double curvature_1_m, double h) {
  auto add = [](const TrackingError& a, const TrackingError& da, double f) {
    return TrackingError{a.e_theta_rad + f * da.e_theta_rad, a.e_d_m + f * da.e_d_m};
  };
  const TrackingError k1 = derivative(e, u, curvature_1_m);
  const TrackingError k2 = derivative(add(e, k1, h / 2), u, curvature_1_m);
  const TrackingError k3 = derivative(add(e, k2, h / 2), u, curvature_1_m);
  const TrackingError k4 = derivative(add(e, k3, h), u, curvature_1_m);
  return {e.e_theta_rad +
              h / 6 * (k1.e_theta_rad + 2 * k2.e_theta_rad + 2 * k3.e_theta_rad + k4.e_theta_rad),
          e.e_d_m + h / 6 * (k1.e_d_m + 2 * k2.e_d_m + 2 * k3.e_d_m + k4.e_d_m)};
}

}  // namespace

void CommandHistory::record(double sent_at_s, const BodyTwist& command) {
  entries_.push_back({sent_at_s, command});
  while (entries_.size() > 2 && entries_[1].sent_at_s < sent_at_s - keep_s_) entries_.pop_front();
}

TrackingError CommandHistory::predict(const TrackingError& at_from,
                                      const CurvatureProfile& curvature, double from_s,
                                      double to_s) const {
  TrackingError e = at_from;
  double travelled_m = 0.0;  // along the path, for the curvature's change
  if (entries_.empty() || to_s <= from_s) return e;
  double t = from_s;
  while (t < to_s) {
    // The command acting at t: the last one sent at or before t (or the first, if none).
    auto it =
        std::upper_bound(entries_.begin(), entries_.end(), t,
                         [](double time, const Entry& entry) { return time < entry.sent_at_s; });
    const Entry& acting = (it == entries_.begin()) ? *it : *std::prev(it);
    const double piece_end_s = (it == entries_.end()) ? to_s : std::min(to_s, it->sent_at_s);
    const double piece_s = piece_end_s - t;
    const int steps = std::max(1, static_cast<int>(std::ceil(piece_s / kMaxStep_s)));
    for (int i = 0; i < steps; ++i) {
      const double h = piece_s / steps;
      const double k =
          travelled_m < curvature.change_m ? curvature.curvature_1_m : curvature.ahead_1_m;
      travelled_m += h * along_path_m_s(e, acting.command, k);
      e = rk4(e, acting.command, k, h);
    }
    t = piece_end_s;
  }
  return e;
}

}  // namespace agv::control
