#pragma once

#include <cmath>
#include <numbers>

namespace agv {

inline constexpr double kPi = std::numbers::pi;

// Wraps an angle to (-pi, pi].
inline double wrap_angle_rad(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * std::numbers::pi);
  if (wrapped <= -std::numbers::pi) wrapped += 2.0 * std::numbers::pi;
  return wrapped;
}

constexpr double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }
constexpr double rad_to_deg(double rad) { return rad * 180.0 / std::numbers::pi; }

}  // namespace agv
