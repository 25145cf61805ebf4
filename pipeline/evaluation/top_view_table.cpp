#include "pipeline/evaluation/top_view_table.h"

#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace agv::pipeline {

void write_top_view_table(const std::string& file, const Pose2& pose,
                          const std::vector<Eigen::Vector2d>& remembered,
                          const perception::LineDetection& detection,
                          const std::vector<TapeStrip>& tapes) {
  std::ofstream out(file);
  out << "kind,x_m,y_m\n" << std::setprecision(7);
  auto row = [&](const char* kind, const Eigen::Vector2d& p) {
    if (p.norm() <= kTopViewReach_m) out << kind << ',' << p.x() << ',' << p.y() << '\n';
  };
  const Pose2 to_vehicle = pose.inverse();
  for (const TapeStrip& tape : tapes) {
    for (double s = 0.0; s <= tape.path.length_m(); s += 0.002)
      row("tape_laid", to_vehicle.transform(tape.path.point_at(s)));
  }
  for (const Eigen::Vector2d& p : remembered) row("remembered", p);
  for (size_t line = 0; line < detection.lines.size(); ++line) {
    const char* kind = static_cast<int>(line) == detection.followed ? "followed" : "other_line";
    for (int chord : detection.lines[line].chords) row(kind, detection.chords[chord].centre());
  }
  if (!out) throw std::runtime_error(file + ": cannot write");
}

}  // namespace agv::pipeline
