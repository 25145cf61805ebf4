#pragma once

#include <vector>

namespace agv::control {

// The finite-step optimal correction of seed 000 (shared/seeds/DIGEST.md, eq. 12-22), in the
// paper's own symbols. The mapping to this project's frame is done once, in
// finite_step_controller.cpp: e_theta and e_d have the same sign as DESIGN.md's, the paper's
// lateral correction speed v_x is minus the body velocity v_y (left positive), and the paper's
// turn rate dw is minus the yaw rate w_z.

// Error state of the eq. 12 model.
struct PlanErrors {
  double e_theta_rad = 0.0;
  double e_d_m = 0.0;
};

struct FiniteStepPlan {
  int steps = 0;                    // N
  double c = 0.0;                   // eq. 20
  std::vector<double> lateral_m_s;  // v_x(k), k = 0..N-1 (eq. 21)
  double turn_rate_rad_s = 0.0;     // dw = e_theta(0) / (N Ts): eq. 16 (erratum 1 of DIGEST)
  double eq22_accel_m_s2 = 0.0;     // |a|max of eq. 22 = c e_theta(0)^2 (2N-1) / N^2
};

// Eq. 20-21: the control sequence that brings e_d(N) to 0 on the eq. 12 model while e_theta
// falls linearly to 0 in N steps (eq. 16). Requires steps >= 1, ts_s > 0.
FiniteStepPlan plan_finite_step(int steps, const PlanErrors& start, double path_speed_m_s,
                                double ts_s);

// One step of the eq. 12 model:
//   e_theta(k+1) = e_theta(k) - dw Ts
//   e_d(k+1)     = e_d(k) - Ts v_x + Ts v_tau e_theta(k) - Ts v_x e_theta(k)^2
PlanErrors eq12_step(const PlanErrors& now, double lateral_m_s, double turn_rate_rad_s,
                     double path_speed_m_s, double ts_s);

}  // namespace agv::control
