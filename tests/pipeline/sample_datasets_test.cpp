#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/angles.h"
#include "pipeline/config/factory.h"
#include "pipeline/config/recorded_run.h"
#include "pipeline/config/scenario_source.h"
#include "pipeline/dataset.h"
#include "pipeline/dataset_source.h"

namespace agv::pipeline {
namespace {

// Arc positions along the scenario's path where the tape changes shape: joints between its
// segments, and where another tape leaves or meets it.
std::vector<double> shape_changes_m(const Scenario& scenario) {
  std::vector<double> s_m;
  double s = 0.0;
  for (const control::PathSegment& segment : scenario.path.segments()) {
    s += segment.length_m;
    s_m.push_back(s);
  }
  for (const control::Path& extra : scenario.extra_paths) {
    if (extra.empty()) continue;
    s_m.push_back(scenario.path.project(extra.point_at(0.0)).s_m);
  }
  return s_m;
}

struct DatasetAccuracy {
  int frames = 0, single_piece = 0, single_piece_found = 0, frames_bad = 0;
  double rms_e_d_m = 0.0, rms_e_theta_rad = 0.0;          // on frames whose view holds one piece
  double all_rms_e_d_m = 0.0, all_rms_e_theta_rad = 0.0;  // on every frame with a line
  int found = 0;
};

// Replays a shipped dataset (as `agv replay` does, with its camera.yaml) and compares with the
// manifest's ground truth on the frames whose view holds one piece of tape (a straight or an
// arc, no joint and no branch from 0.1 m behind the vehicle to 0.25 m beyond the camera): there
// the model of perception (one arc) is the truth's. Elsewhere the single arc fitted across a
// joint extrapolated to the vehicle differs from the path under it by design; DESIGN.md's
// e_d is at the vehicle.
DatasetAccuracy replay_sample(const std::string& name, const std::string& scenario_file) {
  const Dataset dataset =
      open_dataset(std::string(AGV_SOURCE_DIR) + "/datasets/" + name, "", 0.0, false);
  const Scenario scenario =
      pipeline::load_scenario_for_command(std::string(AGV_SOURCE_DIR) + "/" + scenario_file, {});
  RecordedRunOptions options;
  options.perception = recorded_perception_options(scenario, dataset.camera);
  DatasetSource source(dataset, /*pass_bad_frames=*/false);
  const RunResult result = run_on_source(
      source, perception::camera_model_of(dataset.camera, dataset.camera_name), scenario, options);
  const std::vector<double> changes = shape_changes_m(scenario);
  const double view_end_m = dataset.camera.mount->xyz_m.x() + 0.25;
  DatasetAccuracy a;
  double d2 = 0.0, t2 = 0.0, all_d2 = 0.0, all_t2 = 0.0;
  EXPECT_EQ(result.frames.size(), dataset.rows.size());
  for (size_t i = 0; i < result.frames.size(); ++i) {
    const FrameRecord& frame = result.frames[i];
    const DatasetRow& row = dataset.rows[i];
    ++a.frames;
    a.frames_bad += frame.bad ? 1 : 0;
    if (!row.pose || !row.truth) continue;
    if (frame.measurement.line_found) {
      ++a.found;
      all_d2 += std::pow(frame.measurement.e_d_m - row.truth->e_d_m, 2);
      all_t2 += std::pow(wrap_angle_rad(frame.measurement.e_theta_rad - row.truth->e_theta_rad), 2);
    }
    const double s0 = scenario.path.project(row.pose->translation()).s_m;
    bool one_piece = true;
    for (double s : changes) one_piece = one_piece && !(s > s0 - 0.1 && s < s0 + view_end_m);
    if (!one_piece) continue;
    ++a.single_piece;
    if (!frame.measurement.line_found) continue;
    ++a.single_piece_found;
    d2 += std::pow(frame.measurement.e_d_m - row.truth->e_d_m, 2);
    t2 += std::pow(wrap_angle_rad(frame.measurement.e_theta_rad - row.truth->e_theta_rad), 2);
  }
  a.all_rms_e_d_m = std::sqrt(all_d2 / std::max(1, a.found));
  a.all_rms_e_theta_rad = std::sqrt(all_t2 / std::max(1, a.found));
  a.rms_e_d_m = std::sqrt(d2 / std::max(1, a.single_piece_found));
  a.rms_e_theta_rad = std::sqrt(t2 / std::max(1, a.single_piece_found));
  return a;
}

// The three sample datasets (JPEG quality 85, noise, wear, stray marks): on every one-piece
// frame a line, within issue 3's bar for rendered frames (RMS 0.5 mm, 0.2 deg); on the epoxy
// floor, where the vehicle's shadow edge and a glare spot lie across the tape itself, within
// twice that (a shadow edge or glare on one side of the tape shifts that edge by a fraction of a
// pixel: known, see datasets/black_epoxy_curve_shadow/README.md).
TEST(SampleDatasets, ReplayEachWithinTheAccuracyBar) {
  const struct {
    const char* name;
    const char* scenario;
    int min_single_piece;  // the test must look at enough frames to mean something
    double max_rms_e_d_m, max_rms_e_theta_deg;
  } samples[] = {
      {"blue_concrete_straight", "scenarios/dataset_blue_concrete.yaml", 45, 0.0005, 0.2},
      {"black_epoxy_curve_shadow", "scenarios/dataset_black_epoxy_curve.yaml", 8, 0.001, 0.4},
      {"yellow_junction_worn", "scenarios/dataset_yellow_junction.yaml", 25, 0.0005, 0.2}};
  for (const auto& sample : samples) {
    const DatasetAccuracy a = replay_sample(sample.name, sample.scenario);
    EXPECT_EQ(a.frames, 51) << sample.name;
    EXPECT_EQ(a.frames_bad, 0) << sample.name;
    EXPECT_GE(a.single_piece, sample.min_single_piece) << sample.name;
    EXPECT_EQ(a.single_piece_found, a.single_piece) << sample.name;
    EXPECT_LE(a.rms_e_d_m, sample.max_rms_e_d_m) << sample.name;
    EXPECT_LE(rad_to_deg(a.rms_e_theta_rad), sample.max_rms_e_theta_deg) << sample.name;
    // Every frame, joints and the fork under the vehicle included: the errors come from the
    // remembered tape under it (placed with the motion read from the frames: these recordings
    // have no odometry columns), within twice issue 3's bar (carried back from the view they
    // were up to 50 mm off: 18.8 mm RMS on the epoxy curve).
    EXPECT_EQ(a.found, a.frames) << sample.name;
    EXPECT_LE(a.all_rms_e_d_m, 0.001) << sample.name;
    EXPECT_LE(rad_to_deg(a.all_rms_e_theta_rad), 0.4) << sample.name;
    std::printf(
        "%s: %d of %d frames one-piece, RMS %.3f mm %.3f deg; all frames %.3f mm %.3f deg\n",
        sample.name, a.single_piece, a.frames, 1e3 * a.rms_e_d_m, rad_to_deg(a.rms_e_theta_rad),
        1e3 * a.all_rms_e_d_m, rad_to_deg(a.all_rms_e_theta_rad));
  }
}

}  // namespace
}  // namespace agv::pipeline
