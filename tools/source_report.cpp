#include "tools/source_report.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "common/angles.h"
#include "common/input_error.h"
#include "common/statistics.h"
#include "pipeline/command_stream.h"
#include "pipeline/config/factory.h"
#include "pipeline/evaluation/frame_annotation.h"
#include "pipeline/evaluation/trace_csv.h"
#include "tools/build_info.h"
#include "tools/gnuplot.h"
#include "tools/peak_memory.h"
#include "tools/tape_width_check.h"

namespace agv::tools {

FrameAnnotator::FrameAnnotator(const pipeline::OutputFolder& folder, const SourceSetup& setup,
                               bool video)
    : folder_(folder),
      camera_(setup.camera),
      video_enabled_(video),
      fps_(std::clamp(setup.opened.source->frame_period_s() > 0.0
                          ? 1.0 / setup.opened.source->frame_period_s()
                          : 30.0,
                      1.0, 60.0)),
      strip_every_(std::max(1L, setup.opened.source->frame_count() / 12)) {}

pipeline::FrameSink FrameAnnotator::sink() {
  return [this](const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
                const perception::LineDetection* detection) { add(record, frame, detection); };
}

void FrameAnnotator::add(const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
                         const perception::LineDetection* detection) {
  if (!detection) return;  // a bad frame: nothing to draw
  const bool want_strip = static_cast<long>(record.index) % strip_every_ == 0 && strip_.size() < 12;
  if (!video_enabled_ && !want_strip) return;
  char caption[96];
  std::snprintf(caption, sizeof(caption), "frame %llu  t %.2f s",
                static_cast<unsigned long long>(record.index), record.stamp_s);
  const cv::Mat annotated =
      pipeline::annotate_frame(frame.image, camera_, *detection, record.measurement, caption);
  if (video_enabled_) {
    if (!video_.isOpened()) {
      const std::string path = folder_.file("annotated.avi").string();
      // OpenCV's own MJPEG writer: through FFmpeg (the default backend) the process grew by
      // 75 kB a frame (600 MB over a 10 000-frame replay); this one keeps its memory constant
      // (its files are larger, about 85 kB a VGA frame; --no-video leaves the video out).
      video_.open(path, cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps_,
                  annotated.size());
      if (!video_.isOpened()) throw InputError(path + ": cannot write the video");
    }
    video_.write(annotated);
  }
  if (want_strip) {
    cv::Mat small;
    cv::resize(annotated, small, annotated.size() / 2, 0, 0, cv::INTER_AREA);
    strip_.push_back(small);
  }
}

void FrameAnnotator::finish() {
  video_.release();
  if (strip_.empty()) return;
  while (strip_.size() % 4 != 0)
    strip_.push_back(cv::Mat::zeros(strip_.front().size(), strip_.front().type()));
  std::vector<cv::Mat> rows;
  for (size_t i = 0; i < strip_.size(); i += 4) {
    cv::Mat row;
    cv::hconcat(std::vector<cv::Mat>(strip_.begin() + i, strip_.begin() + i + 4), row);
    rows.push_back(row);
  }
  cv::Mat sheet;
  cv::vconcat(rows, sheet);
  cv::imwrite(folder_.file("strip.png").string(), sheet);
}

SourceFigures source_figures(const pipeline::RunResult& result) {
  SourceFigures f;
  for (const pipeline::FrameRecord& frame : result.frames) {
    ++f.frames;
    if (frame.bad) {
      ++f.bad;
      f.bad_frames.push_back(
          {{"index", frame.index}, {"source", frame.label}, {"problem", frame.problem}});
      continue;
    }
    f.perceive_ms.push_back(1e3 * frame.perceive_s);
    const LineMeasurement& m = frame.measurement;
    if (!m.line_found) {
      ++f.lost;
      continue;
    }
    if (m.junction_ahead) ++f.junctions;
    if (m.tape_width_m > 0.0) f.tape_width_m.push_back(m.tape_width_m);
    if (frame.truth) {
      f.error_e_d_m.push_back(m.e_d_m - frame.truth->e_d_m);
      f.error_e_theta_rad.push_back(wrap_angle_rad(m.e_theta_rad - frame.truth->e_theta_rad));
    }
  }
  return f;
}

nlohmann::json source_summary(const pipeline::RunResult& result, const SourceFigures& f,
                              const SourceSetup& setup, const SourceArgs& args) {
  auto rms_or_null = [](const std::vector<double>& v) {
    return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(rms(v));
  };
  nlohmann::json j;
  j["source"] = args.source;
  j["source_kind"] = setup.opened.kind;
  j["camera"] = setup.opened.camera_name;
  j["scenario"] = setup.scenario.source_name;
  j["controller"] = result.controller_name;
  j["ts_s"] = setup.scenario.controller.ts_s;
  j["branch"] = args.branch;
  j["frames"] = f.frames;
  j["frames_lost"] = f.lost;
  j["frames_bad"] = f.bad;
  j["bad_frames"] = f.bad_frames;
  j["frames_dropped"] = result.frames_dropped;
  j["frames_with_junction"] = f.junctions;
  j["has_ground_truth"] = setup.opened.has_truth;
  j["frames_tracked"] = result.perception_counts.tracked;
  j["frames_searched"] = result.perception_counts.searched;
  j["odometry"] = result.odometry_source;
  int extrapolated = 0, remembered_only = 0;
  for (const pipeline::FrameRecord& frame : result.frames) {
    extrapolated += frame.measurement.line_found && frame.measurement.extrapolated ? 1 : 0;
    remembered_only += frame.measurement.line_found && frame.measurement.remembered_only ? 1 : 0;
  }
  j["frames_extrapolated"] = extrapolated;
  j["frames_remembered_only"] = remembered_only;
  // The tape's width as measured, and the camera file's (a hint): when the tape seen is
  // consistently other than the hint, say so once.
  const std::optional<double> configured_m = setup.opened.camera.tape_width_m;
  const double measured_m = f.tape_width_m.empty() ? 0.0 : percentile(f.tape_width_m, 0.5);
  j["tape_width_m"] = {
      {"measured_median",
       f.tape_width_m.empty() ? nlohmann::json(nullptr) : nlohmann::json(measured_m)},
      {"configured", configured_m ? nlohmann::json(*configured_m) : nlohmann::json(nullptr)}};
  j["warnings"] = nlohmann::json::array();
  if (const std::optional<std::string> warning = tape_width_warning(f.tape_width_m, configured_m))
    j["warnings"].push_back(*warning);
  for (const std::string& warning : pipeline::scenario_warnings(setup.scenario))
    j["warnings"].push_back(warning);
  j["perception_rms_e_d_m"] = rms_or_null(f.error_e_d_m);
  j["perception_rms_e_theta_rad"] = rms_or_null(f.error_e_theta_rad);
  j["commands"] = result.rows.size();
  j["stop_reason"] = result.stop_reason;
  j["timing"] = {{"perceive_ms_median", percentile(f.perceive_ms, 0.5)},
                 {"perceive_ms_p99", percentile(f.perceive_ms, 0.99)},
                 {"wall_s", result.wall_s},
                 {"frames_per_s", f.frames / std::max(1e-9, result.wall_s)}};
  return j;
}

void write_commands(const pipeline::OutputFolder& folder, const pipeline::RunResult& result) {
  std::ofstream out(folder.file("commands.jsonl"));
  for (const pipeline::TraceRow& row : result.rows) out << pipeline::command_json_line(row) << '\n';
  if (!out) throw InputError(folder.file("commands.jsonl").string() + ": cannot write");
}

namespace {

std::string plot_measurements(const pipeline::OutputFolder& folder,
                              const pipeline::RunResult& result, bool has_truth,
                              const std::string& title) {
  // Columns of measurements.csv: 2 t_s, 3 line_found, 4 e_theta_rad, 5 e_d_m, 19/20 the truth.
  const std::string data = gnuplot_quote(folder.file("measurements.csv").string());
  bool any_line = false;
  for (const pipeline::FrameRecord& f : result.frames) any_line |= f.measurement.line_found;
  std::ostringstream script;
  script << "set terminal pngcairo size 1100,800 font 'DejaVu Sans,11'\n"
         << "set output " << gnuplot_quote(folder.file("errors.png").string()) << "\n"
         << "set datafile separator ','\n"
         << "set multiplot layout 2,1 title " << gnuplot_quote(title) << " noenhanced\n"
         << "set grid\nset key top right\nset xlabel 'time (s)'\n";
  if (!any_line) {  // nothing to scale the axes by: the frames' time span, and say why
    const double t0 = result.frames.empty() ? 0.0 : result.frames.front().stamp_s;
    const double t1 = result.frames.empty() ? 1.0 : result.frames.back().stamp_s;
    script << "set xrange [" << t0 << ":" << std::max(t1, t0 + 1e-3) << "]\n"
           << "set yrange [-1:1]\nset label 1 'no line found in any frame' at graph 0.5, 0.5 "
              "center\n";
  }
  const char* measured =
      any_line ? "points pt 7 ps 0.6 lc rgb '#ff7f0e' title 'measured'" : "points notitle";
  script << "set ylabel 'lateral error e_{d} (mm)'\n"
         << "plot " << data << " using 2:($3>0 ? $5*1000 : NaN) every ::1 with " << measured;
  if (has_truth)
    script << ", '' using 2:($20*1000) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true'";
  script << "\nset ylabel 'heading error e_{θ} (deg)'\n"
         << "plot " << data << " using 2:($3>0 ? $4*180/pi : NaN) every ::1 with " << measured;
  if (has_truth)
    script << ", '' using 2:($19*180/pi) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true'";
  script << "\nunset multiplot\n";
  return run_gnuplot(script.str());
}

// A plot title that fits: "replay of video file run.avi", a long source cut short.
std::string plot_title(const std::string& what, const std::string& kind,
                       const std::string& source) {
  constexpr size_t kMaxSource = 70;  // the title must fit above a 1100 px wide plot
  const std::string shown =
      source.size() <= kMaxSource ? source : source.substr(0, kMaxSource - 3) + "...";
  return what + " " + kind + " " + shown;
}

}  // namespace

void finish_source_run(pipeline::OutputFolder& folder, const pipeline::RunResult& result,
                       const SourceSetup& setup, nlohmann::json summary, const std::string& what,
                       const std::string& command, bool json,
                       const std::vector<std::string>& already_said) {
  const bool has_truth = setup.opened.has_truth;
  summary["agv"] = build_json();
  summary["peak_rss_mb"] = peak_rss_mb();  // so far: the run's peak
  {
    std::ofstream csv(folder.file("measurements.csv"));
    pipeline::write_measurements_csv(csv, result.frames, has_truth);
    std::ofstream out(folder.file("summary.json"));
    out << summary.dump(2) << '\n';
    if (!csv || !out) throw InputError(folder.target().string() + ": cannot write the results");
  }
  const std::string failure =
      plot_measurements(folder, result, has_truth,
                        plot_title(what, setup.opened.kind, summary["source"].get<std::string>()));
  if (!failure.empty())
    std::cerr << "agv " << command << ": warning: plot skipped: " << failure << '\n';
  folder.commit();
  for (const nlohmann::json& warning : summary["warnings"]) {
    const std::string text = warning.get<std::string>();
    if (std::find(already_said.begin(), already_said.end(), text) != already_said.end()) continue;
    std::cerr << "agv " << command << ": warning: " << text << '\n';
  }
  if (!json) return;
  summary["output"] = folder.target().string();
  std::cout << summary.dump(2) << '\n';
}

std::string rms_text(const std::vector<double>& values, double scale) {
  if (values.empty()) return "n/a";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f", scale * rms(values));
  return text;
}

}  // namespace agv::tools
