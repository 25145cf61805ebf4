#pragma once

#include "control/path_controller.h"

namespace agv::control {

// Two independent PID loops for comparison with the finite-step law: lateral speed from e_d,
// yaw rate from e_theta, plus the curvature feed-forward. The gains are per second so that a
// gain of 1 halves an error in about 0.7 s. The default gains were tuned on a grid
// (docs/pid_tuning_suite.py): the smallest worst-case settle time over Table 1, Table 2, heavy
// noise and 3 frames of uncompensated latency. Integral and derivative action did not help there
// (the integral's slow tail cost seconds; straight tape has no steady disturbance to remove).
class PidController : public PathController {
 public:
  struct Options {
    double kp_d_1_s = 2.0;
    double ki_d_1_s2 = 0.0;
    double kd_d = 0.0;
    double kp_theta_1_s = 2.0;
    double ki_theta_1_s2 = 0.0;
    double kd_theta = 0.0;
    double integral_limit_m_s = 0.05;  // anti-windup: bound on each integral term's output
  };

  explicit PidController(const Options& options) : options_(options) {}

  ControllerOutput update(const TrackingEstimate& estimate, const ControlContext& context) override;
  void reset() override;
  std::string name() const override { return "pid"; }

 private:
  Options options_;
  bool has_previous_ = false;
  double previous_e_d_m_ = 0.0;
  double previous_e_theta_rad_ = 0.0;
  double integral_e_d_m_s_ = 0.0;
  double integral_e_theta_rad_s_ = 0.0;
};

}  // namespace agv::control
