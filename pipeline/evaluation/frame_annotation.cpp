#include "pipeline/evaluation/frame_annotation.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "common/angles.h"

namespace agv::pipeline {
namespace {

const cv::Scalar kEdge(0, 255, 255), kLine(255, 0, 255), kFollowed(0, 255, 0), kBranch(0, 128, 255);

// Draws a curve between arc positions s0 and s1 as a polyline in the image.
void draw_curve(cv::Mat& image, const perception::CameraModel& camera,
                const perception::CurveModel& model, double s0, double s1, const cv::Scalar& colour,
                int thickness) {
  std::vector<cv::Point> polyline;
  const int steps = 40;
  for (int i = 0; i <= steps; ++i) {
    const auto pixel = camera.floor_to_pixel(model.point_at(s0 + (s1 - s0) * i / steps));
    if (!pixel || std::abs(pixel->x) > 1e5 || std::abs(pixel->y) > 1e5) continue;
    polyline.emplace_back(cvRound(pixel->x), cvRound(pixel->y));
  }
  if (polyline.size() >= 2) cv::polylines(image, polyline, false, colour, thickness, cv::LINE_AA);
}

void put_text(cv::Mat& image, const std::string& text, cv::Point at, double scale = 0.5) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 3,
              cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
}

}  // namespace

cv::Mat annotate_frame(const cv::Mat& frame, const perception::CameraModel& camera,
                       const perception::LineDetection& detection, const LineMeasurement& m,
                       const std::string& caption) {
  cv::Mat image;
  if (frame.channels() == 1) {
    cv::cvtColor(frame, image, cv::COLOR_GRAY2BGR);
  } else {
    image = frame.clone();
  }
  for (const perception::EdgePair& edge : detection.edges) {
    cv::circle(image, edge.first_px, 1, kEdge, -1);
    cv::circle(image, edge.second_px, 1, kEdge, -1);
  }
  for (size_t i = 0; i < detection.lines.size(); ++i) {
    const perception::DetectedLine& line = detection.lines[i];
    const bool followed = static_cast<int>(i) == detection.followed;
    draw_curve(image, camera, line.model, line.s_min_m, line.s_max_m, followed ? kFollowed : kLine,
               followed ? 3 : 1);
  }
  if (detection.junction) {
    const auto centre = camera.floor_to_pixel(detection.junction->point_m);
    for (const perception::Branch& branch : detection.junction->branches) {
      const Eigen::Vector2d tip =
          detection.junction->point_m +
          0.6 * branch.length_m *
              Eigen::Vector2d(std::cos(branch.heading_rad), std::sin(branch.heading_rad));
      const auto tip_px = camera.floor_to_pixel(tip);
      if (centre && tip_px) {
        cv::arrowedLine(image, cv::Point(cvRound(centre->x), cvRound(centre->y)),
                        cv::Point(cvRound(tip_px->x), cvRound(tip_px->y)), kBranch, 2, cv::LINE_AA,
                        0, 0.15);
      }
    }
    if (centre)
      cv::circle(image, cv::Point(cvRound(centre->x), cvRound(centre->y)), 6, kBranch, 2,
                 cv::LINE_AA);
  }
  put_text(image, caption, {8, 20});
  char text[160];
  if (m.line_found) {
    std::snprintf(text, sizeof(text),
                  "e_d %+.2f mm  e_theta %+.2f deg  curv %+.2f 1/m  conf %.2f  lines %d%s",
                  1e3 * m.e_d_m, rad_to_deg(m.e_theta_rad), m.curvature_1_m, m.confidence,
                  m.lines_seen, m.junction_ahead ? "  junction" : "");
  } else {
    std::snprintf(text, sizeof(text), "NO LINE: %s", detection.rejected_because.c_str());
  }
  put_text(image, text, {8, image.rows - 10});
  return image;
}

}  // namespace agv::pipeline
