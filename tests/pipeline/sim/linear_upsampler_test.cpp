#include "pipeline/sim/linear_upsampler.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace agv::pipeline {
namespace {

// The renderer enlarges its half-resolution floor texture a row at a time and promises frames
// identical to enlarging it with cv::resize: every output value equal, bit for bit, for the
// exact doubling the renderer uses, odd sizes (not exactly double) and other ratios.
TEST(LinearUpsampler, GivesCvResizesValuesBitForBit) {
  const cv::Size cases[][2] = {{{320, 240}, {640, 480}}, {{321, 241}, {641, 481}},
                               {{100, 50}, {333, 211}},  {{160, 120}, {640, 480}},
                               {{7, 5}, {8, 9}},         {{12, 10}, {12, 10}}};
  cv::RNG rng(11);
  for (const auto& [from, to] : cases) {
    cv::Mat src(from, CV_32F);
    rng.fill(src, cv::RNG::NORMAL, 0.0, 1.0);
    cv::Mat expected;
    cv::resize(src, expected, to, 0, 0, cv::INTER_LINEAR);
    LinearUpsampler upsampler(from, to);
    cv::Mat rows(to, CV_32F);
    for (int y = 0; y < to.height; ++y) upsampler.row(src, y, rows.ptr<float>(y));
    EXPECT_EQ(cv::countNonZero(rows != expected), 0) << from << " -> " << to;
    // Rows asked for out of order, and after the source changed (forget), are the same.
    src *= -2.0f;
    cv::resize(src, expected, to, 0, 0, cv::INTER_LINEAR);
    upsampler.forget();
    for (int y = to.height - 1; y >= 0; --y) upsampler.row(src, y, rows.ptr<float>(y));
    EXPECT_EQ(cv::countNonZero(rows != expected), 0) << from << " -> " << to << " reversed";
  }
}

TEST(LinearUpsampler, RefusesToShrink) {
  EXPECT_THROW(LinearUpsampler({10, 10}, {9, 20}), std::invalid_argument);
  EXPECT_THROW(LinearUpsampler({10, 10}, {20, 9}), std::invalid_argument);
}

}  // namespace
}  // namespace agv::pipeline
