#include "perception/edge_scan.h"

#include <algorithm>
#include <cmath>

namespace agv::perception {
namespace {

// Median of values[first, last), using `scratch` (no allocation once it has grown).
float median_of(const float* first, const float* last, std::vector<float>* scratch) {
  scratch->assign(first, last);
  const auto middle = scratch->begin() + scratch->size() / 2;
  std::nth_element(scratch->begin(), middle, scratch->end());
  return *middle;
}

// Contrast samples along a line of pixels starting at `first`, `stride` bytes apart.
void sample_contrast(const unsigned char* first, size_t stride, int count, int channels,
                     const ContrastAxis& axis, std::vector<float>* out) {
  out->resize(count);
  for (int i = 0; i < count; ++i) {
    const unsigned char* p = first + i * stride;
    (*out)[i] =
        channels == 1 ? axis.apply(p[0]) : axis.apply(*reinterpret_cast<const cv::Vec3b*>(p));
  }
}

// From `start` (on the tape), steps in direction `step` while the profile stays at or above
// `threshold`, crossing dips below it that are at most max_dip samples long (worn spots);
// returns the first sample beyond the tape's edge (or the profile's end).
int walk_to_edge(const std::vector<float>& profile, int start, int step, float threshold,
                 int max_dip) {
  const int n = static_cast<int>(profile.size());
  int i = start;
  while (true) {
    const int next = i + step;
    if (next < 0 || next >= n) return i;
    if (profile[next] >= threshold) {
      i = next;
      continue;
    }
    // Below threshold: a dip if the tape comes back within max_dip samples.
    int back = -1;
    for (int k = 2; k <= max_dip + 1; ++k) {
      const int probe = i + k * step;
      if (probe < 0 || probe >= n) break;
      if (profile[probe] >= threshold) {
        back = probe;
        break;
      }
    }
    if (back < 0) return next;
    i = back;
  }
}

struct Run {
  int lo, hi;  // downsampled coordinates along the scan line, inclusive
};

// Runs of `label` on one downsampled scan line; gaps of one sample are bridged.
void runs_on_line(const cv::Mat& labels, int small_line, bool along_rows, int label,
                  std::vector<Run>* runs) {
  runs->clear();
  const int count = along_rows ? labels.cols : labels.rows;
  int start = -1, last = -10;
  for (int i = 0; i < count; ++i) {
    const int value = along_rows ? labels.at<int>(small_line, i) : labels.at<int>(i, small_line);
    if (value != label) continue;
    if (i - last > 2) {
      if (start >= 0) runs->push_back({start, last});
      start = i;
    }
    last = i;
  }
  if (start >= 0) runs->push_back({start, last});
}

}  // namespace

std::vector<EdgePair> scan_tape_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                      const TapeRegions& coarse, const TapeRegion& region,
                                      bool along_rows, const EdgeScanOptions& options) {
  std::vector<EdgePair> edges;
  const int ds = coarse.downsample;
  const int channels = frame.channels();
  const size_t pixel_bytes = frame.elemSize();
  const int line_length = along_rows ? frame.cols : frame.rows;  // samples on one scan line
  const int line_count = along_rows ? frame.rows : frame.cols;
  const cv::Rect& box = region.box_small;
  const int first_line = (along_rows ? box.y : box.x) * ds;
  const int last_line = std::min((along_rows ? box.br().y : box.br().x) * ds, line_count) - 1;
  const cv::Mat& labels = coarse.labels_small;
  const int small_lines = along_rows ? labels.rows : labels.cols;
  const int reach = std::max(options.margin_px, options.flank_px);
  const int side = std::max(3, options.margin_px / 2);
  const float min_contrast = options.min_contrast_to_noise * std::max(coarse.floor_noise, 0.01f);
  std::vector<float> raw, profile, scratch;
  std::vector<Run> runs;

  for (int line = first_line; line <= last_line; line += options.step) {
    runs_on_line(labels, std::min(line / ds, small_lines - 1), along_rows, region.label, &runs);
    for (const Run& run : runs) {
      // Up to `reach` beyond the run on each side, within the image; at least a few floor
      // samples are needed beyond each edge, else the edge is unknowable.
      const int lo = std::max(0, run.lo * ds - reach);
      const int hi = std::min(line_length - 1, run.hi * ds + ds - 1 + reach);
      if (run.lo * ds - lo < 2 * side || hi - (run.hi * ds + ds - 1) < 2 * side) continue;
      const int count = hi - lo + 1;
      const unsigned char* first = along_rows ? frame.ptr<unsigned char>(line) + lo * pixel_bytes
                                              : frame.ptr<unsigned char>(lo) + line * pixel_bytes;
      const size_t stride = along_rows ? pixel_bytes : frame.step[0];
      sample_contrast(first, stride, count, channels, axis, &raw);
      // A symmetric [1 2 1] / 4 smoothing lowers noise without moving a symmetric edge.
      profile.resize(count);
      profile[0] = raw[0];
      profile[count - 1] = raw[count - 1];
      for (int i = 1; i + 1 < count; ++i)
        profile[i] = 0.25f * raw[i - 1] + 0.5f * raw[i] + 0.25f * raw[i + 1];

      const float floor_first = median_of(profile.data(), profile.data() + side, &scratch);
      const float floor_second =
          median_of(profile.data() + count - side, profile.data() + count, &scratch);
      // The peak is searched over the run itself, not the flanks (which may hold other tape).
      const int run_lo = std::max(0, run.lo * ds - lo),
                run_hi = std::min(count - 1, run.hi * ds + ds - 1 - lo);
      const int peak = static_cast<int>(
          std::max_element(profile.begin() + run_lo, profile.begin() + run_hi + 1) -
          profile.begin());
      // Tape level: mean of the samples in the upper half between floor and peak. It sets the
      // threshold of both edges alike, so its error moves them apart or together and leaves
      // their midpoint, the centre line, where it is: a mean is precise enough.
      const float floor_level = 0.5f * (floor_first + floor_second);
      const float upper = 0.5f * (floor_level + profile[peak]);
      float tape_sum = 0.0f;
      int tape_count = 0;
      for (int i = run_lo; i <= run_hi; ++i) {
        if (profile[i] <= upper) continue;
        tape_sum += profile[i];
        ++tape_count;
      }
      const float tape_level = tape_sum / std::max(1, tape_count);
      const float contrast = tape_level - floor_level;
      if (contrast < min_contrast) continue;

      // Walk outwards from the peak to the half-way crossings, each against its own floor level.
      const float threshold_first = 0.5f * (floor_first + tape_level);
      const float threshold_second = 0.5f * (floor_second + tape_level);
      int i = walk_to_edge(profile, peak, -1, threshold_first, options.max_dip_px);
      int j = walk_to_edge(profile, peak, +1, threshold_second, options.max_dip_px);
      if (i < side || j > count - 1 - side)
        continue;  // the crossings must lie beyond the floor samples
      // Second pass with the tape's level next to each edge: a shadow edge or a light gradient
      // across the tape makes it differ from one side of the tape to the other.
      const int inside = std::max(2, (j - i) / 4);
      auto mean_of = [&](int from, int to) {
        float sum = 0.0f;
        int n = 0;
        for (int k = std::max(0, from); k <= std::min(count - 1, to); ++k, ++n) sum += profile[k];
        return n ? sum / n : tape_level;
      };
      const float local_first = 0.5f * (floor_first + mean_of(i + 2, i + 1 + inside));
      const float local_second = 0.5f * (floor_second + mean_of(j - 1 - inside, j - 2));
      i = walk_to_edge(profile, peak, -1, local_first, options.max_dip_px);
      j = walk_to_edge(profile, peak, +1, local_second, options.max_dip_px);
      if (i < side || j > count - 1 - side) continue;
      const float first_pos = i + (local_first - profile[i]) / (profile[i + 1] - profile[i]);
      const float second_pos = j - (local_second - profile[j]) / (profile[j - 1] - profile[j]);

      EdgePair pair;
      pair.contrast = contrast;
      pair.along_rows = along_rows;
      const float a = lo + first_pos, b = lo + second_pos;
      const float l = static_cast<float>(line);
      pair.first_px = along_rows ? cv::Point2f(a, l) : cv::Point2f(l, a);
      pair.second_px = along_rows ? cv::Point2f(b, l) : cv::Point2f(l, b);
      edges.push_back(pair);
    }
  }
  return edges;
}

}  // namespace agv::perception
