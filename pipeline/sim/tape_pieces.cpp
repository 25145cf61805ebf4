#include "pipeline/sim/tape_pieces.h"

#include <algorithm>
#include <numbers>

#include "common/angles.h"
#include "common/vector_clones.h"

namespace agv::pipeline {
namespace {

constexpr double kArcPieceMax_rad = std::numbers::pi / 2.0;
// Hermite pieces are drawn as arcs this long at most, each through the curve's points and
// tangent at its start: the drawn line strays less than a micrometre from the curve.
constexpr double kHermiteDrawStep_m = 0.01;

// The part [s0, s1] of a segment as a line or an arc (a Hermite part as the arc that leaves its
// start point along the curve's tangent and ends at its end point).
void shape_piece(const control::PathSegment& segment, double s0, double s1, WorldPiece* piece) {
  piece->start = segment.point_at(s0);
  piece->end = segment.point_at(s1);
  piece->heading_rad = segment.heading_at(s0);
  piece->length_m = s1 - s0;
  double curvature_1_m = segment.curvature_1_m;
  if (segment.hermite) {
    const Eigen::Vector2d chord = piece->end - piece->start;
    const double chord_heading = std::atan2(chord.y(), chord.x());
    const double half_turn_rad = wrap_angle_rad(chord_heading - piece->heading_rad);
    curvature_1_m = 2.0 * std::sin(half_turn_rad) / chord.norm();
    if (std::abs(curvature_1_m) <= 1e-9)
      piece->heading_rad = chord_heading;
    else
      piece->length_m = 2.0 * std::abs(half_turn_rad) / std::abs(curvature_1_m);
  }
  piece->is_arc = std::abs(curvature_1_m) > 1e-9;
  if (piece->is_arc) {
    piece->radius_m = 1.0 / std::abs(curvature_1_m);
    piece->turn_sign = curvature_1_m > 0.0 ? 1.0 : -1.0;
    const double h = piece->heading_rad;
    piece->centre = piece->start +
                    piece->turn_sign * piece->radius_m * Eigen::Vector2d(-std::sin(h), std::cos(h));
  }
}

}  // namespace

std::vector<WorldPiece> tape_pieces(const std::vector<TapeStrip>& tapes) {
  std::vector<WorldPiece> pieces;
  for (int strip = 0; strip < static_cast<int>(tapes.size()); ++strip) {
    const TapeStrip& tape = tapes[strip];
    const auto& segments = tape.path.segments();
    // Where there is tape along the path: [0, length] less the gaps.
    std::vector<std::pair<double, double>> laid{{0.0, tape.path.length_m()}};
    for (const auto& [gap_from, gap_to] : tape.gaps_m) {
      std::vector<std::pair<double, double>> next;
      for (const auto& [from, to] : laid) {
        if (gap_to <= from || gap_from >= to) {
          next.emplace_back(from, to);
          continue;
        }
        if (gap_from > from) next.emplace_back(from, gap_from);
        if (gap_to < to) next.emplace_back(gap_to, to);
      }
      laid = next;
    }
    double segment_start_s = 0.0;
    for (const control::PathSegment& segment : segments) {
      const double segment_end_s = segment_start_s + segment.length_m;
      for (const auto& [from, to] : laid) {
        const double a = std::max(from, segment_start_s), b = std::min(to, segment_end_s);
        if (b - a <= 1e-9) continue;
        const double sweep_rad = std::abs(segment.curvature_1_m) * (b - a);
        const int parts =
            segment.hermite
                ? static_cast<int>(std::ceil((b - a) / kHermiteDrawStep_m))
                : std::max(1, static_cast<int>(std::ceil(sweep_rad / kArcPieceMax_rad)));
        for (int p = 0; p < parts; ++p) {
          const double s0 = a - segment_start_s + (b - a) * p / parts;
          const double s1 = a - segment_start_s + (b - a) * (p + 1) / parts;
          WorldPiece piece;
          piece.strip = strip;
          shape_piece(segment, s0, s1, &piece);
          // Cut square where the tape starts, ends or is interrupted; rounded at joints.
          piece.flat_start = p == 0 && std::abs(a - from) < 1e-9;
          piece.flat_end = p == parts - 1 && std::abs(b - to) < 1e-9;
          piece.bound_centre = 0.5 * (piece.start + piece.end);
          piece.bound_radius_m = 0.5 * piece.length_m + 1e-6;
          pieces.push_back(piece);
        }
      }
      segment_start_s = segment_end_s;
    }
  }
  return pieces;
}

LocalPiece to_local(const WorldPiece& w, const Pose2& vehicle_inverse) {
  LocalPiece l{};
  l.strip = w.strip;
  l.is_arc = w.is_arc;
  const Eigen::Vector2d a = vehicle_inverse.transform(w.start);
  const Eigen::Vector2d b = vehicle_inverse.transform(w.end);
  l.ax = static_cast<float>(a.x());
  l.ay = static_cast<float>(a.y());
  l.bx = static_cast<float>(b.x());
  l.by = static_cast<float>(b.y());
  l.flat_start = w.flat_start;
  l.flat_end = w.flat_end;
  if (!w.is_arc) {
    const Eigen::Vector2d t =
        vehicle_inverse.rotate({std::cos(w.heading_rad), std::sin(w.heading_rad)});
    l.tx = static_cast<float>(t.x());
    l.ty = static_cast<float>(t.y());
    l.length = static_cast<float>(w.length_m);
  } else {
    const Eigen::Vector2d c = vehicle_inverse.transform(w.centre);
    l.cx = static_cast<float>(c.x());
    l.cy = static_cast<float>(c.y());
    l.radius = static_cast<float>(w.radius_m);
    const Eigen::Vector2d r0 = (a - c) / w.radius_m, r1 = (b - c) / w.radius_m;
    l.r0x = static_cast<float>(r0.x());
    l.r0y = static_cast<float>(r0.y());
    l.r1x = static_cast<float>(r1.x());
    l.r1y = static_cast<float>(r1.y());
    l.turn_sign = static_cast<float>(w.turn_sign);
  }
  return l;
}

AGV_VECTOR_CLONES
void piece_distances(const LocalPiece& piece, const float* xs, const float* ys, int count,
                     float* distance, bool cuts) {
  constexpr float kFar = 1e30f;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  // Past a flat end the tape is cut: positions along the piece outside [cut_before, cut_after].
  const float cut_before = cuts && piece.flat_start ? 0.0f : -kInf;
  if (!piece.is_arc) {
    const float cut_after = cuts && piece.flat_end ? piece.length : kInf;
    // Locals, so that the compiler knows that writing `distance` cannot change them.
    const float ax = piece.ax, ay = piece.ay, tx = piece.tx, ty = piece.ty, length = piece.length;
    for (int u = 0; u < count; ++u) {
      const float dx = xs[u] - ax, dy = ys[u] - ay;
      const float along = dx * tx + dy * ty;
      const float clamped = std::min(std::max(along, 0.0f), length);
      const float ex = dx - clamped * tx, ey = dy - clamped * ty;
      const float d = std::sqrt(ex * ex + ey * ey);
      distance[u] = ((along < cut_before) | (along > cut_after)) ? kFar : d;
    }
    return;
  }
  const float start_weight = cuts && piece.flat_start ? kFar : 0.0f;
  const float end_weight = cuts && piece.flat_end ? kFar : 0.0f;
  const float cx = piece.cx, cy = piece.cy, radius = piece.radius, sign = piece.turn_sign;
  const float r0x = piece.r0x, r0y = piece.r0y, r1x = piece.r1x, r1y = piece.r1y;
  const float ax = piece.ax, ay = piece.ay, bx = piece.bx, by = piece.by;
  for (int u = 0; u < count; ++u) {
    const float qx = xs[u] - cx, qy = ys[u] - cy;
    const float after_start = sign * (r0x * qy - r0y * qx);
    const float before_end = sign * (qx * r1y - qy * r1x);
    const float on_arc = std::abs(std::sqrt(qx * qx + qy * qy) - radius);
    const float sx = xs[u] - ax, sy = ys[u] - ay;
    const float ex = xs[u] - bx, ey = ys[u] - by;
    const float to_start = std::sqrt(sx * sx + sy * sy) + start_weight;
    const float to_end = std::sqrt(ex * ex + ey * ey) + end_weight;
    distance[u] =
        ((after_start >= 0.0f) & (before_end >= 0.0f)) ? on_arc : std::min(to_start, to_end);
  }
}

}  // namespace agv::pipeline
