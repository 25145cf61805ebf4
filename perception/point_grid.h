#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace agv::perception {

// Points by square cells of a given size: the points within that distance of any place lie in
// the 3 x 3 cells around that place's cell. The points of a cell are listed in index order.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector2d>& points, double cell_m) : cell_m_(cell_m) {
    if (points.empty()) return;
    // A counting sort into the cells of the points' bounding box (a few hundred cells for the
    // tape in and near the view). The cell of a coordinate never decreases as it grows, so the
    // box's corner cells are the cells of the points' least and greatest coordinates.
    Eigen::Vector2d lo = points.front(), hi = lo;
    for (const Eigen::Vector2d& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const auto [x0, y0] = cell(lo);
    const auto [x1, y1] = cell(hi);
    x0_ = x0;
    y0_ = y0;
    columns_ = x1 - x0 + 1;
    rows_ = y1 - y0 + 1;
    if (points.size() >= kNone32 || columns_ > 4096 || rows_ > 4096 ||
        columns_ * rows_ > static_cast<long long>(max_cells(points.size()))) {
      columns_ = rows_ = 0;  // too spread out for a dense grid: none (every lookup scans all)
      all_.resize(points.size());
      for (size_t j = 0; j < points.size(); ++j) all_[j] = j;
      return;
    }
    // Counted into each cell's slot, summed so that start_[k] is where cell k ends, then each
    // point placed just before its cell's end, which moves down, the last point first: start_[k]
    // is then where cell k begins, and each cell lists its points in index order.
    // Each point's cell (two divisions) worked out once, not once a pass.
    const size_t cells = static_cast<size_t>(columns_ * rows_);
    start_.assign(cells + 1, 0);
    std::vector<std::uint32_t> slots(points.size());
    for (size_t j = 0; j < points.size(); ++j) {
      slots[j] = static_cast<std::uint32_t>(slot(points[j]));
      ++start_[slots[j]];
    }
    for (size_t k = 1; k < cells; ++k) start_[k] += start_[k - 1];
    start_[cells] = static_cast<std::uint32_t>(points.size());
    indices_.resize(points.size());
    for (size_t j = points.size(); j-- > 0;)
      indices_[--start_[slots[j]]] = static_cast<std::uint32_t>(j);
  }

  // The most cells of a dense grid for this many points (else every lookup scans them all).
  static size_t max_cells(size_t points) { return 4 * points + 1024; }
  // A cell size of at least smallest_m for which the points' bounding box, grown by margin_m,
  // holds a dense grid (points spread far for their number need larger cells).
  static double dense_cell_m(const std::vector<Eigen::Vector2d>& points, double smallest_m,
                             double margin_m) {
    if (points.empty()) return smallest_m;
    Eigen::Vector2d lo = points.front(), hi = lo;
    for (const Eigen::Vector2d& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Eigen::Vector2d size = hi - lo;
    const double cells = static_cast<double>(max_cells(points.size()));
    return std::max(smallest_m,
                    1.1 * std::sqrt((size.x() + margin_m) * (size.y() + margin_m) / cells));
  }

  // What nearest_index returns where no point lies within the radius.
  static constexpr size_t kNone = std::numeric_limits<size_t>::max();

  // The index of the point nearest to p within radius_m (the lowest index among equals), if
  // any: the cells in rings of growing distance around p's, until the rings left lie farther
  // than the nearest found (with cells much smaller than the radius, few are looked at).
  std::optional<size_t> nearest(const std::vector<Eigen::Vector2d>& points,
                                const Eigen::Vector2d& p, double radius_m) const {
    const size_t j = nearest_index(points, p, radius_m);
    return j == kNone ? std::nullopt : std::optional<size_t>(j);
  }
  // The same, kNone for none (a std::optional returned in a loop's every pass went through
  // memory in two parts and was read back in one: a stall each time).
  size_t nearest_index(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p,
                       double radius_m) const {
    size_t found = kNone;
    double best = radius_m * radius_m;
    // Ties: the lower index (none found yet is kNone, above every index).
    auto consider = [&](size_t j) {
      const double d2 = (points[j] - p).squaredNorm();
      if (d2 > best || (d2 == best && j > found)) return;
      best = d2;
      found = j;
    };
    if (columns_ == 0) {
      for (size_t j : all_) consider(j);
      return found;
    }
    const auto [cx, cy] = cell(p);
    const long long x = cx - x0_, y = cy - y0_;
    const long long last_ring = static_cast<long long>(std::floor(radius_m / cell_m_)) + 1;
    // A cell of ring r lies at least (r - 1) cells from p.
    if (x < -last_ring || y < -last_ring || x >= columns_ + last_ring || y >= rows_ + last_ring)
      return found;
    for (long long r = 0; r <= last_ring; ++r) {
      const double clear_m = static_cast<double>(r - 1) * cell_m_;
      if (r >= 2 && found != kNone && best < clear_m * clear_m) break;
      for (long long i = x - r; i <= x + r; ++i) {
        if (i < 0 || i >= columns_) continue;
        const bool edge_column = i == x - r || i == x + r;
        for (long long k = y - r; k <= y + r; k += edge_column ? 1 : 2 * r) {
          if (k >= 0 && k < rows_) {
            const size_t slot = static_cast<size_t>(i * rows_ + k);
            for (size_t n = start_[slot]; n < start_[slot + 1]; ++n) consider(indices_[n]);
          }
          if (r == 0) break;
        }
      }
    }
    return found;
  }

  // f(index) for every point within cell_m of p (and some a little farther), cell by cell, in
  // index order within a cell.
  template <typename F>
  void for_each_near(const Eigen::Vector2d& p, F f) const {
    const auto [cx, cy] = cell(p);
    visit_cells(cx - 1, cx + 1, cy - 1, cy + 1, f);
  }
  // The same, only in the cells that overlap the box lo..hi (the points for_each_near would
  // give, in the same order, less those in cells wholly outside the box).
  template <typename F>
  void for_each_near_in_box(const Eigen::Vector2d& p, const Eigen::Vector2d& lo,
                            const Eigen::Vector2d& hi, F f) const {
    const auto [cx, cy] = cell(p);
    const auto [lo_x, lo_y] = cell(lo);
    const auto [hi_x, hi_y] = cell(hi);
    visit_cells(std::max(cx - 1, lo_x), std::min(cx + 1, hi_x), std::max(cy - 1, lo_y),
                std::min(cy + 1, hi_y), f);
  }

 private:
  // f(index) for the points of cells x_from..x_to, y_from..y_to (cell coordinates), column by
  // column, in index order within a cell; without a dense grid, for every point.
  template <typename F>
  void visit_cells(long long x_from, long long x_to, long long y_from, long long y_to, F f) const {
    if (columns_ == 0) {
      for (size_t j : all_) f(j);
      return;
    }
    for (long long x = std::max(x_from - x0_, 0LL); x <= std::min(x_to - x0_, columns_ - 1); ++x) {
      for (long long y = std::max(y_from - y0_, 0LL); y <= std::min(y_to - y0_, rows_ - 1); ++y) {
        const size_t k = static_cast<size_t>(x * rows_ + y);
        for (size_t i = start_[k]; i < start_[k + 1]; ++i) f(indices_[i]);
      }
    }
  }
  std::pair<long long, long long> cell(const Eigen::Vector2d& p) const {
    return {static_cast<long long>(std::floor(p.x() / cell_m_)),
            static_cast<long long>(std::floor(p.y() / cell_m_))};
  }
  size_t slot(const Eigen::Vector2d& p) const {
    const auto [cx, cy] = cell(p);
    return static_cast<size_t>((cx - x0_) * rows_ + (cy - y0_));
  }
  // More points than 32-bit indices can name get no dense grid.
  static constexpr size_t kNone32 = std::numeric_limits<std::uint32_t>::max();

  double cell_m_;
  long long x0_ = 0, y0_ = 0, columns_ = 0, rows_ = 0;
  std::vector<std::uint32_t> start_;  // the points of cell k: indices_[start_[k] .. start_[k + 1])
  std::vector<std::uint32_t> indices_;  // point indices, cell by cell
  std::vector<size_t> all_;      // without a dense grid: every point
};

}  // namespace agv::perception
