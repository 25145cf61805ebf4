#include "perception/nearest_piece.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "perception/joined_arcs_fit.h"

namespace agv::perception {

std::optional<CurveModel> nearest_piece(const std::vector<Chord>& chords, const DetectedLine& line,
                                        const CurveModel& model) {
  JoinedArcsOptions options;
  options.both_sides = false;
  options.min_piece_m = 0.04;
  if (line.clean_chords.empty()) return std::nullopt;
  const CurveModel::Prepared prepared = model.prepared();  // its trigonometry once
  double s_near = prepared.arc_position(chords[line.clean_chords.front()].centre());
  for (int index : line.clean_chords) {
    const double s = prepared.arc_position(chords[index].centre());
    if (std::abs(s) < std::abs(s_near)) s_near = s;
  }
  const Eigen::Vector2d t = model.tangent_at(s_near);
  double frame_rad = std::atan2(t.y(), t.x());
  for (int pass = 0; pass < 3; ++pass) {
    const double c = std::cos(frame_rad), s = std::sin(frame_rad);
    std::vector<Eigen::Vector2d> local;
    for (int index : line.clean_chords) {
      const Eigen::Vector2d p = chords[index].centre();
      local.emplace_back(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
    }
    const std::optional<JoinedArcs> fit = fit_joined_arcs(local, options);
    if (!fit || !fit->break_x_m) return std::nullopt;
    if (std::abs(fit->slope) < 0.02 || pass == 2) {
      if (fit->rms_m > line.residual_rms_m / 3.0) return std::nullopt;
      // The near piece's own points (the joined fit's first piece is bent by its joint with the
      // second): a line or a parabola y = a + b x (+ c x^2), least squares.
      double offset = fit->offset_m, slope = fit->slope, curvature = fit->curvature_1_m;
      Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
      Eigen::Vector3d aty = Eigen::Vector3d::Zero();
      double yy = 0.0;
      int n = 0;
      for (const Eigen::Vector2d& p : local) {
        if (p.x() >= *fit->break_x_m) continue;
        const Eigen::Vector3d row(1.0, p.x(), p.x() * p.x());
        ata += row * row.transpose();
        aty += row * p.y();
        yy += p.y() * p.y();
        ++n;
      }
      if (n >= 6) {
        const Eigen::Vector2d straight = ata.topLeftCorner<2, 2>().ldlt().solve(aty.head<2>());
        const Eigen::Vector3d bent = ata.ldlt().solve(aty);
        const double rss_straight = std::max(1e-18, yy - straight.dot(aty.head<2>()));
        const double rss_bent = std::max(1e-18, yy - bent.dot(aty));
        const bool line = n * std::log(rss_straight / rss_bent) < std::log(static_cast<double>(n));
        offset = line ? straight[0] : bent[0];
        slope = line ? straight[1] : bent[1];
        curvature = line ? 0.0 : 2.0 * bent[2];
      }
      const CurveModel piece = curve_in_frame(frame_rad, offset, slope, curvature);
      // A piece of the line runs its way where the evidence comes nearest. A fit that read a
      // chord along the tape (at a junction) among chords across it turned further each pass
      // and may end reversed (agv evaluate seed 7, sequence 3, at a fork: slopes 1.6, 11 and
      // 5.8 in the three passes, the line reported 180 deg off).
      if (piece.tangent_at(piece.arc_position(model.point_at(s_near))).dot(t) <= 0.0)
        return std::nullopt;
      return piece;
    }
    frame_rad += std::atan(fit->slope);
  }
  return std::nullopt;
}

}  // namespace agv::perception
