#pragma once

#include "control/finite_step_plan.h"
#include "control/path_controller.h"

namespace agv::control {

enum class HorizonMode {
  kShrinking,  // plan N, then N-1, ... from each new measurement; deadbeat
  kFixed,      // plan the same N every period and apply the first step; exponential
};

// Seed 000's finite-step optimal tracker (DIGEST eq. 16-22 with its errata), as a receding
// controller. Each period it picks N, plans eq. 21 from the current estimate and sends the
// first step: v_y = -v_x(0), w_z = -e_theta / (N Ts) + curvature * v_tau, v_x = v_tau.
// N is the smallest N in range whose plan is feasible. When none is (a vehicle acceleration
// limit so low that eq. 21's nearly flat profile cannot start or end within it), N is the
// smallest that meets everything but the acceleration limits, the output says so, and the
// LineTracker's limiter ramps the command at the vehicle's limits.
class FiniteStepController : public PathController {
 public:
  struct Options {
    double a_max_m_s2 = 0.05;  // eq. 22 bound on |a| inside the plan (paper: 0.05)
    double v_x_max_m_s = 0.5;  // eq. 22 bound on the first lateral speed (paper: 0.5)
    // Shrinking settles faster than fixed in every condition measured (0.5 s against 0.9 s on
    // Table 1 with one frame of latency) provided the latency is compensated.
    HorizonMode mode = HorizonMode::kShrinking;
    int n_fixed = 4;  // fixed mode: N, raised when the limits need more steps
    int n_min = 1;
    int n_max = 10;  // the paper's experiment corrected in 10 steps
  };

  explicit FiniteStepController(const Options& options) : options_(options) {}

  ControllerOutput update(const TrackingEstimate& estimate, const ControlContext& context) override;
  void reset() override { steps_left_ = 0; }
  std::string name() const override;

  // True when the N-step plan meets eq. 22 and the vehicle's speed limits and, with
  // `check_rates`, the vehicle's acceleration limits on every step, including the step from the
  // previous command to the first one and the drop to zero after the last.
  bool plan_is_feasible(const FiniteStepPlan& plan, const ControlContext& context,
                        double curvature_1_m, bool check_rates = true) const;

 private:
  Options options_;
  int steps_left_ = 0;  // shrinking mode: steps left in the manoeuvre under way
};

}  // namespace agv::control
