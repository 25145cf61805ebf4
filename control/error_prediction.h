#pragma once

#include <deque>
#include <limits>

#include "common/body_twist.h"
#include "control/path.h"

namespace agv::control {

// The path's curvature along the way: curvature_1_m, changing to ahead_1_m once the vehicle has
// travelled change_m along the path (never, when infinite).
struct CurvatureProfile {
  double curvature_1_m = 0.0;
  double change_m = std::numeric_limits<double>::infinity();
  double ahead_1_m = 0.0;
};

// The commands sent to the vehicle, each acting from its send time until the next one.
class CommandHistory {
 public:
  explicit CommandHistory(double keep_s = 2.0) : keep_s_(keep_s) {}
  void record(double sent_at_s, const BodyTwist& command);
  void clear() { entries_.clear(); }

  // Tracking error at to_s, predicted from the error measured at from_s by integrating the exact
  // path-frame error kinematics under the commands sent in between, on a path of constant
  // curvature:
  //   e_d'     = vx sin(e_theta) + vy cos(e_theta)
  //   e_theta' = wz - curvature * (vx cos(e_theta) - vy sin(e_theta)) / (1 - curvature e_d)
  // Before the first recorded command the vehicle is assumed to hold that first command.
  TrackingError predict(const TrackingError& at_from, double curvature_1_m, double from_s,
                        double to_s) const {
    return predict(at_from, CurvatureProfile{curvature_1_m}, from_s, to_s);
  }
  // The same on a path whose curvature changes on the way (a preview of the tape ahead).
  TrackingError predict(const TrackingError& at_from, const CurvatureProfile& curvature,
                        double from_s, double to_s) const;

 private:
  struct Entry {
    double sent_at_s;
    BodyTwist command;
  };
  std::deque<Entry> entries_;
  double keep_s_;
};

}  // namespace agv::control
