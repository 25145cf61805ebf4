#include "perception/hough_baseline.h"

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace agv::perception {
namespace {

struct FloorSegment {
  Eigen::Vector2d a, b;
  double length_m() const { return (b - a).norm(); }
};

// Angle between two undirected directions, in [0, pi/2].
double undirected_angle_rad(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  const double c = std::abs(u.normalized().dot(v.normalized()));
  return std::acos(std::min(1.0, c));
}

}  // namespace

LineMeasurement HoughBaseline::estimate(const cv::Mat& frame_bgr, double stamp_s) const {
  LineMeasurement m;
  m.stamp_s = stamp_s;
  if (frame_bgr.empty()) return m;
  cv::Mat grey, blurred, edges;
  if (frame_bgr.channels() == 3) {
    cv::cvtColor(frame_bgr, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = frame_bgr;
  }
  cv::GaussianBlur(grey, blurred, cv::Size(5, 5), 1.5);
  cv::Canny(blurred, edges, 50, 150);
  std::vector<cv::Vec4i> lines;
  cv::HoughLinesP(edges, lines, 1.0, CV_PI / 180.0, 50, 50, 10);

  std::vector<FloorSegment> segments;
  for (const cv::Vec4i& l : lines) {
    const auto a = camera_.pixel_to_floor(cv::Point2d(l[0], l[1]));
    const auto b = camera_.pixel_to_floor(cv::Point2d(l[2], l[3]));
    if (a && b && (*b - *a).norm() > 1e-6) segments.push_back({*a, *b});
  }
  if (segments.empty()) return m;
  const FloorSegment& longest = *std::max_element(
      segments.begin(), segments.end(),
      [](const FloorSegment& x, const FloorSegment& y) { return x.length_m() < y.length_m(); });
  const Eigen::Vector2d direction = longest.b - longest.a;

  // Direction: the sum of the segments that agree with the longest, each turned to point the
  // same way (a length-weighted mean direction). Not a fit through their end points: the tape's
  // two edges are parallel but seen over different stretches, and one line through both leans
  // by their offset (1.2 deg and 5.9 mm at the vehicle on a centred straight 25 mm tape).
  std::vector<const FloorSegment*> agreeing;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const FloorSegment& s : segments) {
    if (undirected_angle_rad(s.b - s.a, direction) > 10.0 * CV_PI / 180.0) continue;
    agreeing.push_back(&s);
    sum +=
        (s.b - s.a).dot(direction) >= 0.0 ? Eigen::Vector2d(s.b - s.a) : Eigen::Vector2d(s.a - s.b);
  }
  Eigen::Vector2d tangent = sum.normalized();
  if (tangent.x() < 0.0) tangent = -tangent;  // the line runs forward (+x of V)
  const Eigen::Vector2d normal(-tangent.y(), tangent.x());

  // Centre: midway between the outermost segments within 1.5 tape widths of the longest one;
  // with only one edge seen the centre is unknown.
  const double longest_offset_m = (0.5 * (longest.a + longest.b)).dot(normal);
  double lo = longest_offset_m, hi = longest_offset_m;
  for (const FloorSegment* s : agreeing) {
    const double offset_m = (0.5 * (s->a + s->b)).dot(normal);
    if (std::abs(offset_m - longest_offset_m) > 1.5 * tape_width_m_) continue;
    lo = std::min(lo, offset_m);
    hi = std::max(hi, offset_m);
  }
  if (hi - lo < 0.5 * tape_width_m_) return m;
  const double centre_offset_m = 0.5 * (lo + hi);
  m.line_found = true;
  m.e_theta_rad = -std::atan2(tangent.y(), tangent.x());
  m.e_d_m = -centre_offset_m;  // the origin's signed distance, positive on the line's left
  m.points_used = static_cast<int>(2 * agreeing.size());
  m.tape_width_m = hi - lo;
  m.lines_seen = 1;
  m.confidence = 1.0;
  return m;
}

}  // namespace agv::perception
