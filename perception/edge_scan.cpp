#include "perception/edge_scan.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>

#include "common/prefetch.h"

namespace agv::perception {
namespace {

// Median of values[first, last) (the element a sort puts at the middle), using `scratch` (no
// allocation once it has grown); of a few values (a window's ends), the one whose rank (values
// below it, and equal ones before it) is the middle, by comparisons without branches.
float median_of(const float* first, const float* last, std::vector<float>* scratch) {
  constexpr std::ptrdiff_t kFew = 16;
  const std::ptrdiff_t n = last - first;
  if (n <= kFew) {
    for (std::ptrdiff_t i = 0; i + 1 < n; ++i) {
      std::ptrdiff_t rank = 0;
      for (std::ptrdiff_t j = 0; j < n; ++j)
        rank += (first[j] < first[i]) | ((j < i) & (first[j] == first[i]));
      if (rank == n / 2) return first[i];
    }
    return first[n - 1];
  }
  scratch->assign(first, last);
  const auto middle = scratch->begin() + scratch->size() / 2;
  std::nth_element(scratch->begin(), middle, scratch->end());
  return *middle;
}

// Contrast samples along a line of pixels starting at `first`, `stride` bytes apart.
void sample_contrast(const unsigned char* first, size_t stride, int count, int channels,
                     const ContrastAxis& axis, std::vector<float>* out) {
  out->resize(count);
  if (stride == static_cast<size_t>(channels)) {  // along a row
    axis.apply_to_row(first, count, channels, out->data());
    return;
  }
  for (int i = 0; i < count; ++i) {
    const unsigned char* p = first + i * stride;
    (*out)[i] =
        channels == 1 ? axis.apply(p[0]) : axis.apply(*reinterpret_cast<const cv::Vec3b*>(p));
  }
}

// Whether any of `count` samples from p, kStep (+1 or -1) apart, is at or above `threshold`:
// without an early exit, so without a branch to mispredict (walk_to_edge's probes past an edge
// are mostly all below it, and an exit where one is not cost more than the probes).
template <int kStep>
bool any_at_or_above(const float* p, int count, float threshold) {
  bool any = false;
  for (int k = 0; k < count; ++k) any |= p[k * kStep] >= threshold;
  return any;
}

// walk_to_edge (below) in direction kStep.
template <int kStep>
int walk_to_edge_towards(const std::vector<float>& profile, int start, float threshold,
                         int max_dip) {
  const int n = static_cast<int>(profile.size());
  const float* p = profile.data();
  int i = start;
  while (true) {
    const int next = i + kStep;
    if (next < 0 || next >= n) return i;
    if (p[next] >= threshold) {
      i = next;
      continue;
    }
    // Below threshold: a dip if the tape comes back within max_dip samples (probes i + k kStep,
    // k = 2 .. max_dip + 1, within the profile).
    const int last_k = std::min(max_dip + 1, kStep > 0 ? n - 1 - i : i);
    if (last_k < 2 || !any_at_or_above<kStep>(p + i + 2 * kStep, last_k - 1, threshold))
      return next;
    int k = 2;
    while (p[i + k * kStep] < threshold) ++k;
    i += k * kStep;
  }
}

// From `start` (on the tape), steps in direction `step` while the profile stays at or above
// `threshold`, crossing dips below it that are at most max_dip samples long (worn spots);
// returns the first sample beyond the tape's edge (or the profile's end).
int walk_to_edge(const std::vector<float>& profile, int start, int step, float threshold,
                 int max_dip) {
  return step > 0 ? walk_to_edge_towards<1>(profile, start, threshold, max_dip)
                  : walk_to_edge_towards<-1>(profile, start, threshold, max_dip);
}

struct Run {
  int lo, hi;  // downsampled coordinates along the scan line, inclusive
};

// Runs of `label` on one downsampled scan line, within [from, to) along it (the label's box:
// there are none beyond); gaps of one sample are bridged.
void runs_on_line(const cv::Mat& labels, int small_line, bool along_rows, int label, int from,
                  int to, std::vector<Run>* runs) {
  runs->clear();
  int start = -1, last = -10;
  for (int i = from; i < to; ++i) {
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

// An edge's half-way level is taken from kEdgeNear samples on each side of it, starting kEdgeGap
// samples away (find_profile_edges' third pass, edge_from_border).
constexpr int kEdgeNear = 4;
constexpr float kEdgeGap = 1.5f;

// The profile between samples (linear interpolation; clamped to its ends). Truncation stands in
// for the floor (a quarter of the cost): they differ only below 0, which the clamp takes to 0.
float profile_at(const std::vector<float>& profile, float x) {
  const int k = std::clamp(static_cast<int>(x), 0, static_cast<int>(profile.size()) - 2);
  return profile[k] + (x - k) * (profile[k + 1] - profile[k]);
}

// The mean of the profile at e -+ (kEdgeGap + k), k = 0 .. kEdgeNear - 1: symmetric about the
// edge at e, so that the blur of the edge raises the one side's level as much as it lowers the
// other's and leaves the half-way level where it is.
float half_way_level(const std::vector<float>& profile, float e) {
  float sum = 0.0f;
  for (int k = 0; k < kEdgeNear; ++k)
    sum += profile_at(profile, e + (kEdgeGap + k)) + profile_at(profile, e - (kEdgeGap + k));
  return sum / (2 * kEdgeNear);
}

// The index of the first largest of samples [lo, hi] (std::max_element's answer): the largest
// value first, over four interleaved running maxima (std::max_element's one running comparison
// waits on itself at every sample), then its first place. With the partial sums below, about
// 1.5 us of a tracked frame's 100. The profile holds no NaN (pixel levels through a finite axis).
int first_largest(const std::vector<float>& profile, int lo, int hi) {
  const float* p = profile.data();
  float m[4] = {p[lo], p[lo], p[lo], p[lo]};
  int i = lo;
  for (; i + 3 <= hi; i += 4)
    for (int k = 0; k < 4; ++k) m[k] = p[i + k] > m[k] ? p[i + k] : m[k];
  for (; i <= hi; ++i) m[0] = p[i] > m[0] ? p[i] : m[0];
  const float largest = std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
  int first = lo;
  while (p[first] != largest) ++first;
  return first;
}

// Sum and count of samples [lo, hi] above `level`, in four interleaved partial sums (one sum
// waited on its own addition at every sample); the sum's rounding differs from the sum in order
// by a few parts in 10^7 of the tape's level.
std::pair<float, int> sum_above(const std::vector<float>& profile, int lo, int hi, float level) {
  const float* p = profile.data();
  float sums[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  int counts[4] = {0, 0, 0, 0};
  int i = lo;
  for (; i + 3 <= hi; i += 4) {
    for (int k = 0; k < 4; ++k) {
      const bool above = p[i + k] > level;
      sums[k] += above ? p[i + k] : 0.0f;
      counts[k] += above;
    }
  }
  for (; i <= hi; ++i) {
    const bool above = p[i] > level;
    sums[0] += above ? p[i] : 0.0f;
    counts[0] += above;
  }
  return {(sums[0] + sums[1]) + (sums[2] + sums[3]), counts[0] + counts[1] + counts[2] + counts[3]};
}

// The medians of a profile window's outermost `side` samples at each end.
struct WindowEnds {
  float first, second;
};
WindowEnds window_ends(const std::vector<float>& profile, int side, std::vector<float>* scratch) {
  const int count = static_cast<int>(profile.size());
  return {median_of(profile.data(), profile.data() + side, scratch),
          median_of(profile.data() + count - side, profile.data() + count, scratch)};
}

// The tape's two edges on one contrast profile whose samples [run_lo, run_hi] hold the tape
// (its peak is searched there only; the flanks may hold other tape), with at least 2 * side
// floor samples beyond each edge: the places where the profile crosses half-way between the
// local floor level (each side separately: `ends`, the medians of its outermost `side` samples
// from window_ends) and the tape level next to that edge. Positions are sub-pixel sample
// indices.
struct ProfileEdges {
  float first = 0.0f, second = 0.0f;
  float contrast = 0.0f;  // tape level minus floor level
};

std::optional<ProfileEdges> find_profile_edges(const std::vector<float>& profile, int run_lo,
                                               int run_hi, int side, int max_dip,
                                               float min_contrast, const WindowEnds& ends) {
  const int count = static_cast<int>(profile.size());
  const float floor_first = ends.first, floor_second = ends.second;
  const int peak = first_largest(profile, run_lo, run_hi);
  // Tape level: mean of the samples in the upper half between floor and peak. It sets the
  // threshold of both edges alike, so its error moves them apart or together and leaves
  // their midpoint, the centre line, where it is: a mean is precise enough.
  const float floor_level = 0.5f * (floor_first + floor_second);
  const float upper = 0.5f * (floor_level + profile[peak]);
  const auto [tape_sum, tape_count] = sum_above(profile, run_lo, run_hi, upper);
  const float tape_level = tape_sum / std::max(1, tape_count);
  const float contrast = tape_level - floor_level;
  if (contrast < min_contrast) return std::nullopt;

  // Walk outwards from the peak to the half-way crossings, each against its own floor level.
  const float threshold_first = 0.5f * (floor_first + tape_level);
  const float threshold_second = 0.5f * (floor_second + tape_level);
  int i = walk_to_edge(profile, peak, -1, threshold_first, max_dip);
  int j = walk_to_edge(profile, peak, +1, threshold_second, max_dip);
  if (i < side || j > count - 1 - side) return std::nullopt;  // beyond the floor samples
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
  // A walk at a level no higher than the first pass's passes wherever that walk passed (each
  // sample it stood on, and the end of each dip it bridged, lies at or above the lower level
  // too, and no dip is longer): it goes on from the first pass's last sample on the tape, not
  // from the peak (the same answer, without walking the tape's width again: a tenth of a
  // tracked frame's time). The first pass's answer at the profile's ends may be either.
  auto walk_again = [&](int before, int step, float before_level, float level) {
    const bool goes_on = level <= before_level && before > 0 && before < count - 1;
    return walk_to_edge(profile, goes_on ? before - step : peak, step, level, max_dip);
  };
  i = walk_again(i, -1, threshold_first, local_first);
  j = walk_again(j, +1, threshold_second, local_second);
  if (i < side || j > count - 1 - side) return std::nullopt;
  // Third pass with both levels taken right next to each edge: floor texture varies over a few
  // millimetres, so the floor far out differs from the floor the edge blends into. At the
  // second pass's sub-pixel edge e, the floor's level is the mean of the profile at
  // e -+ (kEdgeGap + k) and the tape's at e +- (kEdgeGap + k), k = 0 .. kEdgeNear - 1 (linear
  // interpolation): symmetric about the edge, so that the blur of the edge raises the one level
  // as much as it lowers the other and leaves the half-way level where it is. An edge this
  // moves by more than 2 samples (a texture blob as bright as the tape next to it) keeps the
  // second pass's place.
  // Sub-pixel place where the profile crosses `level` between sample k (below it, on the floor)
  // and its neighbour towards the tape: k + 1 for the first edge, k - 1 for the second.
  auto first_crossing = [&](int k, float level) {
    return k + (level - profile[k]) / (profile[k + 1] - profile[k]);
  };
  auto second_crossing = [&](int k, float level) {
    return k - (level - profile[k]) / (profile[k - 1] - profile[k]);
  };
  const float first_2 = first_crossing(i, local_first);
  const float second_2 = second_crossing(j, local_second);
  const float reach = kEdgeGap + kEdgeNear - 1;
  // The walk to an edge at `level` starts 3 samples inside the tape from the edge before (the
  // peak walk would pass there on its way to any edge within 2 samples), or else at the peak.
  auto walk_near = [&](int edge, int step, float level) {
    const int start = step < 0 ? std::min(peak, edge + 3) : std::max(peak, edge - 3);
    return walk_to_edge(profile, profile[start] >= level ? start : peak, step, level, max_dip);
  };
  // Each round moves the edge by about a quarter of the error the round before left (the
  // windows sit on the ramps' flanks); two rounds bring a half-pixel error to a few hundredths.
  ProfileEdges edges;
  edges.contrast = contrast;
  edges.first = first_2;
  edges.second = second_2;
  for (int round = 0; round < 2; ++round) {
    const float first = edges.first, second = edges.second;
    if (first - reach >= 0.0f && first + reach < second) {
      const float level = half_way_level(profile, first);
      const int k = walk_near(i, -1, level);
      if (k >= side && std::abs(k - i) <= 2) edges.first = first_crossing(k, level);
    }
    if (second + reach <= count - 1 && second - reach > first) {
      const float level = half_way_level(profile, second);
      const int k = walk_near(j, +1, level);
      if (k <= count - 1 - side && std::abs(k - j) <= 2) edges.second = second_crossing(k, level);
    }
  }
  return edges;
}

// Contrast profile of samples [lo, lo + count) of one image row (along_rows) or column, smoothed
// by a symmetric [1 2 1] / 4 kernel, which lowers noise without moving a symmetric edge.
void contrast_profile(const cv::Mat& frame, const ContrastAxis& axis, bool along_rows, int line,
                      int lo, int count, std::vector<float>* raw, std::vector<float>* profile) {
  const size_t pixel_bytes = frame.elemSize();
  const unsigned char* first = along_rows ? frame.ptr<unsigned char>(line) + lo * pixel_bytes
                                          : frame.ptr<unsigned char>(lo) + line * pixel_bytes;
  const size_t stride = along_rows ? pixel_bytes : frame.step[0];
  sample_contrast(first, stride, count, frame.channels(), axis, raw);
  profile->resize(count);
  (*profile)[0] = (*raw)[0];
  (*profile)[count - 1] = (*raw)[count - 1];
  for (int i = 1; i + 1 < count; ++i)
    (*profile)[i] = 0.25f * (*raw)[i - 1] + 0.5f * (*raw)[i] + 0.25f * (*raw)[i + 1];
}

// Whether each end of a profile window lies on the tape rather than the floor: the median of its
// outermost samples (`ends`) is within a quarter of the contrast from the peak of the run
// [run_lo, run_hi].
std::pair<bool, bool> window_ends_on_tape(const std::vector<float>& profile, int run_lo, int run_hi,
                                          const WindowEnds& ends) {
  const float peak = *std::max_element(profile.begin() + run_lo, profile.begin() + run_hi + 1);
  const float near_peak = peak - 0.25f * (peak - std::min(ends.first, ends.second));
  return {ends.first > near_peak, ends.second > near_peak};
}

EdgePair edge_pair(const ProfileEdges& found, int lo, int line, bool along_rows) {
  EdgePair pair;
  pair.contrast = found.contrast;
  pair.along_rows = along_rows;
  const float a = lo + found.first, b = lo + found.second;
  const float l = static_cast<float>(line);
  pair.first_px = along_rows ? cv::Point2f(a, l) : cv::Point2f(l, a);
  pair.second_px = along_rows ? cv::Point2f(b, l) : cv::Point2f(l, b);
  return pair;
}

// One scan line's crossing of a region: its edges found crossing dips up to max_dip (wide) and
// crossing none (tight), in samples along the line.
struct Crossing {
  int line = 0, lo = 0;
  std::optional<ProfileEdges> wide, tight;
};

// Where a dip was crossed on some scan lines, which place is the tape's edge there: a dip may be
// a worn spot inside the tape (the edge beyond it) or a gap of floor between the tape and a floor
// blob as bright as the tape (the edge before it). The tape's edge runs on from line to line, a
// blob's rim does not. Each side of a crossing whose two walks disagree counts, for each of its
// two places, the settled places (both walks agree) of that side on the lines within
// kSettledReach_px, of crossings of the same tape (their pairs overlap this one's tight pair),
// that line up with it: within kLinedUp_px (plus kLinedUpPerLine_px a line) of the straight line
// through it at the settled places' median slope. The tight walk's place is taken where at least
// kMinSupport places line up with it and more than twice as many as with the wide walk's (at a
// fork, the legs' chords, bridged near their split, line up with the wide place as the one-leg
// chords further on do with the tight one: the wide place stays). A crossing whose wide walk
// found no pair (it ran off the window) gives the tight walk's where both its sides are taken.
std::vector<EdgePair> edges_past_dips(const std::vector<Crossing>& crossings, bool along_rows) {
  constexpr int kSettledReach_px = 32, kMinSupport = 3;
  constexpr float kSettled_px = 1.0f, kLinedUp_px = 1.5f, kLinedUpPerLine_px = 0.05f;
  auto place = [](const Crossing& c, const ProfileEdges& e, int side) {
    return c.lo + (side == 0 ? e.first : e.second);
  };
  auto settled = [&](const Crossing& c, int side) {
    return c.wide && c.tight &&
           std::abs(place(c, *c.wide, side) - place(c, *c.tight, side)) < kSettled_px;
  };
  std::vector<std::pair<float, float>> near;  // (line offset, settled place)
  std::vector<float> slopes;
  // Whether the tight place of `side` of crossing k is the tape's edge (see above).
  auto tight_lines_up = [&](size_t k, int side) {
    const Crossing& c = crossings[k];
    const float lo = place(c, *c.tight, 0), hi = place(c, *c.tight, 1);
    near.clear();
    // The crossings come in the order of their lines.
    size_t first = k, last = k;
    while (first > 0 && c.line - crossings[first - 1].line <= kSettledReach_px) --first;
    while (last + 1 < crossings.size() && crossings[last + 1].line - c.line <= kSettledReach_px)
      ++last;
    for (size_t m = first; m <= last; ++m) {
      const Crossing& o = crossings[m];
      if (m == k || !settled(o, side)) continue;
      if (place(o, *o.wide, 1) < lo || place(o, *o.wide, 0) > hi) continue;  // other tape
      near.emplace_back(static_cast<float>(o.line - c.line), place(o, *o.wide, side));
    }
    if (static_cast<int>(near.size()) < kMinSupport) return false;
    slopes.clear();
    for (size_t i = 0; i + 1 < near.size(); ++i)
      if (near[i + 1].first > near[i].first)
        slopes.push_back((near[i + 1].second - near[i].second) /
                         (near[i + 1].first - near[i].first));
    if (slopes.empty()) return false;
    std::nth_element(slopes.begin(), slopes.begin() + slopes.size() / 2, slopes.end());
    const float slope = slopes[slopes.size() / 2];
    auto lined_up = [&](float at) {
      int count = 0;
      for (const auto& [dl, p] : near)
        count += std::abs(p - (at + slope * dl)) <= kLinedUp_px + kLinedUpPerLine_px * std::abs(dl);
      return count;
    };
    const int tight = lined_up(place(c, *c.tight, side));
    const int wide = c.wide ? lined_up(place(c, *c.wide, side)) : 0;
    return tight >= kMinSupport && tight > 2 * wide;
  };
  std::vector<EdgePair> edges;
  for (size_t k = 0; k < crossings.size(); ++k) {
    const Crossing& c = crossings[k];
    if (!c.tight || (c.wide && settled(c, 0) && settled(c, 1))) {
      if (c.wide) edges.push_back(edge_pair(*c.wide, c.lo, c.line, along_rows));
      continue;
    }
    ProfileEdges chosen = c.wide ? *c.wide : *c.tight;
    bool kept = true;
    for (int side = 0; side < 2; ++side) {
      if (settled(c, side)) continue;
      const bool tight = tight_lines_up(k, side);
      if (!c.wide) {
        kept = kept && tight;
      } else if (tight) {
        (side == 0 ? chosen.first : chosen.second) = side == 0 ? c.tight->first : c.tight->second;
      }
    }
    if (kept) edges.push_back(edge_pair(chosen, c.lo, c.line, along_rows));
  }
  return edges;
}

}  // namespace

// The walk that crosses no dip is tried only on a floor this textured (its noise in tape
// contrasts): no plainer floor shows a blob near the tape's brightness, and a dip there is a worn
// spot, or the floor between a fork's legs near their split, where the legs' bridged chords make
// the way taken at wide forks (agv evaluate seeds 1-36 with the walks chosen on every floor: a
// dozen fork sequences, all on plainer floors, took the other way; gated, they read as before,
// while 18/2's 92 mm light grey tape on a floor of 0.09 went from 72 to 100 % found, 16.9 to
// 0.16 mm; forks of wide tape on textured floors still move: 36/4 9.4 -> 11.5 mm).
constexpr float kTexturedFloorNoise = 0.05f;

std::vector<EdgePair> scan_tape_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                      const TapeRegions& coarse, const TapeRegion& region,
                                      bool along_rows, const EdgeScanOptions& options) {
  std::vector<Crossing> crossings;
  const int ds = coarse.downsample;
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

  int runs_small_line = -1;  // the downsampled line `runs` were found on
  for (int line = first_line; line <= last_line; line += options.step) {
    const int small_line = std::min(line / ds, small_lines - 1);
    if (small_line != runs_small_line) {
      runs_on_line(labels, small_line, along_rows, region.label, along_rows ? box.x : box.y,
                   along_rows ? box.br().x : box.br().y, &runs);
      runs_small_line = small_line;
    }
    for (const Run& run : runs) {
      // Up to `reach` beyond the run on each side, within the image; at least a few floor
      // samples are needed beyond each edge, else the edge is unknowable.
      int lo = std::max(0, run.lo * ds - reach);
      int hi = std::min(line_length - 1, run.hi * ds + ds - 1 + reach);
      if (run.lo * ds - lo < 2 * side || hi - (run.hi * ds + ds - 1) < 2 * side) continue;
      contrast_profile(frame, axis, along_rows, line, lo, hi - lo + 1, &raw, &profile);
      // The coarse run may hold only one end of the tape's width (next to a shadow's edge, say):
      // a window ending on the tape is widened on that side once, by twice the flank.
      WindowEnds ends = window_ends(profile, side, &scratch);
      const auto [first_on_tape, second_on_tape] =
          window_ends_on_tape(profile, run.lo * ds - lo, run.hi * ds + ds - 1 - lo, ends);
      if (first_on_tape || second_on_tape) {
        const int wider_lo = first_on_tape ? std::max(0, lo - 2 * reach) : lo;
        const int wider_hi = second_on_tape ? std::min(line_length - 1, hi + 2 * reach) : hi;
        if (wider_lo != lo || wider_hi != hi) {
          lo = wider_lo;
          hi = wider_hi;
          contrast_profile(frame, axis, along_rows, line, lo, hi - lo + 1, &raw, &profile);
          ends = window_ends(profile, side, &scratch);
        }
      }
      const int count = hi - lo + 1;
      const int run_lo = std::max(0, run.lo * ds - lo),
                run_hi = std::min(count - 1, run.hi * ds + ds - 1 - lo);
      Crossing crossing;
      crossing.line = line;
      crossing.lo = lo;
      crossing.wide =
          find_profile_edges(profile, run_lo, run_hi, side, options.max_dip_px, min_contrast, ends);
      if (options.max_dip_px > 0 && coarse.floor_noise >= kTexturedFloorNoise)
        crossing.tight = find_profile_edges(profile, run_lo, run_hi, side, 0, min_contrast, ends);
      if (crossing.wide || crossing.tight) crossings.push_back(crossing);
    }
  }
  return edges_past_dips(crossings, along_rows);
}

namespace {

// The tape's one edge on a whole-line profile, walking inwards (+1: towards higher indices, -1:
// lower) from `start`, a sample on the tape near the end it runs out at, while the tape lasts;
// takes the tape's and the floor's levels (medians of `side` samples a little inside and beyond the
// first sample below half-way) and places the edge where the profile crosses half-way between
// them, refined twice with both levels taken symmetrically right next to it (as
// find_profile_edges does). Nullopt where the tape reaches the other end, where fewer than
// 2 * side samples of tape or floor lie in the image, or where the contrast is below
// min_contrast.
std::optional<float> edge_from_border(const std::vector<float>& profile, int start, int inward,
                                      int side, int max_dip, float min_contrast, float* contrast,
                                      std::vector<float>* scratch) {
  const int n = static_cast<int>(profile.size());
  auto inside = [&](int i) { return i >= 0 && i < n; };
  const int k = walk_to_edge(profile, start, inward, 0.5f, max_dip);
  if (profile[k] >= 0.5f) return std::nullopt;  // tape up to the other end
  const int floor_from = k + 2 * inward, floor_to = k + (1 + 2 * side) * inward;
  const int tape_from = k - 2 * inward, tape_to = k - (1 + 2 * side) * inward;
  if (!inside(floor_to) || !inside(tape_to) || (tape_to - start) * inward < 0) return std::nullopt;
  auto median_between = [&](int a, int b) {
    const int lo = std::min(a, b), hi = std::max(a, b);
    return median_of(profile.data() + lo, profile.data() + hi + 1, scratch);
  };
  const float floor_level = median_between(floor_from, floor_from + (side - 1) * inward);
  const float tape_level = median_between(tape_from, tape_from - (side - 1) * inward);
  *contrast = tape_level - floor_level;
  if (*contrast < min_contrast) return std::nullopt;
  // The sub-pixel place in [m, m + 1] where the profile crosses `level`, for the m nearest
  // `near` (within 2 samples) at which it does so from tape to floor going inwards.
  auto crossing_near = [&](float near, float level) -> std::optional<float> {
    std::optional<float> best;
    const int centre = static_cast<int>(std::floor(near));
    for (int m = centre - 2; m <= centre + 2; ++m) {
      if (m < 0 || m + 1 >= n) continue;
      const float tape_side = inward > 0 ? profile[m] : profile[m + 1];
      const float floor_side = inward > 0 ? profile[m + 1] : profile[m];
      if (!(tape_side >= level && floor_side < level)) continue;
      const float at = m + (level - profile[m]) / (profile[m + 1] - profile[m]);
      if (!best || std::abs(at - near) < std::abs(*best - near)) best = at;
    }
    return best;
  };
  std::optional<float> edge = crossing_near(k - 0.5f * inward, 0.5f * (floor_level + tape_level));
  if (!edge) return std::nullopt;
  for (int round = 0; round < 2; ++round) {
    const std::optional<float> refined = crossing_near(*edge, half_way_level(profile, *edge));
    if (!refined) break;
    edge = refined;
  }
  return edge;
}

}  // namespace

std::vector<EdgePair> scan_border_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                        bool along_rows, int step, float min_contrast,
                                        const EdgeScanOptions& options) {
  std::vector<EdgePair> edges;
  const int n = along_rows ? frame.cols : frame.rows;
  const int line_count = along_rows ? frame.rows : frame.cols;
  const int side = std::max(3, options.margin_px / 2);
  step = std::max(1, step);
  std::vector<float> raw, profile, scratch;
  // Where the tape meets an end: its outermost `side` samples, or the `side` after a strip of
  // floor too narrow to measure the tape's edge against (under 2 * side samples: the tape's far
  // edge just inside the image), lie on the tape; the sample on the tape the walk starts from.
  auto tape_at_end = [&](int inward) -> std::optional<int> {
    for (int offset : {0, 2 * side}) {
      const int lo = inward > 0 ? offset : n - offset - side;
      if (median_of(profile.data() + lo, profile.data() + lo + side, &scratch) < 0.5f) continue;
      return static_cast<int>(std::max_element(profile.begin() + lo, profile.begin() + lo + side) -
                              profile.begin());
    }
    return std::nullopt;
  };
  for (int line = step / 2; line < line_count; line += step) {
    contrast_profile(frame, axis, along_rows, line, 0, n, &raw, &profile);
    const std::optional<int> first_start = tape_at_end(1), second_start = tape_at_end(-1);
    if (first_start.has_value() == second_start.has_value()) continue;
    const bool first_on_tape = first_start.has_value();
    float contrast = 0.0f;
    const std::optional<float> edge = edge_from_border(
        profile, first_on_tape ? *first_start : *second_start, first_on_tape ? 1 : -1, side,
        options.max_dip_px, min_contrast, &contrast, &scratch);
    if (!edge) continue;
    ProfileEdges found;
    found.contrast = contrast;
    found.first = first_on_tape ? 0.0f : *edge;
    found.second = first_on_tape ? *edge : static_cast<float>(n - 1);
    EdgePair pair = edge_pair(found, 0, line, along_rows);
    pair.first_at_border = first_on_tape;
    pair.second_at_border = !first_on_tape;
    edges.push_back(pair);
  }
  return edges;
}

namespace {

// Asks for the pixels that a band line's window (the predicted run widened by margin_px, and
// 2 * side floor samples beyond) will read, ahead of the scan. Along rows the windows lie `step`
// rows apart (15 kB at VGA for step 8), a stride the processor does not prefetch by itself, and
// the frame a camera (or the renderer) has just written is not in the nearer caches: the first
// read of a window waited about 430 cycles on memory, two thirds of the profile's cost (agv
// bench's frames). Along columns the next line's pixels share this one's cache lines.
void prefetch_band_line(const cv::Mat& frame, const PredictedBand& band, int line, double margin_px,
                        int side) {
  if (!band.along_rows || line < 0 || line >= frame.rows) return;
  const auto [first, second] = band.edges_at(line);
  const double lo = std::max(0.0, std::min(first, second) - margin_px - 2 * side);
  const double hi =
      std::min<double>(frame.cols - 1, std::max(first, second) + margin_px + 2 * side);
  if (!(lo <= hi)) return;  // outside the image, or NaN
  const int pixel_bytes = static_cast<int>(frame.elemSize());
  const unsigned char* row = frame.ptr<unsigned char>(line);
  const int first_byte = static_cast<int>(lo) * pixel_bytes;
  const int last_byte = (static_cast<int>(hi) + 1) * pixel_bytes - 1;
  constexpr int kCacheLine = 64;
  for (int byte = first_byte; byte < last_byte; byte += kCacheLine) prefetch(row + byte);
  prefetch(row + last_byte);
}

// Buffers reused from one scan line to the next.
struct ScanBuffers {
  std::vector<float> raw, profile, scratch;
};

// One line of a band, the predicted run widened by margin_px (and 2 * side floor samples beyond
// it): the tape's edges, or nullopt. Counts windows inside the image and covered ones.
std::optional<EdgePair> scan_band_line(const cv::Mat& frame, const ContrastAxis& axis,
                                       const PredictedBand& band, int line, double margin_px,
                                       int side, int max_dip, ScanBuffers* buffers,
                                       PredictedScanStats* counts) {
  const bool along_rows = band.along_rows;
  const int line_length = along_rows ? frame.cols : frame.rows;
  const auto [first, second] = band.edges_at(line);
  // The predicted tape must lie inside the image with floor samples beyond it; the margin is
  // clipped to the image.
  const double tape_lo = std::min(first, second), tape_hi = std::max(first, second);
  if (tape_lo < 2 * side || tape_hi > line_length - 1 - 2 * side) return std::nullopt;
  const int run_lo = std::max(2 * side, static_cast<int>(std::floor(tape_lo - margin_px)));
  const int run_hi =
      std::min(line_length - 1 - 2 * side, static_cast<int>(std::ceil(tape_hi + margin_px)));
  const int lo = run_lo - 2 * side, hi = run_hi + 2 * side;
  const int count = hi - lo + 1;
  std::vector<float>& profile = buffers->profile;
  contrast_profile(frame, axis, along_rows, line, lo, count, &buffers->raw, &profile);
  ++counts->windows;
  // Tape (about 1) rather than floor (about 0) at either end of the window.
  const WindowEnds ends = window_ends(profile, side, &buffers->scratch);
  if (std::max(ends.first, ends.second) > 0.5f) {
    ++counts->covered;
    return std::nullopt;
  }
  const auto found =
      find_profile_edges(profile, run_lo - lo, run_hi - lo, side, max_dip, band.min_contrast, ends);
  if (!found) return std::nullopt;
  return edge_pair(*found, lo, line, along_rows);
}

}  // namespace

std::pair<double, double> PredictedBand::edges_at(int line) const {
  const double l = line;
  return {first[0] + first[1] * l + first[2] * l * l,
          second[0] + second[1] * l + second[2] * l * l};
}

std::optional<PredictedBand> recentre_band(const cv::Mat& frame, const ContrastAxis& axis,
                                           const PredictedBand& band, double search_margin_px,
                                           const EdgeScanOptions& options, int lines) {
  const int line_count = band.along_rows ? frame.rows : frame.cols;
  const int first_line = std::max(0, band.first_line);
  const int last_line = std::min(line_count - 1, band.last_line);
  if (last_line <= first_line || lines < 3) return std::nullopt;
  const int side = std::max(3, options.margin_px / 2);
  ScanBuffers buffers;
  PredictedScanStats counts;
  std::vector<Eigen::Vector2d> shifts;  // (line, found centre - predicted centre)
  auto line_of = [&](int k) {
    return first_line + static_cast<int>((k + 0.5) * (last_line - first_line) / lines);
  };
  for (int k = 0; k < lines; ++k)
    prefetch_band_line(frame, band, line_of(k), search_margin_px, side);
  for (int k = 0; k < lines; ++k) {
    const int line = line_of(k);
    const auto pair = scan_band_line(frame, axis, band, line, search_margin_px, side,
                                     options.max_dip_px, &buffers, &counts);
    if (!pair) continue;
    const auto [first, second] = band.edges_at(line);
    const double found = band.along_rows ? 0.5 * (pair->first_px.x + pair->second_px.x)
                                         : 0.5 * (pair->first_px.y + pair->second_px.y);
    shifts.emplace_back(line, found - 0.5 * (first + second));
  }
  if (2 * static_cast<int>(shifts.size()) < lines) return std::nullopt;
  // shift = a + b (line - middle), least squares with two rounds of Cauchy weights (scale: a
  // tenth of the tape's width), so that a line that caught something else counts little.
  const double middle = 0.5 * (first_line + last_line);
  const auto [first_mid, second_mid] = band.edges_at(static_cast<int>(middle));
  const double scale_px = std::max(1.0, 0.1 * std::abs(second_mid - first_mid));
  Eigen::Vector2d ab = Eigen::Vector2d::Zero();
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix2d ata = Eigen::Matrix2d::Zero();
    Eigen::Vector2d atb = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& ls : shifts) {
      const Eigen::Vector2d row(1.0, ls.x() - middle);
      const double r = round == 0 ? 0.0 : (ls.y() - row.dot(ab)) / scale_px;
      const double w = 1.0 / (1.0 + r * r);
      ata += w * row * row.transpose();
      atb += w * row * ls.y();
    }
    ab = ata.ldlt().solve(atb);
  }
  if (!ab.allFinite()) return std::nullopt;
  PredictedBand moved = band;
  const Eigen::Vector3d shift(ab[0] - ab[1] * middle, ab[1], 0.0);
  moved.first += shift;
  moved.second += shift;
  return moved;
}

std::vector<EdgePair> scan_predicted_edges(const cv::Mat& frame, const ContrastAxis& axis,
                                           const PredictedBand& band,
                                           const EdgeScanOptions& options,
                                           PredictedScanStats* stats) {
  std::vector<EdgePair> edges;
  PredictedScanStats counts;
  const int line_count = band.along_rows ? frame.rows : frame.cols;
  const int side = std::max(3, options.margin_px / 2);
  ScanBuffers buffers;
  const int first_line = std::max(0, band.first_line);
  const int last_line = std::min(line_count - 1, band.last_line);
  const int step = std::max(1, band.step);
  constexpr int kLinesAhead = 2;  // the windows prefetched ahead of the one scanned
  for (int k = 1; k < kLinesAhead; ++k)
    prefetch_band_line(frame, band, first_line + k * step, band.margin_px, side);
  for (int line = first_line; line <= last_line; line += step) {
    if (line + kLinesAhead * step <= last_line)
      prefetch_band_line(frame, band, line + kLinesAhead * step, band.margin_px, side);
    const auto pair = scan_band_line(frame, axis, band, line, band.margin_px, side,
                                     options.max_dip_px, &buffers, &counts);
    if (pair) edges.push_back(*pair);
  }
  if (stats) *stats = counts;
  return edges;
}

}  // namespace agv::perception
