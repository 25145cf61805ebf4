#pragma once

#include <mutex>

#include "common/body_twist.h"
#include "common/pose2.h"
#include "pipeline/sim/plant.h"

namespace agv::pipeline {

// The plant over a run: its state at the last control period and the command it has followed
// since. The camera, which takes frames between periods, sees the pose the plant reaches under
// that command (through its actuator lag or steer rates), exactly as the next period will find
// it. Thread-safe: the camera and control threads share one.
class SimulatedVehicle {
 public:
  struct State {
    Pose2 pose;
    BodyTwist twist;  // the twist the vehicle really has
  };

  SimulatedVehicle(const Plant& plant, const BodyTwist& command, double t_s = 0.0)
      : plant_(plant), command_(command), t_s_(t_s) {}

  // Moves the plant to the next control period at t_s, dt_s after the last one.
  void advance(double t_s, double dt_s);
  // The command the vehicle follows from now on.
  void command(const BodyTwist& command);
  // The state at t_s, not before the last period.
  State state_at(double t_s) const;

 private:
  mutable std::mutex mutex_;
  Plant plant_;
  BodyTwist command_;
  double t_s_;
};

}  // namespace agv::pipeline
