#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace agv::pipeline {

// cv::resize(src, dst, to, 0, 0, cv::INTER_LINEAR) of a CV_32F image of size `from` to a size
// `to` no smaller either way (enlarging: OpenCV shrinks by other rules), one output
// row at a time and bit for bit (the same weights, borders and order of float operations as
// OpenCV's generic linear resize), so that a renderer can use each row while it is in the cache
// instead of writing and reading back the whole enlarged image. Keeps the last two horizontally
// resized source rows: rows asked for in order cost one horizontal pass per source row.
class LinearUpsampler {
 public:
  // Throws std::invalid_argument when `to` is smaller than `from` either way.
  LinearUpsampler(cv::Size from, cv::Size to);

  // Output row y (to.width values) of src (CV_32F, size `from`). Call forget() when src changes.
  void row(const cv::Mat& src, int y, float* out);
  void forget();

 private:
  const std::vector<float>& resized_source_row(const cv::Mat& src, int source_row);

  cv::Size from_, to_;
  std::vector<int> x_source_;     // per output column: the left source column
  std::vector<float> x_weights_;  // per output column: the left and right source weights
  int x_interpolated_end_ = 0;    // columns from here on copy their source column
  bool doubling_ = false;         // to.width is 2 from.width with the doubling's weights
  std::vector<int> y_source_;     // per output row: the upper source row (before clamping)
  std::vector<float> y_weights_;  // per output row: the upper and lower weights
  int kept_row_[2] = {-1, -1};
  std::vector<float> kept_[2];
  int next_slot_ = 0;
};

}  // namespace agv::pipeline
