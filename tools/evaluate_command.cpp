#include "tools/evaluate_command.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "common/angles.h"
#include "common/input_error.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/evaluation/perception_benchmark.h"
#include "pipeline/evaluation/sequence_benchmark.h"
#include "tools/build_info.h"
#include "tools/peak_memory.h"
#include "tools/progress_bar.h"
#include "tools/top_view_plots.h"

namespace agv::tools {

void add_evaluate_command(CLI::App& app, EvaluateArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "evaluate",
      "Perception accuracy over randomised rendered frames: tape colours and polarities, widths "
      "10-50 mm, floors, lighting, shadow, glare, noise, motion blur, camera height and tilt, lens "
      "distortion, straight tape and arcs of 0.3-3 m radius, plus frames without tape. Prints "
      "the detection rate on frames showing at least half the tape, their RMS errors at the "
      "vehicle's origin (e_d, e_theta as DESIGN.md defines them) and at the nearest evidence "
      "(before the line is carried back to the origin), the lines reported where there is no "
      "tape; and the detection rate, errors at the origin and lines without tape of the usual "
      "blur + Canny + HoughLinesP detector on the same frames. Then sequences: consecutive "
      "frames along random paths (lines joined to arcs, S-bends, corners of R 0.1-0.3 m, Y forks "
      "with the way chosen), tape 10-100 mm wide with no width configured, perception as the "
      "loop runs it (tracking, path memory on wheel odometry): found, RMS at the origin after "
      "the memory's warm-up, by piece, direction flips, lines without tape.");
  sub->add_option("--conditions", args.conditions, "Random draws of camera, floor, tape and light")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  sub->add_option("--frames-per-condition", args.frames_per_condition, "Poses per draw")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sub->add_option("--empty-conditions", args.empty_conditions, "Draws without tape")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  sub->add_option("--sequences", args.sequences, "Random paths driven frame by frame (0: none)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  sub->add_option("--empty-sequences", args.empty_sequences,
                  "Drives of 1 m over floors without tape")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  sub->add_option("--sequence-length-m", args.sequence_length_m, "Path driven per sequence")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  sub->add_option("--sequence-pieces", args.sequence_pieces,
                  "What the sequences' paths are laid from, comma-separated")
      ->delimiter(',')
      ->check(CLI::IsMember({"line", "arc", "s-bend", "corner", "fork"}))
      ->capture_default_str();
  sub->add_option("--seed", args.seed, "Seed (same seed, same frames)")->capture_default_str();
  sub->add_option("--only-sequence", args.only_sequence,
                  "Drive only this sequence (numbered from 0 as sequences.csv numbers them: the "
                  "same frames as in the full run), to look at one again")
      ->check(CLI::Range(0, 2000));
  sub->add_option("--out", args.out_dir,
                  "Also write frames.csv, sequences.csv and summary.json to this folder");
  sub->add_flag("--force", args.force, "Replace an existing output folder (a previous result)");
  sub->add_option(
      "--save-failures", args.save_failures,
      "Write annotated frames that were missed, off by more than 1 mm / 0.5 deg, or gave a line "
      "without tape, to this folder (at most 60; the sequences' in sequences/ there, at most 5 a "
      "sequence, 60 with --only-sequence, each with a top view of what the path memory held: "
      "NAME_top.png, its points in NAME_top.csv)");
  sub->add_option("--save-frames", args.save_frames,
                  "With --only-sequence and --save-failures: also write that sequence's frames "
                  "FIRST to LAST (numbered from 0 as the saved files name them), failed or not, "
                  "with their top views (at most 60)")
      ->type_name("FIRST LAST");
  sub->add_flag("--json", args.json, "Print the summary as JSON");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
}

namespace {

// A CSV field in double quotes (RFC 4180: a quote inside is doubled), for text with commas.
std::string csv_quoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// One row per frame of the sequences; the draw of each sequence, quoted, in its last column.
void write_sequences_csv(const pipeline::SequenceBenchmarkResult& sequences,
                         const std::string& file) {
  std::ofstream csv(file);
  csv << "sequence,has_tape,piece,travelled_m,line_found,extrapolated,remembered_only,"
         "error_e_d_m,error_e_theta_rad,measured_width_m,true_width_m,perceive_ms,"
         "no_line_reason,sequence_draw\n"
      << std::setprecision(9);
  for (const pipeline::SequenceFrame& f : sequences.frames) {
    std::string reason = f.no_line_reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    csv << f.sequence << ',' << f.has_tape << ',' << f.piece << ',' << f.travelled_m << ','
        << f.line_found << ',' << f.extrapolated << ',' << f.remembered_only << ',' << f.error_e_d_m
        << ',' << f.error_e_theta_rad << ',' << f.measured_width_m << ',' << f.true_width_m << ','
        << f.perceive_ms << ',' << reason << ','
        << csv_quoted(sequences.sequence_texts[static_cast<std::size_t>(f.sequence)]) << '\n';
  }
  if (!csv) throw InputError(file + ": cannot write the sequences");
}

void print_sequences(const nlohmann::json& s) {
  const nlohmann::json& a = s["after_warm_up"];
  std::printf(
      "sequences %d (%d frames, tape 10-100 mm, width not configured): found %.2f %% | after "
      "%.1f m: RMS e_d %.3f mm, e_theta %.3f deg (max %.3f mm, %.3f deg; %d frames carried back "
      "from the view) | direction flips %d | without tape: %d lines in %d frames | %.2f ms per "
      "frame (p99 %.2f)\n",
      s["sequences"].get<int>(), s["frames_with_tape"].get<int>(),
      100.0 * s["found_fraction"].get<double>(), s["warm_up_m"].get<double>(),
      1e3 * a["rms_e_d_m"].get<double>(), rad_to_deg(a["rms_e_theta_rad"].get<double>()),
      1e3 * a["max_abs_e_d_m"].get<double>(), rad_to_deg(a["max_abs_e_theta_rad"].get<double>()),
      a["frames_extrapolated"].get<int>(), s["direction_flips"].get<int>(),
      s["lines_reported_without_tape"].get<int>(), s["frames_without_tape"].get<int>(),
      s["perceive_ms_median"].get<double>(), s["perceive_ms_p99"].get<double>());
  std::printf("sequences by piece (RMS / max):");
  if (s["by_piece"].empty()) std::printf(" no frame found after the warm-up");
  for (const auto& [piece, e] : s["by_piece"].items()) {
    std::printf(" | %s %d: %.3f / %.3f mm, %.3f / %.3f deg", piece.c_str(), e["frames"].get<int>(),
                1e3 * e["rms_e_d_m"].get<double>(), 1e3 * e["max_abs_e_d_m"].get<double>(),
                rad_to_deg(e["rms_e_theta_rad"].get<double>()),
                rad_to_deg(e["max_abs_e_theta_rad"].get<double>()));
  }
  std::printf("\n");
}

}  // namespace

int run_evaluate(const EvaluateArgs& args) {
  pipeline::PerceptionBenchmarkOptions options;
  options.conditions = args.conditions;
  options.frames_per_condition = args.frames_per_condition;
  options.empty_conditions = args.empty_conditions;
  options.seed = args.seed;
  options.save_failures_dir = args.save_failures;
  if (args.only_sequence >= args.sequences + args.empty_sequences)
    throw InputError("--only-sequence " + std::to_string(args.only_sequence) + ": there are " +
                     std::to_string(args.sequences + args.empty_sequences) +
                     " sequences (--sequences plus --empty-sequences), numbered from 0");
  if (args.save_frames) {
    const auto [first, last] = *args.save_frames;
    const std::string given =
        "--save-frames " + std::to_string(first) + " " + std::to_string(last) + ": ";
    if (args.only_sequence < 0 || args.save_failures.empty())
      throw InputError(given + "needs --only-sequence (the sequence) and --save-failures (where)");
    if (first < 0 || last < first || last - first >= 60)
      throw InputError(given + "FIRST must be 0 or more, LAST from FIRST to FIRST + 59");
  }
  // The output folder first: a folder that may not be replaced is refused before the work.
  std::optional<pipeline::OutputFolder> folder;
  if (!args.out_dir.empty()) folder.emplace(args.out_dir, "summary.json", args.force);
  pipeline::PerceptionBenchmarkResult result;
  {
    ProgressBar bar("evaluating perception", !args.quiet);
    result = pipeline::run_perception_benchmark(options, [&](double f) { bar.update(f); });
  }
  pipeline::SequenceBenchmarkResult sequences;
  if (args.sequences + args.empty_sequences > 0) {
    pipeline::SequenceBenchmarkOptions sequence_options;
    sequence_options.sequences = args.sequences;
    sequence_options.empty_sequences = args.empty_sequences;
    sequence_options.path_length_m = args.sequence_length_m;
    sequence_options.seed = args.seed;
    sequence_options.only_sequence = args.only_sequence;
    if (args.save_frames) {
      sequence_options.save_first_frame = args.save_frames->first;
      sequence_options.save_last_frame = args.save_frames->second;
    }
    if (args.only_sequence >= 0)
      sequence_options.max_saved_per_sequence = sequence_options.max_saved;
    sequence_options.pieces.clear();
    for (const std::string& word : args.sequence_pieces)
      sequence_options.pieces.push_back(pipeline::parse_path_piece(word));
    if (!args.save_failures.empty())
      sequence_options.save_failures_dir = args.save_failures + "/sequences";
    ProgressBar bar("driving sequences", !args.quiet);
    sequences =
        pipeline::run_sequence_benchmark(sequence_options, [&](double f) { bar.update(f); });
    // A top view of what the path memory held at each failed frame saved, beside its picture.
    if (!sequence_options.save_failures_dir.empty()) {
      try {
        plot_top_views(sequence_options.save_failures_dir);
      } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "agv evaluate: no top views: %s\n", e.what());
      }
    }
  }
  nlohmann::json j = result.summary;
  if (!sequences.frames.empty()) j["sequences"] = sequences.summary;
  j["agv"] = build_json();
  j["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
  if (folder) {
    std::ofstream csv(folder->file("frames.csv"));
    csv << "condition,has_tape,curved,visible_fraction,line_found,error_e_d_m,error_e_theta_rad,"
           "near_error_offset_m,near_error_heading_rad,perceive_ms,baseline_found,baseline_error_e_"
           "d_m,baseline_error_e_theta_rad,baseline_ms,"
           "conditions\n"
        << std::setprecision(9);
    for (const pipeline::BenchmarkFrame& b : result.frames) {
      csv << b.condition << ',' << b.has_tape << ',' << b.curved << ',' << b.visible_fraction << ','
          << b.line_found << ',' << b.error_e_d_m << ',' << b.error_e_theta_rad << ','
          << b.near_error_offset_m << ',' << b.near_error_heading_rad << ',' << b.perceive_ms << ','
          << b.baseline_found << ',' << b.baseline_error_e_d_m << ','
          << b.baseline_error_e_theta_rad << ',' << b.baseline_ms << ',' << b.conditions_text
          << '\n';
    }
    if (!sequences.frames.empty()) write_sequences_csv(sequences, folder->file("sequences.csv"));
    std::ofstream(folder->file("summary.json")) << j.dump(2) << '\n';
    if (!csv) throw InputError(folder->target().string() + ": cannot write the results");
    folder->commit();
  }
  if (args.json) {
    if (folder) j["output"] = folder->target().string();
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::printf(
      "frames %d (%d show at least half the tape) | found %.1f %% | RMS e_d %.3f mm, e_theta %.3f "
      "deg "
      "(p95 %.3f mm, %.3f deg) | straight %d: %.3f mm %.3f deg | arcs %d: %.3f mm %.3f deg | "
      "without tape: %d lines in %d frames | %.2f ms per frame\n"
      "the same found frames at the nearest evidence (before extrapolation to the vehicle's "
      "origin): RMS offset %.3f mm, heading %.3f deg (p95 %.3f mm, %.3f deg)\n",
      j["frames"].get<int>(), j["frames_half_visible"].get<int>(),
      100.0 * j["found_fraction"].get<double>(), 1e3 * j["rms_e_d_m"].get<double>(),
      rad_to_deg(j["rms_e_theta_rad"].get<double>()), 1e3 * j["p95_abs_e_d_m"].get<double>(),
      rad_to_deg(j["p95_abs_e_theta_rad"].get<double>()), j["straight"]["frames"].get<int>(),
      1e3 * j["straight"]["rms_e_d_m"].get<double>(),
      rad_to_deg(j["straight"]["rms_e_theta_rad"].get<double>()), j["arcs"]["frames"].get<int>(),
      1e3 * j["arcs"]["rms_e_d_m"].get<double>(),
      rad_to_deg(j["arcs"]["rms_e_theta_rad"].get<double>()),
      j["lines_reported_without_tape"].get<int>(), j["frames_without_tape"].get<int>(),
      j["perceive_ms_median"].get<double>(),
      1e3 * j["at_nearest_evidence"]["rms_offset_m"].get<double>(),
      rad_to_deg(j["at_nearest_evidence"]["rms_heading_rad"].get<double>()),
      1e3 * j["at_nearest_evidence"]["p95_abs_offset_m"].get<double>(),
      rad_to_deg(j["at_nearest_evidence"]["p95_abs_heading_rad"].get<double>()));
  const nlohmann::json& base = j["baseline_canny_hough"];
  std::printf(
      "baseline Canny+HoughLinesP on the same frames: found %.1f %% | RMS e_d %.3f mm, e_theta "
      "%.3f deg (p95 %.3f mm, %.3f deg) | without tape: %d lines | %.2f ms per frame\n",
      100.0 * base["found_fraction"].get<double>(), 1e3 * base["rms_e_d_m"].get<double>(),
      rad_to_deg(base["rms_e_theta_rad"].get<double>()), 1e3 * base["p95_abs_e_d_m"].get<double>(),
      rad_to_deg(base["p95_abs_e_theta_rad"].get<double>()),
      base["lines_reported_without_tape"].get<int>(), base["ms_median"].get<double>());
  if (j.contains("sequences")) print_sequences(j["sequences"]);
  return 0;
}

}  // namespace agv::tools
