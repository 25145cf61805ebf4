#include "perception/tracking_line_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/angles.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

// A pose near the first tape of the scene: at arc length s, offset e_d to the left and turned
// by e_theta.
Pose2 pose_on(const control::Path& path, double s_m, double e_d_m, double e_theta_rad) {
  const Eigen::Vector2d foot = path.point_at(s_m);
  const double heading = path.heading_at(s_m);
  const Eigen::Vector2d p = foot + e_d_m * Eigen::Vector2d(-std::sin(heading), std::cos(heading));
  return {p.x(), p.y(), wrap_angle_rad(heading + e_theta_rad)};
}

struct SequenceResult {
  int frames = 0, found = 0, found_by_full_search = 0;
  double rms_e_d_m = 0.0, rms_e_theta_rad = 0.0;                          // tracking
  double full_search_rms_e_d_m = 0.0, full_search_rms_e_theta_rad = 0.0;  // every frame searched
  TrackingLineEstimator::Counts counts;
};

// A vehicle driving along the scene's first tape at 0.3 m/s, 10 frames per second, weaving
// (e_d within 10 mm, e_theta within 4 deg), measured with tracking and with the full search.
SequenceResult drive(const CameraModel& camera, const pipeline::Scene& scene, double s_start_m,
                     int frames) {
  const pipeline::FrameRenderer renderer(camera, scene);
  const control::Path& path = scene.tapes.front().path;
  TrackingLineEstimator tracking(camera, testing::hinted(scene));
  const LineEstimator full_search(camera, testing::hinted(scene));
  SequenceResult r;
  double d2 = 0, t2 = 0, fd2 = 0, ft2 = 0;
  for (int k = 0; k < frames; ++k) {
    const double s = s_start_m + 0.03 * k;
    const Pose2 pose =
        pose_on(path, s, 0.010 * std::sin(0.3 * k), deg_to_rad(4.0) * std::cos(0.2 * k));
    const control::TrackingError truth =
        path.tracking_error(pose, path.project(pose.translation(), s, 0.2));
    const cv::Mat frame = renderer.render(pose, {0.3, 0.0, 0.0}, static_cast<std::uint64_t>(k));
    const LineMeasurement m = tracking.measure(frame, 0.1 * k);
    const LineMeasurement full = full_search.estimate(frame, 0.1 * k);
    ++r.frames;
    if (m.line_found) {
      ++r.found;
      d2 += std::pow(m.e_d_m - truth.e_d_m, 2);
      t2 += std::pow(wrap_angle_rad(m.e_theta_rad - truth.e_theta_rad), 2);
    }
    if (full.line_found) {
      ++r.found_by_full_search;
      fd2 += std::pow(full.e_d_m - truth.e_d_m, 2);
      ft2 += std::pow(wrap_angle_rad(full.e_theta_rad - truth.e_theta_rad), 2);
    }
  }
  r.rms_e_d_m = std::sqrt(d2 / std::max(1, r.found));
  r.rms_e_theta_rad = std::sqrt(t2 / std::max(1, r.found));
  r.full_search_rms_e_d_m = std::sqrt(fd2 / std::max(1, r.found_by_full_search));
  r.full_search_rms_e_theta_rad = std::sqrt(ft2 / std::max(1, r.found_by_full_search));
  r.counts = tracking.counts();
  return r;
}

// Tracking must not trade accuracy for speed: on a straight tape and on an arc of 0.6 m radius
// it meets issue 4's bar (RMS 0.2 mm, 0.1 deg) on clean rendered frames, where the full search
// meets it too; most frames are tracked (every 10th is a full search by design, and a failed
// track falls back).
TEST(TrackingLineEstimator, AsAccurateAsTheFullSearchOnStraightAndCurvedSequences) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const pipeline::Scene straight = testing::straight_tape_scene();
  const SequenceResult a = drive(camera, straight, 2.0, 60);
  EXPECT_EQ(a.found, a.frames);
  EXPECT_LE(a.rms_e_d_m, 0.0002);
  EXPECT_LE(rad_to_deg(a.rms_e_theta_rad), 0.1);
  EXPECT_GE(a.counts.tracked, 45);

  pipeline::Scene arc = testing::straight_tape_scene();
  arc.tapes[0].path = control::Path::starting_at({0.0, 0.0, 0.0}).add_line(1.0).add_arc(0.6, kPi);
  const SequenceResult b = drive(camera, arc, 1.3, 40);
  EXPECT_EQ(b.found, b.frames);
  EXPECT_EQ(b.found_by_full_search, b.frames);
  EXPECT_LE(b.rms_e_d_m, 0.0002) << "full search: " << b.full_search_rms_e_d_m;
  EXPECT_LE(rad_to_deg(b.rms_e_theta_rad), 0.1)
      << "full search: " << rad_to_deg(b.full_search_rms_e_theta_rad);
  EXPECT_GE(b.counts.tracked, 25);
}

// A line that jumps further than the tracking search (45 mm sideways between two frames: a
// dropped frame, a bump) is found again by the full search, at the right place.
TEST(TrackingLineEstimator, FallsBackToTheFullSearchWhenTheLineJumps) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const pipeline::Scene scene = testing::straight_tape_scene();
  const pipeline::FrameRenderer renderer(camera, scene);
  TrackingLineEstimator tracking(camera, testing::hinted(scene));
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(
        tracking.measure(renderer.render({1.0 + 0.03 * k, 0.0, 0.0}, {}, k), 0.1 * k).line_found);
  }
  ASSERT_EQ(tracking.counts().tracked, 2);
  const Pose2 jumped{1.09, 0.045, deg_to_rad(2.0)};
  const LineMeasurement m = tracking.measure(renderer.render(jumped, {}, 3), 0.3);
  EXPECT_EQ(tracking.counts().track_failed, 1);
  ASSERT_TRUE(m.line_found);
  EXPECT_NEAR(m.e_d_m, jumped.y_m, 0.0005);
  EXPECT_NEAR(m.e_theta_rad, jumped.yaw_rad, deg_to_rad(0.2));
}

// Leaving the tape (or the tape ending) while tracking gives no line, never the old one.
TEST(TrackingLineEstimator, ReportsNoLineWhenTheTapeLeavesTheView) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  const pipeline::FrameRenderer renderer(camera, scene);
  TrackingLineEstimator tracking(camera, testing::hinted(scene));
  for (int k = 0; k < 4; ++k)
    ASSERT_TRUE(tracking.measure(renderer.render({1.0 + 0.03 * k, 0.0, 0.0}, {}, k), 0).line_found);
  // The tape ends at x = 8 m; the camera looks 0.3 m ahead of the vehicle.
  EXPECT_FALSE(tracking.measure(renderer.render({8.5, 0.0, 0.0}, {}, 5), 0).line_found);
  EXPECT_FALSE(tracking.measure(renderer.render({1.2, 0.5, 0.0}, {}, 6), 0).line_found);
}

// A second tape crossing the tracked one must not pull the measurement: every line reported
// while driving through a crossing is the straight tape, within 0.5 mm and 0.3 deg.
TEST(TrackingLineEstimator, ACrossingTapeDoesNotCaptureTheTrackedLine) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  pipeline::TapeStrip crossing = scene.tapes[0];
  crossing.path = control::Path::starting_at({2.5, -1.0, kPi / 2}).add_line(2.0);
  scene.tapes.push_back(crossing);
  const pipeline::FrameRenderer renderer(camera, scene);
  TrackingLineEstimator tracking(camera, testing::hinted(scene));
  int found = 0;
  for (int k = 0; k < 30; ++k) {
    const Pose2 pose{1.7 + 0.03 * k, 0.004 * std::sin(0.4 * k),
                     deg_to_rad(2.0 * std::cos(0.3 * k))};
    const LineMeasurement m = tracking.measure(renderer.render(pose, {0.3, 0.0, 0.0}, k), 0.1 * k);
    if (!m.line_found) continue;
    ++found;
    EXPECT_NEAR(m.e_d_m, pose.y_m, 0.0005) << "frame " << k;
    EXPECT_NEAR(m.e_theta_rad, pose.yaw_rad, deg_to_rad(0.3)) << "frame " << k;
  }
  EXPECT_GE(found, 20);  // the crossing may hide the line in a few frames, not in most
}

// The tape followed so far decides what a line is: with no width configured, after frames of 50
// mm tape a frame showing only a 20 mm strip (a floorboard seam, another tape) has no line, and
// says why; a fresh estimator takes the same frame's strip (so the memory made the difference);
// after TapeWidthMemory::kForgetAfterFrames frames without a line the strip is taken up.
TEST(TrackingLineEstimator, AWidthUnlikeTheTapeSeenSoFarIsNoLine) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].path = control::Path::starting_at({-2.0, 0.0, 0.0}).add_line(5.0);
  scene.tapes[0].width_m = 0.050;
  pipeline::TapeStrip strip = scene.tapes[0];
  strip.path = control::Path::starting_at({3.5, 0.03, 0.0}).add_line(5.0);
  strip.width_m = 0.020;
  scene.tapes.push_back(strip);
  const pipeline::FrameRenderer renderer(camera, scene);
  LineEstimator::Options any_width;
  any_width.tape.width_m = 0.0;
  TrackingLineEstimator tracking(camera, any_width);
  for (int k = 0; k < 10; ++k) {
    const LineMeasurement m =
        tracking.measure(renderer.render({1.0 + 0.03 * k, 0.0, 0.0}, {}, k), 0);
    ASSERT_TRUE(m.line_found) << "frame " << k;
    ASSERT_NEAR(m.tape_width_m, 0.050, 0.0025);
  }
  const cv::Mat seam_only = renderer.render({5.0, 0.0, 0.0}, {}, 10);
  LineDetection details;
  const LineMeasurement seam = tracking.measure(seam_only, 0, &details);
  EXPECT_FALSE(seam.line_found);
  EXPECT_NE(details.rejected_because.find("unlike the 50."), std::string::npos)
      << details.rejected_because;
  const LineMeasurement fresh = LineEstimator(camera, any_width).estimate(seam_only, 0);
  ASSERT_TRUE(fresh.line_found);
  EXPECT_NEAR(fresh.tape_width_m, 0.020, 0.001);
  EXPECT_NEAR(fresh.e_d_m, -0.03, 0.0005);  // the strip lies 30 mm to the vehicle's left
  int frames_until_taken = 1;
  for (; frames_until_taken < 40; ++frames_until_taken) {
    if (tracking.measure(renderer.render({5.0 + 0.01 * frames_until_taken, 0.0, 0.0}, {}, 11), 0)
            .line_found)
      break;
  }
  EXPECT_EQ(frames_until_taken, TapeWidthMemory::kForgetAfterFrames);
}

// A tape wider than the part of the view it leaves (80 mm, camera 0.12 m up: about 0.2 m across)
// while the vehicle drifts 2.5 mm a frame to its side: once its far edge has left the image, its
// one edge in view and the width measured in the frames before still give the line, within 0.5 mm
// and 0.2 deg of the truth (the tape's width is measured to about 0.2 mm, so the centre is off by
// about half that). An estimator without those frames finds no line in the last frame.
TEST(TrackingLineEstimator, ATapeWhoseFarEdgeLeftTheViewIsFollowedByItsOneEdge) {
  const CameraModel camera(testing::default_intrinsics(),
                           testing::straight_down_mount(0.30, 0.0, 0.12));
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].width_m = 0.080;
  const pipeline::FrameRenderer renderer(camera, scene);
  LineEstimator::Options any_width;
  any_width.tape.width_m = 0.0;
  TrackingLineEstimator tracking(camera, any_width);
  int one_edge = 0;
  cv::Mat last;
  for (int k = 0; k < 36; ++k) {
    const Pose2 pose{1.0 + 0.01 * k, 0.0025 * k, 0.0};
    last = renderer.render(pose, {0.1, 0.0, 0.0}, k);
    LineDetection details;
    const LineMeasurement m = tracking.measure(last, 0.1 * k, &details);
    ASSERT_TRUE(m.line_found) << "frame " << k << ": " << details.rejected_because;
    EXPECT_NEAR(m.e_d_m, pose.y_m, 0.0005) << "frame " << k;
    EXPECT_NEAR(m.e_theta_rad, 0.0, deg_to_rad(0.2)) << "frame " << k;
    if (details.one_edge) ++one_edge;
  }
  EXPECT_GE(one_edge, 8);
  EXPECT_FALSE(LineEstimator(camera, any_width).estimate(last, 0.0).line_found);
}

// The colour the tape followed was found on decides what tape is: after frames of dark tape on
// a grey floor, a frame showing only a light strip of the same width (the floor between the two
// legs of a fork of dark tape looks like that) has no line, where a fresh estimator takes the
// strip; after FollowHistory::kForgetAxisAfterFrames frames without a line it is taken up.
TEST(TrackingLineEstimator, AStripOfTheOppositeColourIsNoLineWhileTheTapeIsRemembered) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].path = control::Path::starting_at({-2.0, 0.0, 0.0}).add_line(5.0);
  scene.tapes[0].color_bgr = {30.0, 30.0, 30.0};
  pipeline::TapeStrip light = scene.tapes[0];
  light.path = control::Path::starting_at({3.5, 0.0, 0.0}).add_line(5.0);
  light.color_bgr = {235.0, 235.0, 235.0};
  scene.tapes.push_back(light);
  const pipeline::FrameRenderer renderer(camera, scene);
  LineEstimator::Options any_width;
  any_width.tape.width_m = 0.0;
  TrackingLineEstimator tracking(camera, any_width);
  for (int k = 0; k < 10; ++k)
    ASSERT_TRUE(tracking.measure(renderer.render({1.0 + 0.03 * k, 0.0, 0.0}, {}, k), 0).line_found)
        << "frame " << k;
  const cv::Mat light_only = renderer.render({5.0, 0.01, 0.0}, {}, 10);
  EXPECT_FALSE(tracking.measure(light_only, 0).line_found);
  const LineMeasurement fresh = LineEstimator(camera, any_width).estimate(light_only, 0);
  ASSERT_TRUE(fresh.line_found);
  EXPECT_NEAR(fresh.e_d_m, 0.01, 0.0005);
  int frames_until_taken = 1;
  for (; frames_until_taken < 50; ++frames_until_taken) {
    if (tracking.measure(renderer.render({5.0 + 0.01 * frames_until_taken, 0.01, 0.0}, {}, 11), 0)
            .line_found)
      break;
  }
  EXPECT_EQ(frames_until_taken, FollowHistory::kForgetAxisAfterFrames + 1);
}

}  // namespace
}  // namespace agv::perception
