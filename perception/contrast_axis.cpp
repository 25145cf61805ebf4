#include "perception/contrast_axis.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace agv::perception {
namespace {

constexpr double kMinColourDistance = 12.0;  // grey levels: below this a hint is not usable
constexpr double kOutlierFraction = 0.04;    // share of pixels taken as tape candidates

// Per-channel median from 256-bin histograms.
cv::Vec3d median_colour(const cv::Mat& frame) {
  const int channels = frame.channels();
  int histogram[3][256] = {};
  for (int y = 0; y < frame.rows; ++y) {
    const unsigned char* row = frame.ptr<unsigned char>(y);
    if (channels == 1) {
      for (int x = 0; x < frame.cols; ++x) ++histogram[0][row[x]];
    } else {
      for (int x = 0; x < frame.cols; ++x) {
        ++histogram[0][row[3 * x]];
        ++histogram[1][row[3 * x + 1]];
        ++histogram[2][row[3 * x + 2]];
      }
    }
  }
  cv::Vec3d median(0, 0, 0);
  const int half = static_cast<int>(frame.total() / 2);
  for (int c = 0; c < channels; ++c) {
    int cumulative = 0, level = 0;
    while (level < 255 && (cumulative += histogram[c][level]) <= half) ++level;
    median[c] = level;
  }
  if (channels == 1) median[1] = median[2] = median[0];
  return median;
}

cv::Vec3d pixel(const cv::Mat& frame, int y, int x) {
  if (frame.channels() == 1) {
    const double g = frame.at<unsigned char>(y, x);
    return {g, g, g};
  }
  const cv::Vec3b& p = frame.at<cv::Vec3b>(y, x);
  return {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])};
}

// Mean offset from the floor colour of the pixels that differ most from it, on the side
// (darker / lighter / which hue) where most of them lie.
std::optional<cv::Vec3d> dominant_outlier_offset(const cv::Mat& frame, const cv::Vec3d& floor) {
  const int channels = frame.channels();
  const size_t n = frame.total();
  // Squared colour distances (integers up to 3 * 255^2) and a histogram of their square roots.
  std::vector<int> distance_sq(n);
  std::vector<int> histogram(443, 0);
  size_t i = 0;
  for (int y = 0; y < frame.rows; ++y) {
    const unsigned char* row = frame.ptr<unsigned char>(y);
    for (int x = 0; x < frame.cols; ++x, ++i) {
      int sum = 0;
      for (int c = 0; c < channels; ++c) {
        const int d = row[x * channels + c] - static_cast<int>(floor[c]);
        sum += d * d;
      }
      distance_sq[i] = channels == 1 ? 3 * sum : sum;
      ++histogram[static_cast<int>(std::sqrt(static_cast<double>(distance_sq[i])))];
    }
  }
  const size_t keep = std::max<size_t>(8, static_cast<size_t>(n * kOutlierFraction));
  if (n <= keep) return std::nullopt;
  int cutoff = 442;
  for (size_t above = 0; cutoff > 0 && (above += histogram[cutoff]) < keep;) --cutoff;
  const int cutoff_sq = cutoff * cutoff;

  auto offset_at = [&](size_t index) {
    const int y = static_cast<int>(index / frame.cols), x = static_cast<int>(index % frame.cols);
    return pixel(frame, y, x) - floor;
  };
  cv::Vec3d mean(0, 0, 0);
  int count = 0;
  for (i = 0; i < n; ++i) {
    if (distance_sq[i] < cutoff_sq) continue;
    mean += offset_at(i);
    ++count;
  }
  if (count == 0) return std::nullopt;
  mean /= count;
  // Keep those on the mean's side: tape is one colour, floor marks of the other sign are not it.
  cv::Vec3d side(0, 0, 0);
  count = 0;
  for (i = 0; i < n; ++i) {
    if (distance_sq[i] < cutoff_sq) continue;
    const cv::Vec3d d = offset_at(i);
    if (d.dot(mean) <= 0.0) continue;
    side += d;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return side / count;
}

}  // namespace

std::optional<ContrastAxis> estimate_contrast_axis(const cv::Mat& frame,
                                                   const std::optional<cv::Vec3d>& tape_hint_bgr) {
  if (frame.empty()) return std::nullopt;
  const cv::Vec3d floor = median_colour(frame);
  const bool grey = frame.channels() == 1;
  ContrastAxis axis;
  std::optional<cv::Vec3d> direction;
  if (tape_hint_bgr) {
    cv::Vec3d d = *tape_hint_bgr - floor;
    if (grey) {
      const double level = ((*tape_hint_bgr)[0] + (*tape_hint_bgr)[1] + (*tape_hint_bgr)[2]) / 3.0;
      d = cv::Vec3d::all(level - floor[0]);
    }
    if (cv::norm(d) >= kMinColourDistance) {
      direction = d;
      axis.from_hint = true;
    }
  }
  if (!direction) direction = dominant_outlier_offset(frame, floor);
  if (!direction || cv::norm(*direction) < 1e-6) return std::nullopt;

  if (grey) {
    const double d = (*direction)[0];
    axis.weights = cv::Vec3f(static_cast<float>(1.0 / d), 0.0f, 0.0f);
    axis.offset = static_cast<float>(-floor[0] / d);
  } else {
    const cv::Vec3d w = *direction / direction->dot(*direction);
    axis.weights = cv::Vec3f(w);
    axis.offset = static_cast<float>(-w.dot(floor));
  }
  return axis;
}

}  // namespace agv::perception
