#include "perception/tape_regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "common/bin_counts.h"
#include "common/vector_clones.h"

namespace agv::perception {
namespace {

// Contrast values binned over [kLow, kHigh): medians and spreads come from the histogram.
constexpr float kLow = -2.0f, kHigh = 3.0f;
constexpr int kBins = 2000;
constexpr float kBinWidth = (kHigh - kLow) / kBins;

int bin_of(float value) {
  return std::min(kBins - 1, std::max(0, static_cast<int>((value - kLow) / kBinWidth)));
}
// bin_of for n values, in a loop that vectorises.
AGV_VECTOR_CLONES
void bins_of(const float* __restrict values, int n, int* __restrict bins) {
  for (int i = 0; i < n; ++i) bins[i] = bin_of(values[i]);
}

float value_of(double bin) { return kLow + static_cast<float>(bin + 0.5) * kBinWidth; }

// Median of the values in bins [first, last).
float histogram_median(const std::vector<int>& histogram, int first, int last) {
  long total = 0;
  for (int b = first; b < last; ++b) total += histogram[b];
  if (total == 0) return value_of(first);
  long cumulative = 0;
  for (int b = first; b < last; ++b) {
    cumulative += histogram[b];
    if (2 * cumulative >= total) return value_of(b);
  }
  return value_of(last - 1);
}

// The value with a fraction q of the histogram's counts at or below it (its bin's middle).
float histogram_quantile(const std::vector<int>& histogram, double q) {
  long total = 0;
  for (int count : histogram) total += count;
  long cumulative = 0;
  for (int b = 0; b < kBins; ++b) {
    cumulative += histogram[b];
    if (cumulative >= q * total) return value_of(b);
  }
  return value_of(kBins - 1);
}

cv::Mat contrast_of(const cv::Mat& frame, const ContrastAxis& axis) {
  cv::Mat contrast(frame.size(), CV_32F);
  for (int y = 0; y < frame.rows; ++y)
    axis.apply_to_row(frame.ptr<unsigned char>(y), frame.cols, frame.channels(),
                      contrast.ptr<float>(y));
  return contrast;
}

// Mean over `width` samples centred on each sample down the columns, with the edge samples
// repeated beyond the border; running sums (in double, in the order of the samples), O(1) per
// sample; the sums of all columns run together, row by row.
cv::Mat box_mean_down_columns(const cv::Mat& s, int width) {
  cv::Mat out(s.size(), CV_32F);
  const int n = s.rows, before = (width - 1) / 2, after = width - 1 - before;
  const double inverse_width = 1.0 / width;
  const int cols = s.cols;
  cv::Mat prefix(n + width + 1, cols, CV_64F);
  prefix.row(0).setTo(0.0);
  for (int i = 0; i < n + width; ++i) {
    const float* row = s.ptr<float>(std::clamp(i - before, 0, n - 1));
    const double* previous = prefix.ptr<double>(i);
    double* next = prefix.ptr<double>(i + 1);
    for (int x = 0; x < cols; ++x) next[x] = previous[x] + row[x];
  }
  for (int y = 0; y < n; ++y) {
    const double* low = prefix.ptr<double>(y);
    const double* high = prefix.ptr<double>(y + before + after + 1);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < cols; ++x) o[x] = static_cast<float>((high[x] - low[x]) * inverse_width);
  }
  return out;
}

// box_mean_down_columns of one image by width, each worked out once (on a ladder of bar widths
// in steps of 2x, one bar's flanks are the next narrower bar).
class BoxMeans {
 public:
  explicit BoxMeans(const cv::Mat& s) : s_(s) {}
  const cv::Mat& image() const { return s_; }
  const cv::Mat& of(int width) {
    auto at = means_.find(width);
    if (at == means_.end()) at = means_.emplace(width, box_mean_down_columns(s_, width)).first;
    return at->second;
  }

 private:
  const cv::Mat& s_;
  std::map<int, cv::Mat> means_;
};

// Bar response down the columns for a bar `width` samples wide: mean over the bar minus the
// mean of two flanks of width/2 on each side. A bar stands out on both sides: the weaker side
// bounds the response, so that a single edge (a shadow boundary, the edge of a wide stain) does
// not look like a bar. Along rows: the same down the columns of the transpose.
cv::Mat bar_response_down_columns(BoxMeans* means, double width) {
  const cv::Mat& s = means->image();
  const int bar = std::max(1, static_cast<int>(std::lround(width)));
  const int flank = std::max(1, static_cast<int>(std::lround(width / 2.0)));
  const int offset = (bar + flank + 1) / 2;  // centre of a flank from the centre of the bar
  const cv::Mat& centre = means->of(bar);
  const cv::Mat& flanks = means->of(flank);
  cv::Mat response(s.size(), CV_32F);
  for (int y = 0; y < s.rows; ++y) {
    float* out = response.ptr<float>(y);
    const float* c = centre.ptr<float>(y);
    const float* before = flanks.ptr<float>(std::max(0, y - offset));
    const float* after = flanks.ptr<float>(std::min(s.rows - 1, y + offset));
    for (int x = 0; x < s.cols; ++x) out[x] = c[x] - std::max(before[x], after[x]);
  }
  return response;
}

}  // namespace

TapeRegions find_tape_regions(const cv::Mat& small_frame, const ContrastAxis& axis, int downsample,
                              const std::vector<double>& bar_widths_small_px,
                              int min_area_small_px) {
  TapeRegions result;
  result.downsample = downsample;
  result.contrast_small = contrast_of(small_frame, axis);
  cv::Mat& bar = result.bar_small;
  bar = bar_widths_small_px.empty()
            ? result.contrast_small.clone()
            : cv::Mat(result.contrast_small.size(), CV_32F, cv::Scalar(-1e9f));
  cv::Mat transposed, along_rows;
  if (!bar_widths_small_px.empty()) cv::transpose(result.contrast_small, transposed);
  BoxMeans means_down_columns(result.contrast_small), means_along_rows(transposed);
  for (double width : bar_widths_small_px) {
    cv::transpose(bar_response_down_columns(&means_along_rows, width), along_rows);
    bar = cv::max(bar, along_rows);
    bar = cv::max(bar, bar_response_down_columns(&means_down_columns, width));
  }
  const cv::Mat& s = result.bar_small;

  std::vector<int> bins(s.total());
  for (int y = 0; y < s.rows; ++y) bins_of(s.ptr<float>(y), s.cols, &bins[y * s.cols]);
  const std::vector<int> histogram = bin_counts(bins.data(), bins.size(), kBins);
  // ISODATA on the bar response: the threshold settles half-way between the medians of the two
  // classes. It never drops below 0.25 (a quarter of the nominal tape contrast), so that floor
  // texture alone is not called tape on a tape-free frame, nor below half-way between the
  // response's median (the floor) and its 99.5 % point (the strongest bars, the tape where there
  // is any): on a coarse texture as strong as the tape the two classes are the floor's smooth
  // and its blotchy parts, and the split between them lets the blotches join the tape.
  float threshold = 0.5f;
  for (int iteration = 0; iteration < 8; ++iteration) {
    const int split = bin_of(threshold) + 1;
    const float next = std::max(0.25f, 0.5f * (histogram_median(histogram, 0, split) +
                                               histogram_median(histogram, split, kBins)));
    if (std::abs(next - threshold) < kBinWidth) break;
    threshold = next;
  }
  threshold = std::max(threshold, 0.5f * (histogram_quantile(histogram, 0.5) +
                                          histogram_quantile(histogram, 0.995)));
  const int split = bin_of(threshold) + 1;
  result.threshold = threshold;
  result.floor_level = histogram_median(histogram, 0, split);
  result.tape_level = histogram_median(histogram, split, kBins);
  // Robust spread of the floor: median absolute deviation, from the same histogram.
  std::vector<int> deviation(kBins, 0);
  for (int b = 0; b < split; ++b) {
    deviation[std::min(kBins - 1, static_cast<int>(std::abs(value_of(b) - result.floor_level) /
                                                   kBinWidth))] += histogram[b];
  }
  result.floor_noise = 1.4826f * (histogram_median(deviation, 0, kBins) - kLow);

  const cv::Mat mask = s > threshold;
  // Plain labelling; the statistics (area, box, centroid, second moments) in one pass below.
  // (connectedComponentsWithStats costs ten times as much here.)
  const int count = cv::connectedComponents(mask, result.labels_small, 8, CV_32S);
  struct Sums {
    int area = 0, x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  };
  std::vector<Sums> sums(count);
  for (int y = 0; y < s.rows; ++y) {
    const int* row = result.labels_small.ptr<int>(y);
    for (int x = 0; x < s.cols; ++x) {
      if (row[x] == 0) continue;
      Sums& m = sums[row[x]];
      ++m.area;
      m.x0 = std::min(m.x0, x);
      m.x1 = std::max(m.x1, x);
      m.y0 = std::min(m.y0, y);
      m.y1 = std::max(m.y1, y);
      m.sx += x;
      m.sy += y;
      m.sxx += static_cast<double>(x) * x;
      m.syy += static_cast<double>(y) * y;
      m.sxy += static_cast<double>(x) * y;
    }
  }
  for (int label = 1; label < count; ++label) {
    const Sums& m = sums[label];
    if (m.area < min_area_small_px) continue;
    TapeRegion region;
    region.label = label;
    region.area_small_px = m.area;
    region.box_small = cv::Rect(m.x0, m.y0, m.x1 - m.x0 + 1, m.y1 - m.y0 + 1);
    const double area = m.area;
    const cv::Point2d c(m.sx / area, m.sy / area);
    // Central second moments give the major axis.
    const double cxx = m.sxx / area - c.x * c.x, cyy = m.syy / area - c.y * c.y,
                 cxy = m.sxy / area - c.x * c.y;
    const double angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
    region.direction = {std::cos(angle), std::sin(angle)};
    const double major_var =
        (cxx + cyy) / 2.0 + std::sqrt(std::pow((cxx - cyy) / 2.0, 2) + cxy * cxy);
    region.length_px = std::sqrt(12.0 * major_var) * downsample;
    region.width_px = area * downsample * downsample / std::max(region.length_px, 1.0);
    const double minor_var =
        (cxx + cyy) / 2.0 - std::sqrt(std::pow((cxx - cyy) / 2.0, 2) + cxy * cxy);
    region.spread_px = std::sqrt(12.0 * std::max(0.0, minor_var)) * downsample;
    region.centroid_px = {(c.x + 0.5) * downsample - 0.5, (c.y + 0.5) * downsample - 0.5};
    result.regions.push_back(region);
  }
  std::sort(
      result.regions.begin(), result.regions.end(),
      [](const TapeRegion& a, const TapeRegion& b) { return a.area_small_px > b.area_small_px; });
  return result;
}

}  // namespace agv::perception
