#include "pipeline/sim/frame_faults.h"

namespace agv::pipeline {

void apply_frame_faults(const std::vector<FrameFault>& faults, double t_s,
                        std::uint64_t frame_index, cv::Mat* frame) {
  for (const FrameFault& fault : faults) {
    if (t_s < fault.from_s || t_s >= fault.to_s) continue;
    cv::Mat noise(frame->size(), frame->type());
    cv::RNG rng(0x5EED0000u + frame_index);
    if (fault.kind == FrameFault::Kind::kCovered) {
      // Almost no light reaches the sensor: its dark level plus noise.
      rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(8.0), cv::Scalar::all(3.0));
      noise.copyTo(*frame);
    } else {
      // The scene survives at a tenth of its contrast on top of a near-saturated glare.
      rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0.0), cv::Scalar::all(2.0));
      frame->convertTo(*frame, -1, 0.1, 225.0);
      cv::add(*frame, noise, *frame);
    }
  }
}

}  // namespace agv::pipeline
