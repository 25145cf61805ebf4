#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "perception/camera_model.h"
#include "pipeline/camera_stage.h"
#include "pipeline/evaluation/output_folder.h"
#include "pipeline/run_result.h"
#include "tools/source_setup.h"

namespace agv::tools {

// What replay and track draw of the frames they measure: annotated.avi (every frame with what
// perception found on it) and strip.png (up to 12 frames spread over the run).
class FrameAnnotator {
 public:
  // The video plays at the source's frame rate (30 frames/s for a live source).
  FrameAnnotator(const pipeline::OutputFolder& folder, const SourceSetup& setup, bool video);
  // The camera stage's sink.
  pipeline::FrameSink sink();
  // Writes strip.png and closes the video.
  void finish();

 private:
  void add(const pipeline::FrameRecord& record, const pipeline::SourceFrame& frame,
           const perception::LineDetection* detection);

  const pipeline::OutputFolder& folder_;
  perception::CameraModel camera_;
  bool video_enabled_;
  double fps_;
  long strip_every_;
  cv::VideoWriter video_;
  std::vector<cv::Mat> strip_;
};

// Counts and accuracy of a run on recorded or live frames, for summary.json and the one-line
// summary: frames, lost, bad, with junction, perception RMS against ground truth.
struct SourceFigures {
  int frames = 0, lost = 0, bad = 0, junctions = 0;
  std::vector<double> error_e_d_m, error_e_theta_rad, perceive_ms;
  std::vector<double> tape_width_m;  // measured, every frame with a line
  nlohmann::json bad_frames = nlohmann::json::array();
};
SourceFigures source_figures(const pipeline::RunResult& result);

// The summary.json keys replay and track share: the counts and accuracy, what ran on what.
nlohmann::json source_summary(const pipeline::RunResult& result, const SourceFigures& figures,
                              const SourceSetup& setup, const SourceArgs& args);

// commands.jsonl after the run (replay; track streams it as it goes).
void write_commands(const pipeline::OutputFolder& folder, const pipeline::RunResult& result);

// The end of replay and track: measurements.csv, summary.json and errors.png (measured against
// true errors over time, titled "<what> <source>") into the folder, which is then committed;
// with `json`, summary.json with the output folder on stdout. `command` names the program in
// warnings; those in `already_said` (given while the run went on) are not printed again.
void finish_source_run(pipeline::OutputFolder& folder, const pipeline::RunResult& result,
                       const SourceSetup& setup, nlohmann::json summary, const std::string& what,
                       const std::string& command, bool json,
                       const std::vector<std::string>& already_said = {});

// "0.123" in the unit given, or "n/a" for an empty set.
std::string rms_text(const std::vector<double>& values, double scale);

}  // namespace agv::tools
