#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace agv::pipeline {

// Something that spoils the camera's frames for a while, for line-loss tests:
//   covered  the lens is covered (a hand, a cloth, dirt): a dark frame with sensor noise;
//   flash    a bright reflection washes the frame out: grey levels pushed to near saturation.
// (Gaps in the tape and tape ends are scene geometry: tape.gaps_m, the path's length.)
struct FrameFault {
  enum class Kind { kCovered, kFlash };
  Kind kind = Kind::kCovered;
  double from_s = 0.0, to_s = 0.0;  // frames taken at from_s <= t < to_s are spoiled
};

// Applies the faults active at time t_s to the frame (in place); frame_index seeds the noise.
void apply_frame_faults(const std::vector<FrameFault>& faults, double t_s,
                        std::uint64_t frame_index, cv::Mat* frame);

}  // namespace agv::pipeline
