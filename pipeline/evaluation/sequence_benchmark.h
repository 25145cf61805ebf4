#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace agv::pipeline {

// The pieces a sequence's path is laid from.
enum class PathPiece { kLine, kArc, kSBend, kCorner, kFork };
PathPiece parse_path_piece(const std::string& word);  // line | arc | s-bend | corner | fork
const char* path_piece_name(PathPiece piece);

struct SequenceBenchmarkOptions {
  int sequences = 12;          // random paths with tape
  int empty_sequences = 2;     // drives over floors without tape (frames must give no line)
  double path_length_m = 3.0;  // driven per sequence
  // Drawn with equal chances after a 0.6 m lead-in line (a fork at most once a sequence).
  std::vector<PathPiece> pieces = {PathPiece::kLine, PathPiece::kArc, PathPiece::kSBend,
                                   PathPiece::kCorner, PathPiece::kFork};
  double speed_m_s = 0.3;
  double frame_rate_hz = 30.0;
  // Travel before the errors count: the camera sees 0.2-0.45 m ahead, and the vehicle must have
  // driven onto tape it saw before the path memory has it under the vehicle.
  double warm_up_m = 0.5;
  std::uint64_t seed = 1;
  int only_sequence = -1;  // >= 0: drive this one only (the draws of the others still made)
  // Where to write annotated frames that were lost or off by more than 1 mm / 0.5 deg after the
  // warm-up, or gave a line without tape ("": none); at most max_saved_per_sequence of each
  // sequence and max_saved in all.
  std::string save_failures_dir;
  int max_saved_per_sequence = 5;
  int max_saved = 60;
  // Frames save_first_frame to save_last_frame of each sequence driven are saved too, failed or
  // not, whatever the limits above (-1: none).
  int save_first_frame = -1, save_last_frame = -1;
};

// One frame of a sequence and what perception, as the loop runs it (tracking between full
// searches, the path memory placed with wheel odometry), made of it.
struct SequenceFrame {
  int sequence = 0;
  bool has_tape = true;
  std::string piece;  // what the vehicle drives over: line, arc, s-bend, corner, fork
  double travelled_m = 0.0;
  bool line_found = false;
  bool extrapolated = false;     // carried back from the view (no remembered tape under it)
  bool remembered_only = false;  // no tape in view: from the remembered tape alone
  double error_e_d_m = 0.0, error_e_theta_rad = 0.0;
  double measured_width_m = 0.0, true_width_m = 0.0;
  double perceive_ms = 0.0;
  std::string no_line_reason;
};

struct SequenceBenchmarkResult {
  std::vector<SequenceFrame> frames;
  std::vector<std::string> sequence_texts;  // each sequence's draw, for a reader
  nlohmann::json summary;
};

// Consecutive frames along random paths: lines joined to arcs (R 0.5-3 m), S-bends (two
// opposite arcs, R 0.6-1.5 m), corners (R 0.1-0.3 m, 45-135 deg) and one Y fork per sequence
// at most (the branch leaving by 30-60 deg; the way chosen left, right or straight so that the
// path driven is the one named), taped 10-100 mm wide with no width configured, under the
// random cameras, floors and light of the single-frame benchmark; the vehicle weaves about the
// path (up to 5 mm) at speed_m_s. Perception runs as the closed loop runs it. Counts a line
// followed the wrong way round (heading error beyond 90 deg) as a direction flip. Deterministic
// for the seed.
SequenceBenchmarkResult run_sequence_benchmark(const SequenceBenchmarkOptions& options,
                                               const std::function<void(double)>& progress = {});

}  // namespace agv::pipeline
