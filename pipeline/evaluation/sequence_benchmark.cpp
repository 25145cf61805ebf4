#include "pipeline/evaluation/sequence_benchmark.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/angles.h"
#include "common/statistics.h"
#include "perception/junction.h"
#include "pipeline/evaluation/frame_annotation.h"
#include "pipeline/evaluation/random_conditions.h"
#include "pipeline/evaluation/top_view_table.h"
#include "pipeline/perceiver.h"
#include "pipeline/sim/frame_renderer.h"
#include "pipeline/sim/wheel_odometry.h"

namespace agv::pipeline {
namespace {

// A path laid piece by piece, with where each piece starts, and a fork's branch if drawn.
struct PiecedPath {
  control::Path path;
  std::vector<std::pair<double, std::string>> pieces;  // (start arc length, kind)
  std::optional<control::Path> branch;
  perception::BranchChoice choice = perception::BranchChoice::kStraight;
  std::string text;
};

double either_way(cv::RNG& rng) { return rng.uniform(0.0, 1.0) < 0.5 ? 1.0 : -1.0; }

// Random pieces from a 0.6 m lead-in until the path reaches length_m and 1 m beyond (the tape the
// camera sees ahead of the last frame).
PiecedPath draw_path(cv::RNG& rng, double length_m, const std::vector<PathPiece>& allowed) {
  PiecedPath p;
  p.path = control::Path::starting_at({0.0, 0.0, 0.0}).add_line(0.6);
  p.pieces.push_back({0.0, path_piece_name(PathPiece::kLine)});
  p.text = path_piece_name(PathPiece::kLine);
  while (p.path.length_m() < length_m + 1.0) {
    const double start_m = p.path.length_m();
    PathPiece kind =
        allowed[static_cast<std::size_t>(rng.uniform(0, static_cast<int>(allowed.size())))];
    if (kind == PathPiece::kFork && p.branch) kind = PathPiece::kLine;  // the choice is per run
    char text[96];
    if (kind == PathPiece::kLine) {
      const double l = rng.uniform(0.2, 0.8);
      p.path.add_line(l);
      p.pieces.push_back({start_m, path_piece_name(PathPiece::kLine)});
      std::snprintf(text, sizeof(text), " line %.2f", l);
    } else if (kind == PathPiece::kArc) {
      const double r = std::exp(rng.uniform(std::log(0.5), std::log(3.0)));
      const double angle = either_way(rng) * deg_to_rad(rng.uniform(20.0, 90.0));
      p.path.add_arc(r, angle);
      p.pieces.push_back({start_m, path_piece_name(PathPiece::kArc)});
      std::snprintf(text, sizeof(text), " arc R%.2f %+.0fdeg", r, rad_to_deg(angle));
    } else if (kind == PathPiece::kSBend) {
      const double r = rng.uniform(0.6, 1.5);
      const double angle = either_way(rng) * deg_to_rad(rng.uniform(20.0, 45.0));
      p.path.add_arc(r, angle).add_arc(r, -angle);
      p.pieces.push_back({start_m, path_piece_name(PathPiece::kSBend)});
      std::snprintf(text, sizeof(text), " s-bend R%.2f %+.0fdeg", r, rad_to_deg(angle));
    } else if (kind == PathPiece::kCorner) {
      const double r = rng.uniform(0.1, 0.3);
      const double angle = either_way(rng) * deg_to_rad(rng.uniform(45.0, 135.0));
      p.path.add_arc(r, angle);
      p.pieces.push_back({start_m, path_piece_name(PathPiece::kCorner)});
      p.path.add_line(0.3);
      p.pieces.push_back({p.path.length_m() - 0.3, path_piece_name(PathPiece::kLine)});
      std::snprintf(text, sizeof(text), " corner R%.2f %+.0fdeg", r, rad_to_deg(angle));
    } else {
      // The path goes on straight; a branch leaves it tangentially on an arc, to one side. The
      // way driven is the straight one: the rightmost of the two when the branch turns left.
      const Pose2 at = p.path.end_pose();
      const double side = either_way(rng);
      const double r = rng.uniform(0.4, 1.0), angle = deg_to_rad(rng.uniform(30.0, 60.0));
      p.branch = control::Path::starting_at(at).add_arc(r, side * angle).add_line(0.5);
      const bool straight = rng.uniform(0.0, 1.0) < 0.5;
      p.choice = straight   ? perception::BranchChoice::kStraight
                 : side > 0 ? perception::BranchChoice::kRight
                            : perception::BranchChoice::kLeft;
      p.path.add_line(0.8);
      p.pieces.push_back({start_m, path_piece_name(PathPiece::kFork)});
      std::snprintf(text, sizeof(text), " fork(branch %s R%.2f %.0fdeg, take %s)",
                    side > 0 ? "left" : "right", r, rad_to_deg(angle),
                    perception::branch_choice_name(p.choice));
    }
    p.text += text;
  }
  return p;
}

const std::string& piece_at(const PiecedPath& p, double s_m) {
  std::size_t i = 0;
  while (i + 1 < p.pieces.size() && p.pieces[i + 1].first <= s_m) ++i;
  return p.pieces[i].second;
}

// The vehicle's pose at arc length s: weaving about the path by amplitude_m over wavelength_m.
Pose2 weaving_pose(const control::Path& path, double s_m, double amplitude_m, double wavelength_m,
                   double phase_rad) {
  const double k = 2.0 * kPi / wavelength_m;
  const double e_d = amplitude_m * std::sin(k * s_m + phase_rad);
  const double slope = amplitude_m * k * std::cos(k * s_m + phase_rad);
  const double heading = path.heading_at(s_m);
  const Eigen::Vector2d p =
      path.point_at(s_m) + e_d * Eigen::Vector2d(-std::sin(heading), std::cos(heading));
  return {p.x(), p.y(), wrap_angle_rad(heading + std::atan(slope))};
}

// A frame lost or off by more than 1 mm / 0.5 deg once the memory is warm, or a line without tape.
bool failed(const SequenceFrame& f, const SequenceBenchmarkOptions& options) {
  if (!f.has_tape) return f.line_found;
  return f.travelled_m >= options.warm_up_m && (!f.line_found || std::abs(f.error_e_d_m) > 0.001 ||
                                                std::abs(f.error_e_theta_rad) > deg_to_rad(0.5));
}

// One sequence: a drawn camera, floor, light, tape and path, driven frame by frame.
void run_sequence(cv::RNG& rng, const SequenceBenchmarkOptions& options, int index, bool with_tape,
                  SequenceBenchmarkResult* result, int* saved) {
  const RandomCamera camera = draw_camera(rng);
  Scene scene;
  scene.seed = options.seed * 1000 + 500 + index;
  const bool light_floor = draw_floor_and_light(rng, &scene);
  TapeStrip tape;
  tape.width_m = std::exp(rng.uniform(std::log(0.010), std::log(0.100)));
  tape.color_bgr = draw_tape_colour(rng, scene.floor.color_bgr);
  tape.wear = rng.uniform(0.0, 1.0) < 0.2 ? rng.uniform(0.0, 0.1) : 0.0;
  const PiecedPath drawn =
      with_tape ? draw_path(rng, options.path_length_m, options.pieces) : PiecedPath{};
  perception::LineEstimator::Options perception;
  perception.tape.width_m = 0.0;  // not configured: measured
  if (rng.uniform(0.0, 1.0) < 0.5) perception.tape.color_bgr = tape.color_bgr;
  perception.branch = drawn.choice;
  const double amplitude_m = rng.uniform(0.0, 0.005), wavelength_m = rng.uniform(0.8, 1.6);
  const double phase_rad = rng.uniform(-kPi, kPi);

  // Without tape the vehicle drives a straight 1 m far from the only tape.
  const double length_m = with_tape ? options.path_length_m : 1.0;
  const control::Path driven =
      with_tape ? drawn.path : control::Path::starting_at({0.0, 0.0, 0.0}).add_line(2.0);
  tape.path =
      with_tape ? drawn.path : control::Path::starting_at({100.0, 100.0, 0.0}).add_line(1.0);
  scene.tapes.push_back(tape);
  if (drawn.branch) {
    TapeStrip branch = tape;
    branch.path = *drawn.branch;
    scene.tapes.push_back(branch);
  }
  char text[512];
  std::snprintf(
      text, sizeof(text), "h%.2f tilt%.1f width%.0fmm %s%s | %s", camera.height_m,
      rad_to_deg(camera.tilt_rad), 1e3 * tape.width_m, light_floor ? "light-floor" : "dark-floor",
      perception.tape.color_bgr ? " hint" : "", with_tape ? drawn.text.c_str() : "no tape");
  result->sequence_texts.push_back(text);
  if (options.only_sequence >= 0 && index != options.only_sequence) return;

  const FrameRenderer renderer(camera.camera, scene);
  ImagePerceiver perceiver(camera.camera, perception, /*path_memory=*/true);
  WheelOdometry odometry({0.005, 0.0035, 0.0002, 0.0005}, scene.seed);
  const double step_m = options.speed_m_s / options.frame_rate_hz;
  const int frames = static_cast<int>(length_m / step_m);
  int saved_here = 0;
  for (int f = 0; f < frames; ++f) {
    const double s = step_m * f;
    const Pose2 pose = weaving_pose(driven, s, amplitude_m, wavelength_m, phase_rad);
    SourceFrame frame;
    frame.index = static_cast<std::uint64_t>(f);
    frame.t_s = f / options.frame_rate_hz;
    frame.twist = {options.speed_m_s, 0.0, options.speed_m_s * driven.curvature_at(s)};
    frame.image = renderer.render(pose, frame.twist, frame.index);
    frame.odometry = odometry.update(pose);
    perception::LineDetection detection;
    const auto t0 = std::chrono::steady_clock::now();
    const LineMeasurement m = perceiver.measure(frame, &detection);
    SequenceFrame r;
    r.perceive_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    r.sequence = index;
    r.has_tape = with_tape;
    r.piece = with_tape ? piece_at(drawn, s) : "none";
    r.travelled_m = s;
    r.line_found = m.line_found;
    r.extrapolated = m.extrapolated;
    r.remembered_only = m.remembered_only;
    r.measured_width_m = m.tape_width_m;
    r.true_width_m = tape.width_m;
    if (!m.line_found) r.no_line_reason = detection.rejected_because;
    if (with_tape && m.line_found) {
      const control::TrackingError truth =
          driven.tracking_error(pose, driven.project(pose.translation(), s, 0.1));
      r.error_e_d_m = m.e_d_m - truth.e_d_m;
      r.error_e_theta_rad = wrap_angle_rad(m.e_theta_rad - truth.e_theta_rad);
    }
    // The frames asked for are saved beside the failures, not counted against their limits.
    const bool asked = f >= options.save_first_frame && f <= options.save_last_frame;
    const bool failure_kept = failed(r, options) && saved_here < options.max_saved_per_sequence &&
                              *saved < options.max_saved;
    if ((asked || failure_kept) && !options.save_failures_dir.empty()) {
      char name[96], caption[160];
      std::snprintf(name, sizeof(name), "/sequence%03d_frame%03d.png", index, f);
      std::snprintf(caption, sizeof(caption), "seq %d f %d %s %.2f m error %.2f mm %.2f deg", index,
                    f, r.piece.c_str(), s, 1e3 * r.error_e_d_m, rad_to_deg(r.error_e_theta_rad));
      cv::imwrite(options.save_failures_dir + name,
                  annotate_frame(frame.image, camera.camera, detection, m, caption));
      std::snprintf(name, sizeof(name), "/sequence%03d_frame%03d_top.csv", index, f);
      write_top_view_table(options.save_failures_dir + name, pose, perceiver.remembered_tape(),
                           detection, scene.tapes);
      if (!asked) {
        ++saved_here;
        ++*saved;
      }
    }
    result->frames.push_back(std::move(r));
  }
}

nlohmann::json error_figures(const std::vector<double>& d, const std::vector<double>& t) {
  std::vector<double> abs_d, abs_t;
  for (double x : d) abs_d.push_back(std::abs(x));
  for (double x : t) abs_t.push_back(std::abs(x));
  return {{"frames", d.size()},
          {"rms_e_d_m", rms(d)},
          {"rms_e_theta_rad", rms(t)},
          {"p95_abs_e_d_m", percentile(abs_d, 0.95)},
          {"p95_abs_e_theta_rad", percentile(abs_t, 0.95)},
          {"max_abs_e_d_m", percentile(abs_d, 1.0)},
          {"max_abs_e_theta_rad", percentile(abs_t, 1.0)}};
}

// The figures of summary.json's "sequences".
nlohmann::json summarise(const SequenceBenchmarkResult& result,
                         const SequenceBenchmarkOptions& options) {
  int tape_frames = 0, found = 0, empty = 0, false_lines = 0, flips = 0, extrapolated = 0;
  int remembered_only = 0;
  std::vector<double> d, t, times, width_errors;
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> by_piece;
  std::map<std::string, int> reasons;
  for (const SequenceFrame& f : result.frames) {
    times.push_back(f.perceive_ms);
    if (!f.has_tape) {
      ++empty;
      false_lines += f.line_found ? 1 : 0;
      continue;
    }
    ++tape_frames;
    if (!f.line_found) {
      ++reasons[f.no_line_reason.empty() ? "no line" : f.no_line_reason];
      continue;
    }
    ++found;
    if (std::abs(f.error_e_theta_rad) > kPi / 2) ++flips;
    if (f.travelled_m < options.warm_up_m) continue;
    extrapolated += f.extrapolated ? 1 : 0;
    remembered_only += f.remembered_only ? 1 : 0;
    d.push_back(f.error_e_d_m);
    t.push_back(f.error_e_theta_rad);
    by_piece[f.piece].first.push_back(f.error_e_d_m);
    by_piece[f.piece].second.push_back(f.error_e_theta_rad);
    width_errors.push_back(std::abs(f.measured_width_m - f.true_width_m) / f.true_width_m);
  }
  nlohmann::json j;
  j["seed"] = options.seed;
  j["sequences"] = options.only_sequence >= 0 ? 1 : options.sequences;
  j["frames_with_tape"] = tape_frames;
  j["found_fraction"] = tape_frames ? static_cast<double>(found) / tape_frames : 0.0;
  j["warm_up_m"] = options.warm_up_m;
  j["after_warm_up"] = error_figures(d, t);
  j["after_warm_up"]["frames_extrapolated"] = extrapolated;
  j["after_warm_up"]["frames_remembered_only"] = remembered_only;
  j["after_warm_up"]["width_error_median"] = percentile(width_errors, 0.5);
  j["by_piece"] = nlohmann::json::object();  // empty when no frame was found after the warm-up
  for (const auto& [piece, errors] : by_piece)
    j["by_piece"][piece] = error_figures(errors.first, errors.second);
  j["direction_flips"] = flips;
  j["frames_without_tape"] = empty;
  j["lines_reported_without_tape"] = false_lines;
  j["no_line_reasons"] = reasons;
  j["perceive_ms_median"] = percentile(times, 0.5);
  j["perceive_ms_p99"] = percentile(times, 0.99);
  return j;
}

}  // namespace

PathPiece parse_path_piece(const std::string& word) {
  for (PathPiece piece : {PathPiece::kLine, PathPiece::kArc, PathPiece::kSBend, PathPiece::kCorner,
                          PathPiece::kFork}) {
    if (word == path_piece_name(piece)) return piece;
  }
  throw std::invalid_argument("unknown path piece '" + word +
                              "' (line, arc, s-bend, corner or fork)");
}

const char* path_piece_name(PathPiece piece) {
  switch (piece) {
    case PathPiece::kLine:
      return "line";
    case PathPiece::kArc:
      return "arc";
    case PathPiece::kSBend:
      return "s-bend";
    case PathPiece::kCorner:
      return "corner";
    case PathPiece::kFork:
      return "fork";
  }
  return "?";
}

SequenceBenchmarkResult run_sequence_benchmark(const SequenceBenchmarkOptions& options,
                                               const std::function<void(double)>& progress) {
  SequenceBenchmarkResult result;
  if (options.pieces.empty()) throw std::invalid_argument("sequences need at least one path piece");
  cv::RNG rng(options.seed * 2654435761u + 7);
  if (!options.save_failures_dir.empty())
    std::filesystem::create_directories(options.save_failures_dir);
  const int total = options.sequences + options.empty_sequences;
  if (options.only_sequence >= total)
    throw std::invalid_argument("only sequence " + std::to_string(options.only_sequence) +
                                " asked for, but there are " + std::to_string(total) +
                                " (numbered from 0)");
  int saved = 0;
  for (int i = 0; i < total; ++i) {
    run_sequence(rng, options, i, i < options.sequences, &result, &saved);
    if (progress) progress(static_cast<double>(i + 1) / total);
  }
  result.summary = summarise(result, options);
  return result;
}

}  // namespace agv::pipeline
