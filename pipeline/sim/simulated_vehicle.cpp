#include "pipeline/sim/simulated_vehicle.h"

namespace agv::pipeline {

void SimulatedVehicle::advance(double t_s, double dt_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  plant_.step(command_, dt_s);
  t_s_ = t_s;
}

void SimulatedVehicle::command(const BodyTwist& command) {
  std::lock_guard<std::mutex> lock(mutex_);
  command_ = command;
}

SimulatedVehicle::State SimulatedVehicle::state_at(double t_s) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const double ahead_s = t_s - t_s_;
  if (ahead_s <= 1e-9) return {plant_.pose(), plant_.twist()};
  Plant ahead = plant_;
  ahead.step(command_, ahead_s);
  return {ahead.pose(), ahead.twist()};
}

}  // namespace agv::pipeline
