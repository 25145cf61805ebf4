#include "tools/replay_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/angles.h"
#include "common/input_error.h"
#include "common/statistics.h"
#include "pipeline/dataset.h"
#include "pipeline/evaluation/frame_annotation.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/replay.h"
#include "tools/gnuplot.h"
#include "tools/progress_bar.h"

namespace agv::tools {
namespace {

cv::Vec3d parse_colour(const std::string& text) {
  std::stringstream stream(text);
  std::string part;
  std::vector<double> values;
  while (std::getline(stream, part, ',')) {
    try {
      values.push_back(std::stod(part));
    } catch (const std::exception&) {
      throw InputError("--tape-color-bgr " + text + ": expected three numbers B,G,R (0-255)");
    }
  }
  if (values.size() != 3 || *std::min_element(values.begin(), values.end()) < 0 ||
      *std::max_element(values.begin(), values.end()) > 255) {
    throw InputError("--tape-color-bgr " + text + ": expected three numbers B,G,R (0-255)");
  }
  return {values[0], values[1], values[2]};
}

void write_measurements(std::ostream& out, const pipeline::ReplayResult& result, bool has_truth) {
  out << "index,t_s,line_found,e_theta_rad,e_d_m,curvature_1_m,confidence,points_used,tape_width_m,"
         "lines_seen,"
         "junction_ahead,bad,source,perceive_ms,cmd_vx_m_s,cmd_vy_m_s,cmd_wz_rad_s,flags";
  if (has_truth) out << ",true_e_theta_rad,true_e_d_m";
  out << '\n' << std::setprecision(9);
  for (const pipeline::ReplayFrame& f : result.frames) {
    const LineMeasurement& m = f.measurement;
    out << f.index << ',' << f.t_s << ',' << (m.line_found ? 1 : 0) << ',';
    if (m.line_found) {
      out << m.e_theta_rad << ',' << m.e_d_m << ',' << m.curvature_1_m << ',' << m.confidence << ','
          << m.points_used << ',' << m.tape_width_m << ',' << m.lines_seen << ','
          << (m.junction_ahead ? 1 : 0);
    } else {
      out << ",,,0,0,,0,0";
    }
    out << ',' << (f.bad ? 1 : 0) << ',' << f.source << ',' << f.perceive_ms << ','
        << f.command.vx_m_s << ',' << f.command.vy_m_s << ',' << f.command.wz_rad_s << ','
        << f.flags;
    if (has_truth) {
      if (f.truth) {
        out << ',' << f.truth->e_theta_rad << ',' << f.truth->e_d_m;
      } else {
        out << ",,";
      }
    }
    out << '\n';
  }
}

std::string plot_replay(const pipeline::OutputFolder& folder, bool has_truth,
                        const std::string& title) {
  const std::string data = gnuplot_quote(folder.file("measurements.csv").string());
  std::ostringstream script;
  script << "set terminal pngcairo size 1100,800 font 'DejaVu Sans,11'\n"
         << "set output " << gnuplot_quote(folder.file("errors.png").string()) << "\n"
         << "set datafile separator ','\n"
         << "set multiplot layout 2,1 title " << gnuplot_quote(title) << " noenhanced\n"
         << "set grid\nset key top right\nset xlabel 'time (s)'\n"
         << "set ylabel 'lateral error e_{d} (mm)'\n"
         << "plot " << data
         << " using 2:($3>0 ? $5*1000 : NaN) every ::1 with points pt 7 ps 0.6 lc rgb '#ff7f0e' "
            "title 'measured'";
  if (has_truth)
    script << ", '' using 2:($20*1000) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true'";
  script << "\nset ylabel 'heading error e_{θ} (deg)'\n"
         << "plot " << data
         << " using 2:($3>0 ? $4*180/pi : NaN) every ::1 with points pt 7 ps 0.6 lc rgb '#ff7f0e' "
            "title 'measured'";
  if (has_truth)
    script << ", '' using 2:($19*180/pi) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true'";
  script << "\nunset multiplot\n";
  return run_gnuplot(script.str());
}

}  // namespace

void add_replay_command(CLI::App& app, ReplayArgs& args) {
  CLI::App* sub = app.add_subcommand("replay",
                                     "Runs perception and the controller (open loop: the commands "
                                     "it would have given) over recorded frames: "
                                     "a dataset folder (frames/, manifest.csv, camera.yaml) or a "
                                     "video file (with --camera). Writes "
                                     "measurements.csv, summary.json (frames, frames lost, bad "
                                     "frames, timing, and perception RMS against the "
                                     "manifest's ground truth when it has one), errors.png, "
                                     "strip.png and annotated.avi (detected lines, "
                                     "e_d and e_theta drawn on each frame).");
  sub->add_option("dataset", args.dataset, "Dataset folder or video file")->required();
  sub->add_option("--camera", args.camera, "Camera YAML (default: the dataset's camera.yaml)");
  sub->add_option("--controller", args.controller, "Controller whose commands to compute")
      ->check(CLI::IsMember({"finite_step", "pid", "seed004_ff_p", "dwa", "improved_dwa"}));
  sub->add_option("--out", args.out_dir, "Output folder (default: runs/<date-time>)");
  sub->add_flag("--skip-bad-frames", args.skip_bad_frames,
                "Count unreadable or wrong-sized frames, report them in summary.json and go on "
                "(default: stop)");
  sub->add_option("--branch", args.branch, "Branch to follow where lines meet")
      ->check(CLI::IsMember({"left", "straight", "right"}));
  sub->add_option("--tape-width-m", args.tape_width_m,
                  "Tape width (default: camera.yaml's tape_width_m, else 0.025)")
      ->check(CLI::Range(0.0, 0.5));
  sub->add_option("--tape-color-bgr", args.tape_color,
                  "Tape colour hint B,G,R (default: camera.yaml's, else automatic)");
  sub->add_option("--path-speed", args.path_speed_m_s, "Path speed the controller assumes (m/s)")
      ->check(CLI::Range(0.0, 5.0));
  sub->add_flag("--no-tracking", args.no_tracking,
                "Search every whole frame (default: track the line between full searches, "
                "which is faster and as accurate)");
  sub->add_flag("--no-video", args.no_video, "Skip annotated.avi");
  sub->add_flag("--quiet", args.quiet, "No progress bar");
}

int run_replay_command(const ReplayArgs& args) {
  const pipeline::Dataset dataset = pipeline::open_dataset(
      args.dataset, args.camera, 0.0, /*allow_missing_frames=*/args.skip_bad_frames);
  pipeline::ReplayOptions options;
  options.skip_bad_frames = args.skip_bad_frames;
  for (const auto& [word, kind] : pipeline::kControllerKindWords)
    if (word == args.controller) options.controller.kind = kind;
  options.path_speed_m_s = args.path_speed_m_s;
  options.perception.branch = perception::parse_branch_choice(args.branch);
  options.perception.tracking = !args.no_tracking;
  options.perception.tape.width_m =
      args.tape_width_m > 0.0 ? args.tape_width_m : dataset.camera.tape_width_m.value_or(0.025);
  if (!args.tape_color.empty()) {
    options.perception.tape.color_bgr = parse_colour(args.tape_color);
  } else {
    options.perception.tape.color_bgr = dataset.camera.tape_color_bgr;
  }

  pipeline::OutputFolder folder(args.out_dir);
  const perception::CameraModel camera =
      perception::camera_model_of(dataset.camera, dataset.camera_name);
  cv::VideoWriter video;
  std::vector<cv::Mat> strip;
  const int total = dataset.video.empty() ? static_cast<int>(dataset.rows.size()) : 0;
  const int strip_every = std::max(1, total / 12);
  pipeline::ReplayResult result;
  {
    ProgressBar bar(
        "replaying " + (dataset.video.empty() ? std::to_string(total) + " frames" : dataset.video),
        !args.quiet);
    result = pipeline::run_replay(
        dataset, options,
        [&](const pipeline::ReplayFrame& frame, const cv::Mat& image,
            const perception::LineDetection& detection) {
          const bool want_strip = dataset.video.empty()
                                      ? frame.index % strip_every == 0 && strip.size() < 12
                                      : strip.size() < 12;
          if (args.no_video && !want_strip) return;
          char caption[96];
          std::snprintf(caption, sizeof(caption), "frame %d  t %.2f s", frame.index, frame.t_s);
          const cv::Mat annotated =
              pipeline::annotate_frame(image, camera, detection, frame.measurement, caption);
          if (!args.no_video) {
            if (!video.isOpened()) {
              const double fps = std::clamp(1.0 / std::max(1e-3, result.period_s), 1.0, 60.0);
              video.open(folder.file("annotated.avi").string(),
                         cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, annotated.size());
              if (!video.isOpened())
                throw InputError(folder.file("annotated.avi").string() +
                                 ": cannot write the video");
            }
            video.write(annotated);
          }
          if (want_strip) {
            cv::Mat small;
            cv::resize(annotated, small, annotated.size() / 2, 0, 0, cv::INTER_AREA);
            strip.push_back(small);
          }
        },
        [&](double f) { bar.update(f); });
  }
  video.release();

  // Summary.
  int lost = 0, bad = 0, junctions = 0;
  std::vector<double> perceive_ms, err_d, err_theta;
  nlohmann::json bad_frames = nlohmann::json::array();
  for (const pipeline::ReplayFrame& f : result.frames) {
    if (f.bad) {
      ++bad;
      bad_frames.push_back({{"index", f.index}, {"source", f.source}, {"problem", f.problem}});
      continue;
    }
    perceive_ms.push_back(f.perceive_ms);
    if (!f.measurement.line_found) {
      ++lost;
      continue;
    }
    if (f.measurement.junction_ahead) ++junctions;
    if (f.truth) {
      err_d.push_back(f.measurement.e_d_m - f.truth->e_d_m);
      err_theta.push_back(wrap_angle_rad(f.measurement.e_theta_rad - f.truth->e_theta_rad));
    }
  }
  auto rms_or_null = [](const std::vector<double>& v) {
    return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(rms(v));
  };
  double mean_ms = 0.0;
  for (double ms : perceive_ms) mean_ms += ms;
  mean_ms /= std::max<size_t>(1, perceive_ms.size());
  nlohmann::json summary;
  summary["dataset"] = args.dataset;
  summary["camera"] = dataset.camera_name;
  summary["controller"] = result.controller_name;
  summary["branch"] = args.branch;
  summary["period_s"] = result.period_s;
  summary["frames"] = result.frames.size();
  summary["frames_lost"] = lost;
  summary["frames_bad"] = bad;
  summary["bad_frames"] = bad_frames;
  summary["frames_with_junction"] = junctions;
  summary["has_ground_truth"] = dataset.has_truth;
  summary["perception_rms_e_d_m"] = rms_or_null(err_d);
  summary["perception_rms_e_theta_rad"] = rms_or_null(err_theta);
  summary["frames_tracked"] = result.perception_counts.tracked;
  summary["frames_searched"] = result.perception_counts.searched;
  summary["timing"] = {{"perceive_ms_mean", mean_ms},
                       {"perceive_ms_median", percentile(perceive_ms, 0.5)},
                       {"perceive_ms_p99", percentile(perceive_ms, 0.99)},
                       {"wall_s", result.wall_s},
                       {"frames_per_s", result.frames.size() / std::max(1e-9, result.wall_s)}};
  {
    std::ofstream csv(folder.file("measurements.csv"));
    write_measurements(csv, result, dataset.has_truth);
    std::ofstream json(folder.file("summary.json"));
    json << summary.dump(2) << '\n';
    if (!csv || !json) throw InputError(folder.target().string() + ": cannot write the results");
  }
  if (!strip.empty()) {
    while (strip.size() % 4 != 0)
      strip.push_back(cv::Mat::zeros(strip.front().size(), strip.front().type()));
    std::vector<cv::Mat> rows;
    for (size_t i = 0; i < strip.size(); i += 4) {
      cv::Mat row;
      cv::hconcat(std::vector<cv::Mat>(strip.begin() + i, strip.begin() + i + 4), row);
      rows.push_back(row);
    }
    cv::Mat sheet;
    cv::vconcat(rows, sheet);
    cv::imwrite(folder.file("strip.png").string(), sheet);
  }
  const std::string failure = plot_replay(folder, dataset.has_truth, "replay of " + args.dataset);
  if (!failure.empty()) std::cerr << "agv replay: warning: plot skipped: " << failure << '\n';
  folder.commit();

  std::printf(
      "frames %zu | lost %d | bad %d | junctions %d | perception rms %s mm / %s deg | %.2f ms per "
      "frame\n",
      result.frames.size(), lost, bad, junctions,
      err_d.empty() ? "n/a" : std::to_string(1e3 * rms(err_d)).substr(0, 5).c_str(),
      err_theta.empty() ? "n/a" : std::to_string(rad_to_deg(rms(err_theta))).substr(0, 5).c_str(),
      mean_ms);
  std::printf("output: %s\n", folder.target().c_str());
  return 0;
}

}  // namespace agv::tools
