#include "perception/contrast_axis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
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

namespace {

// Linear bar response of one float plane along rows (horizontal) or columns: mean over the
// bar minus the mean of the two flanks of half its width.
cv::Mat linear_bar(const cv::Mat& plane, int bar, bool horizontal) {
  const int flank = std::max(1, bar / 2);
  const int offset = (bar + flank + 1) / 2;
  cv::Mat centre, flanks;
  cv::blur(plane, centre, horizontal ? cv::Size(bar, 1) : cv::Size(1, bar), cv::Point(-1, -1),
           cv::BORDER_REPLICATE);
  cv::blur(plane, flanks, horizontal ? cv::Size(flank, 1) : cv::Size(1, flank), cv::Point(-1, -1),
           cv::BORDER_REPLICATE);
  cv::Mat out(plane.size(), CV_32F);
  for (int y = 0; y < plane.rows; ++y) {
    float* o = out.ptr<float>(y);
    const float* c = centre.ptr<float>(y);
    if (horizontal) {
      const float* f = flanks.ptr<float>(y);
      for (int x = 0; x < plane.cols; ++x)
        o[x] = c[x] - 0.5f * (f[std::max(0, x - offset)] + f[std::min(plane.cols - 1, x + offset)]);
    } else {
      const float* before = flanks.ptr<float>(std::max(0, y - offset));
      const float* after = flanks.ptr<float>(std::min(plane.rows - 1, y + offset));
      for (int x = 0; x < plane.cols; ++x) o[x] = c[x] - 0.5f * (before[x] + after[x]);
    }
  }
  return out;
}

// Exact quantiles of a set of values (the element a full sort would put at index floor(q n)),
// found through a 4096-bin histogram over their range: the bin that holds that element, then a
// partial sort of that bin's few values only. A partial sort of all the values per quantile was
// a quarter of a full search.
class Quantiles {
 public:
  explicit Quantiles(const std::vector<float>& values) : values_(values) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    lo_ = *lo;
    scale_ = *hi > *lo ? kBins / (*hi - *lo) : 0.0f;
    for (float v : values) ++bins_[bin(v)];
  }
  float operator()(double q) const {
    const size_t index = std::min(values_.size() - 1, static_cast<size_t>(q * values_.size()));
    size_t below = 0;
    int b = 0;
    while (below + bins_[b] <= index) below += bins_[b++];
    std::vector<float> in_bin;
    for (float v : values_)
      if (bin(v) == b) in_bin.push_back(v);
    std::nth_element(in_bin.begin(), in_bin.begin() + (index - below), in_bin.end());
    return in_bin[index - below];
  }

 private:
  static constexpr int kBins = 4096;
  int bin(float v) const { return std::min(kBins - 1, static_cast<int>((v - lo_) * scale_)); }
  const std::vector<float>& values_;
  float lo_ = 0.0f, scale_ = 0.0f;
  std::vector<size_t> bins_ = std::vector<size_t>(kBins, 0);
};

}  // namespace

std::optional<ContrastAxis> choose_contrast_axis(const cv::Mat& frame,
                                                 const std::optional<cv::Vec3d>& tape_hint_bgr,
                                                 const std::vector<double>& bar_widths_px) {
  if (frame.empty()) return std::nullopt;
  const int channels = frame.channels();
  const cv::Vec3d floor = median_colour(frame);
  std::vector<cv::Mat> planes;
  cv::Mat as_float;
  frame.convertTo(as_float, CV_32F);
  cv::split(as_float, planes);
  // Linear bar responses per width and channel, along rows and columns; a candidate's response
  // is their combination with its weights, the strongest over widths and directions. Every
  // second sample is enough to score.
  const size_t widths = bar_widths_px.size();
  std::vector<std::vector<cv::Mat>> rows(widths, std::vector<cv::Mat>(channels)),
      cols(widths, std::vector<cv::Mat>(channels));
  for (size_t w = 0; w < widths; ++w) {
    const int bar = std::max(2, static_cast<int>(std::lround(bar_widths_px[w])));
    for (int c = 0; c < channels; ++c) {
      rows[w][c] = linear_bar(planes[c], bar, true);
      cols[w][c] = linear_bar(planes[c], bar, false);
    }
  }
  std::vector<cv::Vec3d> candidates;
  if (tape_hint_bgr) candidates.push_back(*tape_hint_bgr - floor);
  if (const auto outlier = dominant_outlier_offset(frame, floor)) candidates.push_back(*outlier);
  candidates.push_back({-1, -1, -1});
  candidates.push_back({1, 1, 1});
  if (channels == 3) {
    const cv::Vec3d u1 = cv::Vec3d(1, -1, 0) / std::sqrt(2.0),
                    u2 = cv::Vec3d(1, 1, -2) / std::sqrt(6.0);
    for (int k = 0; k < 6; ++k)
      candidates.push_back(std::cos(k * CV_PI / 3) * u1 + std::sin(k * CV_PI / 3) * u2);
  }
  double best_score = 0.0;
  std::optional<ContrastAxis> best;
  std::vector<float> response;
  for (size_t k = 0; k < candidates.size(); ++k) {
    cv::Vec3d d = candidates[k];
    if (channels == 1) d = cv::Vec3d::all((d[0] + d[1] + d[2]) / 3.0);
    const double norm = cv::norm(d);
    if (norm < 1e-9) continue;
    d /= norm;
    float weight[3];
    for (int c = 0; c < channels; ++c) weight[c] = static_cast<float>(channels == 1 ? 1.0 : d[c]);
    response.assign(static_cast<size_t>((frame.rows + 1) / 2) * ((frame.cols + 1) / 2),
                    -std::numeric_limits<float>::infinity());
    for (size_t b = 0; b < widths; ++b) {
      float* out = response.data();
      for (int y = 0; y < frame.rows; y += 2) {
        const float* r[3];
        const float* s[3];
        for (int c = 0; c < channels; ++c) {
          r[c] = rows[b][c].ptr<float>(y);
          s[c] = cols[b][c].ptr<float>(y);
        }
        for (int x = 0; x < frame.cols; x += 2, ++out) {
          float along_row = 0.0f, along_column = 0.0f;
          for (int c = 0; c < channels; ++c) {
            along_row += weight[c] * r[c][x];
            along_column += weight[c] * s[c][x];
          }
          *out = std::max(*out, std::max(along_row, along_column));
        }
      }
    }
    const Quantiles levels(response);
    const float peak = levels(0.995);
    const float middle = levels(0.5);
    for (float& v : response) v = std::abs(v - middle);
    const float spread = 1.4826f * Quantiles(response)(0.5);
    // Contrast over noise, the noise at least the sensor's few grey levels (a colour axis along
    // which nothing varies is not for that a good one); the tape must stand out by 20 levels.
    // The hint is what the user knows: it wins ties.
    constexpr float kSensorNoise = 5.0f, kMinContrast = 20.0f;
    const double score =
        (peak - middle) / std::hypot(spread, kSensorNoise) * (tape_hint_bgr && k == 0 ? 1.2 : 1.0);
    if (score > best_score && peak - middle >= kMinContrast) {
      best_score = score;
      ContrastAxis axis;
      const double level = peak - middle;  // the tape's contrast along d, about
      if (channels == 1) {
        axis.weights = cv::Vec3f(static_cast<float>(d[0] * std::sqrt(3.0) / level), 0.0f, 0.0f);
        axis.offset = static_cast<float>(-floor[0] * d[0] * std::sqrt(3.0) / level);
      } else {
        const cv::Vec3d w = d / level;
        axis.weights = cv::Vec3f(w);
        axis.offset = static_cast<float>(-w.dot(floor));
      }
      axis.from_hint = tape_hint_bgr && k == 0;
      best = axis;
    }
  }
  return best;
}

}  // namespace agv::perception
