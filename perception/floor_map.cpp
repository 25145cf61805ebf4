#include "perception/floor_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/prefetch.h"
#include "common/recent_cache.h"

namespace agv::perception {

FloorMap::FloorMap(const CameraModel& camera) {
  const int w = camera.intrinsics().width_px, h = camera.intrinsics().height_px;
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<size_t>(w) * h);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) pixels.emplace_back(u, v);
  }
  std::vector<Eigen::Vector2d> floor;
  std::vector<bool> valid;
  camera.pixels_to_floor(pixels, &floor, &valid);

  const float nan = std::numeric_limits<float>::quiet_NaN();
  x_m_.create(h, w, CV_32F);
  y_m_.create(h, w, CV_32F);
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      x_m_.at<float>(v, u) = valid[i] ? static_cast<float>(floor[i].x()) : nan;
      y_m_.at<float>(v, u) = valid[i] ? static_cast<float>(floor[i].y()) : nan;
      if (valid[i]) {
        lo = lo.cwiseMin(floor[i]);
        hi = hi.cwiseMax(floor[i]);
      }
    }
  }
  cv::merge(std::vector<cv::Mat>{x_m_, y_m_}, xy_m_);
  view_centre_m_ = 0.5 * (lo + hi);
  view_radius_m_ = 0.5 * (hi - lo).norm();

  footprint_m_.create(h, w, CV_32F);
  std::vector<float> samples;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const int u0 = std::max(0, u - 1), u1 = std::min(w - 1, u + 1);
      const int v0 = std::max(0, v - 1), v1 = std::min(h - 1, v + 1);
      const double dxu = (x_m_.at<float>(v, u1) - x_m_.at<float>(v, u0)) / (u1 - u0);
      const double dyu = (y_m_.at<float>(v, u1) - y_m_.at<float>(v, u0)) / (u1 - u0);
      const double dxv = (x_m_.at<float>(v1, u) - x_m_.at<float>(v0, u)) / (v1 - v0);
      const double dyv = (y_m_.at<float>(v1, u) - y_m_.at<float>(v0, u)) / (v1 - v0);
      const float side = static_cast<float>(std::sqrt(std::abs(dxu * dyv - dyu * dxv)));
      footprint_m_.at<float>(v, u) = side;
      if (std::isfinite(side) && (u % 8 == 0) && (v % 8 == 0)) samples.push_back(side);
    }
  }
  if (!samples.empty()) {
    std::nth_element(samples.begin(), samples.begin() + samples.size() / 2, samples.end());
    typical_footprint_m_ = samples[samples.size() / 2];
  }
}

namespace {

// Everything a floor map depends on, as bytes: cameras with the same key have the same map.
std::string camera_key(const CameraModel& camera) {
  const CameraIntrinsics& in = camera.intrinsics();
  std::vector<double> numbers = {static_cast<double>(in.width_px),
                                 static_cast<double>(in.height_px), in.fisheye ? 1.0 : 0.0};
  for (int i = 0; i < 9; ++i) numbers.push_back(in.camera_matrix.val[i]);
  numbers.insert(numbers.end(), in.distortion.begin(), in.distortion.end());
  for (int i = 0; i < 3; ++i) numbers.push_back(camera.mount().xyz_m[i]);
  for (int i = 0; i < 3; ++i) numbers.push_back(camera.mount().rpy_rad[i]);
  return std::string(reinterpret_cast<const char*>(numbers.data()),
                     numbers.size() * sizeof(double));
}

}  // namespace

std::shared_ptr<const FloorMap> FloorMap::shared(const CameraModel& camera) {
  static RecentCache<std::string, std::shared_ptr<const FloorMap>> maps(8);
  return maps.get(camera_key(camera),
                  [&camera] { return std::make_shared<const FloorMap>(camera); });
}

std::optional<std::pair<int, int>> FloorMap::cell_of(double u_px, double v_px) const {
  if (!(u_px >= 0.0 && v_px >= 0.0 && u_px <= x_m_.cols - 1 && v_px <= x_m_.rows - 1)) {
    return std::nullopt;
  }
  return std::pair{std::min(static_cast<int>(u_px), x_m_.cols - 2),
                   std::min(static_cast<int>(v_px), x_m_.rows - 2)};
}

void FloorMap::prefetch(double u_px, double v_px) const {
  const auto cell = cell_of(u_px, v_px);
  if (!cell) return;
  const auto [u0, v0] = *cell;
  agv::prefetch(xy_m_.ptr<float>(v0) + 2 * u0);
  agv::prefetch(xy_m_.ptr<float>(v0 + 1) + 2 * u0);
}

std::optional<Eigen::Vector2d> FloorMap::at(double u_px, double v_px) const {
  const auto cell = cell_of(u_px, v_px);
  if (!cell) return std::nullopt;
  const auto [u0, v0] = *cell;
  const double fu = u_px - u0, fv = v_px - v0;
  // The four neighbours' x (channel 0) or y (channel 1), from the interleaved map: both in one
  // or two cache lines a row.
  const float* r0 = xy_m_.ptr<float>(v0) + 2 * u0;
  const float* r1 = xy_m_.ptr<float>(v0 + 1) + 2 * u0;
  auto bilinear = [&](int channel) {
    return (1 - fv) * ((1 - fu) * r0[channel] + fu * r0[2 + channel]) +
           fv * ((1 - fu) * r1[channel] + fu * r1[2 + channel]);
  };
  const Eigen::Vector2d p(bilinear(0), bilinear(1));
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return std::nullopt;
  return p;
}

}  // namespace agv::perception
