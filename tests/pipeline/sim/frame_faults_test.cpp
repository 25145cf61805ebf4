#include "pipeline/sim/frame_faults.h"

#include <gtest/gtest.h>

namespace agv::pipeline {
namespace {

cv::Mat scene_frame() {
  cv::Mat frame(120, 160, CV_8UC3, cv::Scalar(140, 130, 120));
  frame(cv::Rect(60, 0, 40, 120)).setTo(cv::Scalar(200, 60, 20));  // a blue tape
  return frame;
}

// A covered lens is dark (mean below 30 of 255, as a hand over a lens gives), a flash washes the
// frame out (mean above 230); only frames taken within [from_s, to_s) are touched, and the same
// frame index gives the same noise.
TEST(FrameFaults, EachFaultSpoilsOnlyItsOwnTime) {
  const std::vector<FrameFault> faults = {{FrameFault::Kind::kCovered, 1.0, 2.0},
                                          {FrameFault::Kind::kFlash, 3.0, 3.5}};
  cv::Mat before = scene_frame(), covered = scene_frame(), flashed = scene_frame(),
          after = scene_frame(), edge = scene_frame();
  apply_frame_faults(faults, 0.5, 5, &before);
  apply_frame_faults(faults, 1.5, 15, &covered);
  apply_frame_faults(faults, 3.2, 32, &flashed);
  apply_frame_faults(faults, 2.0, 20, &edge);  // to_s is outside
  apply_frame_faults(faults, 4.0, 40, &after);
  EXPECT_EQ(cv::norm(before, scene_frame(), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(edge, scene_frame(), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(after, scene_frame(), cv::NORM_INF), 0.0);
  EXPECT_LT(cv::mean(covered)[0], 30.0);
  EXPECT_GT(cv::mean(flashed)[1], 230.0);
  cv::Mat again = scene_frame();
  apply_frame_faults(faults, 1.5, 15, &again);
  EXPECT_EQ(cv::norm(again, covered, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace agv::pipeline
