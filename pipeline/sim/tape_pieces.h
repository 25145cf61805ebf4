#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

#include "common/pose2.h"
#include "pipeline/sim/scene.h"

namespace agv::pipeline {

// A straight or circular piece of one tape strip, in the world.
struct WorldPiece {
  int strip = 0;
  bool is_arc = false;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;  // lines: direction
  double length_m = 0.0;
  double radius_m = 0.0;
  double turn_sign = 1.0;   // arcs: +1 counter-clockwise (left turn)
  bool flat_start = false;  // the strip starts here: cut square, not rounded
  bool flat_end = false;
  Eigen::Vector2d bound_centre = Eigen::Vector2d::Zero();
  double bound_radius_m = 0.0;
};

// The same piece in the vehicle frame of one sub-exposure pose, in floats for the pixel loop.
struct LocalPiece {
  int strip;
  bool is_arc;
  float ax, ay, bx, by;      // start and end points
  float tx, ty, length;      // lines: unit direction and length
  float cx, cy, radius;      // arcs: centre and radius
  float r0x, r0y, r1x, r1y;  // arcs: unit radials to start and end
  float turn_sign;
  bool flat_start, flat_end;
};

// The tape strips cut into pieces: lines, and arcs of at most 90 degrees (so that a point's
// position along an arc is decided by two cross products), leaving out the strips' gaps. Flat
// ends where a strip starts, ends or is interrupted; rounded joints between its pieces.
std::vector<WorldPiece> tape_pieces(const std::vector<TapeStrip>& tapes);

// Distance from each of `count` floor points (vehicle frame) to a piece's centre line; a very
// large value past a flat end (with `cuts`; without, the distance to the centre line's piece
// itself: never more than with them, and 1-Lipschitz in the point, which bounds it between
// points). Branch-free loops that the compiler can vectorise.
void piece_distances(const LocalPiece& piece, const float* xs, const float* ys, int count,
                     float* distance, bool cuts = true);

// A piece seen from a vehicle pose (pass the inverse of the vehicle's pose in the world).
LocalPiece to_local(const WorldPiece& piece, const Pose2& vehicle_inverse);

}  // namespace agv::pipeline
