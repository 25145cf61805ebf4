#include "perception/line_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "perception/camera_file.h"
#include "pipeline/sim/frame_renderer.h"
#include "support/test_scenes.h"

namespace agv::perception {
namespace {

struct Accuracy {
  int frames = 0, found = 0;
  double rms_e_d_m = 0.0, rms_e_theta_rad = 0.0;
};

// Renders `frames` frames of a straight tape along the world x axis with the vehicle at random
// poses (|y| <= 30 mm, |yaw| <= 8 deg, moving at 0.3 m/s) and measures them.
Accuracy measure(const CameraModel& camera, const pipeline::Scene& scene,
                 const LineEstimator::Options& options, int frames, bool grey = false,
                 std::uint64_t seed = 11) {
  const pipeline::FrameRenderer renderer(camera, scene);
  const LineEstimator estimator(camera, options);
  cv::RNG rng(seed);
  Accuracy a;
  double sum_d = 0.0, sum_theta = 0.0;
  for (int i = 0; i < frames; ++i) {
    const Pose2 pose{rng.uniform(0.0, 3.0), rng.uniform(-0.03, 0.03),
                     deg_to_rad(rng.uniform(-8.0, 8.0))};
    cv::Mat frame = renderer.render(pose, {0.3, 0.0, 0.0}, i);
    if (grey) cv::cvtColor(frame, frame, cv::COLOR_BGR2GRAY);
    const LineMeasurement m = estimator.estimate(frame, 0.0);
    ++a.frames;
    if (!m.line_found) continue;
    ++a.found;
    // Truth for a tape along x: e_theta = yaw, e_d = y.
    sum_d += std::pow(m.e_d_m - pose.y_m, 2);
    sum_theta += std::pow(m.e_theta_rad - pose.yaw_rad, 2);
  }
  a.rms_e_d_m = std::sqrt(sum_d / std::max(1, a.found));
  a.rms_e_theta_rad = std::sqrt(sum_theta / std::max(1, a.found));
  return a;
}

// Issue 3's bar on rendered frames with the default noise: RMS <= 0.5 mm in e_d and <= 0.2 deg
// in e_theta, under two different mounts. Every frame shows the tape, so every frame must give
// a line.
TEST(LineEstimator, AccuracyOnRenderedFramesUnderTwoMounts) {
  const pipeline::Scene scene = testing::straight_tape_scene();
  for (const MountPose& mount : {testing::straight_down_mount(), testing::tilted_offset_mount()}) {
    const CameraModel camera(testing::default_intrinsics(), mount);
    const Accuracy a = measure(camera, scene, testing::hinted(scene), 60);
    EXPECT_EQ(a.found, a.frames) << mount.describe();
    EXPECT_LE(a.rms_e_d_m, 0.0005) << mount.describe();
    EXPECT_LE(rad_to_deg(a.rms_e_theta_rad), 0.2) << mount.describe();
  }
}

// Without a colour hint, on grey frames, dark tape on a light floor and light tape on a dark one.
TEST(LineEstimator, FindsTheTapeWithoutHintsForAnyPolarity) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  LineEstimator::Options no_hint;
  no_hint.tape.width_m = 0.025;
  pipeline::Scene blue = testing::straight_tape_scene();
  pipeline::Scene black_on_light = testing::straight_tape_scene();
  black_on_light.tapes[0].color_bgr = {30, 30, 30};
  black_on_light.floor.color_bgr = {200, 205, 210};
  pipeline::Scene white_on_dark = testing::straight_tape_scene();
  white_on_dark.tapes[0].color_bgr = {235, 235, 235};
  white_on_dark.floor.color_bgr = {70, 72, 75};
  for (const pipeline::Scene* scene : {&blue, &black_on_light, &white_on_dark}) {
    for (bool grey : {false, true}) {
      const Accuracy a = measure(camera, *scene, no_hint, 20, grey);
      EXPECT_EQ(a.found, a.frames) << "grey=" << grey;
      EXPECT_LE(a.rms_e_d_m, 0.0005) << "grey=" << grey;
      EXPECT_LE(rad_to_deg(a.rms_e_theta_rad), 0.2) << "grey=" << grey;
    }
  }
}

// The frame measured with a history of one frame whose line (`clean`'s, width_m wide) was found
// on `axis`.
LineMeasurement with_one_frame_history(const LineEstimator& estimator, const cv::Mat& frame,
                                       const LineDetection& clean, double width_m,
                                       const ContrastAxis& axis) {
  FollowHistory history;
  history.update(std::nullopt, clean.followed_model, width_m, axis);
  return estimator.estimate(frame, 0.0, nullptr, &history);
}

// A line within 0.3 mm and 0.2 deg of the reference.
void expect_as_reference(const LineMeasurement& m, const LineMeasurement& reference) {
  ASSERT_TRUE(m.line_found);
  EXPECT_NEAR(m.e_d_m, reference.e_d_m, 0.0003);
  EXPECT_NEAR(rad_to_deg(m.e_theta_rad), rad_to_deg(reference.e_theta_rad), 0.2);
}

// White tape on a light floor strewn with darker blotches: the colour axis chosen afresh is the
// blotches' (darker; they stand out more than the tape), and no line comes of it; the next axis
// that points another way in colour (lighter) is searched too and finds the tape where the same
// frame without blotches puts it (within 0.3 mm and 0.2 deg: the blotches keep a tape width away
// from it). With a history whose tape was found on the lighter axis, that axis alone is searched,
// with the same result.
TEST(LineEstimator, AFloorWhoseBlotchesOutshineTheTapeIsSearchedOnTheAxisTheTapeWasFoundOn) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].color_bgr = {235, 235, 235};
  scene.tapes[0].width_m = 0.014;
  scene.floor.color_bgr = {180, 180, 180};
  const pipeline::FrameRenderer renderer(camera, scene);
  const Pose2 pose{1.0, 0.012, deg_to_rad(3.0)};
  const cv::Mat clean = renderer.render(pose, {}, 1);
  LineEstimator::Options no_hint;
  no_hint.tape.width_m = 0.0;
  const LineEstimator estimator(camera, no_hint);
  LineDetection clean_detection;
  const LineMeasurement reference = estimator.estimate(clean, 0.0, &clean_detection);
  ASSERT_TRUE(reference.line_found);
  ASSERT_GT(clean_detection.axis.weights[0], 0.0f);  // the tape is lighter than the floor

  // Dark blotches 8-14 px across (10-18 mm here), none within 25 px of the tape.
  cv::Mat tape_mask = clean > cv::Scalar(215, 215, 215);
  cv::cvtColor(tape_mask, tape_mask, cv::COLOR_BGR2GRAY);
  cv::Mat away_from_tape;
  cv::distanceTransform(255 - tape_mask, away_from_tape, cv::DIST_L2, 3);
  cv::Mat blotchy = clean.clone();
  cv::RNG rng(5);
  for (int k = 0; k < 400; ++k) {
    const cv::Point centre(rng.uniform(0, blotchy.cols), rng.uniform(0, blotchy.rows));
    const int radius = rng.uniform(4, 8);
    if (away_from_tape.at<float>(centre) < 25.0f) continue;
    cv::circle(blotchy, centre, radius, cv::Scalar(95, 95, 95), cv::FILLED, cv::LINE_AA);
  }
  cv::Mat small;
  cv::resize(blotchy, small, blotchy.size() / 4, 0, 0, cv::INTER_AREA);
  const std::optional<ContrastAxis> first = choose_contrast_axis(small, std::nullopt, {2.0, 4.0});
  ASSERT_TRUE(first.has_value());
  ASSERT_LT(first->weights[0], 0.0f) << "the blotches' darker axis must win for this test";
  LineDetection fresh;
  const LineMeasurement without_history = estimator.estimate(blotchy, 0.0, &fresh);
  expect_as_reference(without_history, reference);
  EXPECT_GT(fresh.axis.weights[0], 0.0f);
  expect_as_reference(with_one_frame_history(estimator, blotchy, clean_detection,
                                             reference.tape_width_m, clean_detection.axis),
                      reference);
}

// Dark blue tape on a dark grey floor with a glare spot (the renderer's) beside it: the colour
// axis the frame suggests is the spot's, which points the tape's way in colour (both raise
// blue) and gives no line, nor does the next best. Before, a history whose tape was found on the
// blue axis searched the frame's best axis alone (it points the same way) and found nothing;
// the remembered axis is searched next, and finds the tape where the frame without glare puts it
// (within 0.3 mm and 0.2 deg: the spot keeps clear of it). agv evaluate, seed 12, sequence 6 (13
// mm dark blue tape, a glare spot on a dark floor): 86.7 % of the frames found before, 99.3 %.
TEST(LineEstimator, AGlareSpotThatOutshinesTheTapeLeavesTheRememberedAxisToSearch) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].color_bgr = {120, 40, 20};
  scene.tapes[0].width_m = 0.013;
  scene.floor.color_bgr = {60, 60, 62};
  const Pose2 pose{1.0, 0.0, deg_to_rad(2.0)};
  const cv::Mat clean = pipeline::FrameRenderer(camera, scene).render(pose, {}, 1);
  scene.effects.specular_strength = 90.0;
  scene.effects.specular_x = 0.3;
  scene.effects.specular_y = 0.5;
  const cv::Mat glare = pipeline::FrameRenderer(camera, scene).render(pose, {}, 1);
  LineEstimator::Options no_hint;
  no_hint.tape.width_m = 0.0;
  const LineEstimator estimator(camera, no_hint);
  LineDetection clean_detection;
  const LineMeasurement reference = estimator.estimate(clean, 0.0, &clean_detection);
  ASSERT_TRUE(reference.line_found);

  LineDetection fresh;
  ASSERT_FALSE(estimator.estimate(glare, 0.0, &fresh).line_found)
      << "the spot must defeat the search without a history for this test";
  ASSERT_GT(fresh.axis.weights.dot(clean_detection.axis.weights), 0.0f)
      << "the spot's axis must point the tape's way in colour for this test";
  // The frame's best axis remembered: searched alone.
  ASSERT_FALSE(
      with_one_frame_history(estimator, glare, clean_detection, reference.tape_width_m, fresh.axis)
          .line_found);
  expect_as_reference(with_one_frame_history(estimator, glare, clean_detection,
                                             reference.tape_width_m, clean_detection.axis),
                      reference);
}

// The axis is remembered from the frames that found a line and forgotten after
// kForgetAxisAfterFrames frames without one.
TEST(FollowHistory, RemembersTheColourAxisOfTheTapeFollowed) {
  FollowHistory history;
  ContrastAxis axis;
  axis.weights = {0.01f, 0.01f, 0.01f};
  history.update(std::nullopt, CurveModel{}, 0.02, axis);
  ASSERT_TRUE(history.axis.has_value());
  for (int k = 0; k < FollowHistory::kForgetAxisAfterFrames; ++k) {
    history.update(std::nullopt, std::nullopt);
    ASSERT_TRUE(history.axis.has_value()) << k;
  }
  history.update(std::nullopt, std::nullopt);
  EXPECT_FALSE(history.axis.has_value());
}

// Frames of a straight tape width_m wide seen straight down from height_m, the vehicle off by
// up to offset_m and yaw_deg, measured without a width given: every frame a line, the width
// within 5 % and issue 3's accuracy (0.5 mm, 0.2 deg RMS).
void expect_width_measured(double width_m, double height_m, double offset_m, double yaw_deg) {
  const CameraModel camera(testing::default_intrinsics(),
                           testing::straight_down_mount(0.30, 0.0, height_m));
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].width_m = width_m;
  LineEstimator::Options unknown;
  unknown.tape.width_m = 0.0;
  const pipeline::FrameRenderer renderer(camera, scene);
  const LineEstimator estimator(camera, unknown);
  int found = 0;
  double worst_width_error = 0.0, d2 = 0.0, t2 = 0.0;
  const int frames = 12;
  for (int i = 0; i < frames; ++i) {
    const Pose2 pose{0.2 * i, offset_m * std::sin(i), deg_to_rad(yaw_deg) * std::cos(i)};
    const LineMeasurement m = estimator.estimate(renderer.render(pose, {0.3, 0.0, 0.0}, i), 0.0);
    if (!m.line_found) continue;
    ++found;
    worst_width_error = std::max(worst_width_error, std::abs(m.tape_width_m - width_m) / width_m);
    d2 += std::pow(m.e_d_m - pose.y_m, 2);
    t2 += std::pow(m.e_theta_rad - pose.yaw_rad, 2);
  }
  const std::string label = std::to_string(1e3 * width_m) + " mm";
  EXPECT_EQ(found, frames) << label;
  EXPECT_LE(worst_width_error, 0.05) << label;
  EXPECT_LE(std::sqrt(d2 / std::max(1, found)), 0.0005) << label;
  EXPECT_LE(rad_to_deg(std::sqrt(t2 / std::max(1, found))), 0.2) << label;
}

// No width configured (width 0: unknown): tape from 8 to 150 mm wide is found and its width
// measured. The camera is higher for the widest tapes so that the tape fills at most half the
// view (0.15 m up sees 0.19 m across; 0.30 m up, 0.37 m). Bars: every frame a line, the width
// within 5 % (the tape's edges are found to a tenth of a pixel: 1 mm px at 0.30 m, a 8 mm tape
// 5 px wide at 0.15 m), and issue 3's accuracy.
TEST(LineEstimator, MeasuresATapeWidthThatWasNotGiven) {
  for (double width_m : {0.008, 0.015, 0.030, 0.060, 0.100, 0.150})
    expect_width_measured(width_m, width_m > 0.07 ? 0.30 : 0.15, 0.02, 6.0);
}

// Wide tape seen from low down without a width given: 90 mm tape from 0.17 m up, where the view
// is 0.21 m across and the tape fills 0.43 of it, wider than the 64 mm bar that the ladder of
// 8-128 mm bars keeps (the 128 mm one does not fit): where the ladder's candidate is refused for
// sparse evidence, the widest bar that fits answers to it. Bars as above (every frame, width within
// 5 %, issue 3's accuracy); without that bar 6 of the 12 frames gave a line. (100 mm tape from
// there, half the view: the ladder finds a line along part of it, 40 % narrower, and the widest bar
// is not tried.)
TEST(LineEstimator, AWideTapeFromALowCameraIsFound) {
  expect_width_measured(0.090, 0.17, 0.01, 4.0);
}

// Tape wider than any bar that fits the view, without a width given: 100 mm tape from 0.17 m
// up (half the view) and 120 mm from 0.15 m up (0.63 of the view's 0.19 m). A bar answers to
// such tape only next to its edges, one edge a region; the contrast's plateau is the region that
// holds it. Bars as above (every frame, width within 5 %, issue 3's accuracy). Without the
// plateau search the 120 mm tape gave no line, and the 100 mm tape gave one on 8 of 12 frames,
// a strip along one edge (34 % narrower, 6 mm RMS off).
TEST(LineEstimator, TapeFillingMoreThanHalfTheViewIsFoundByItsPlateau) {
  expect_width_measured(0.100, 0.17, 0.01, 4.0);
  expect_width_measured(0.120, 0.15, 0.01, 4.0);
}

// White tape 97 mm wide on a dark floor seen from 0.13 m up (half the view) with the vehicle's
// hard shadow across it: the bars answer to the band between the shadow's edge and a tape edge,
// 40-50 mm wide, not along the tape. Where the tape's width settled before (97 mm) and lines of
// other widths since have unsettled it (a fork's overlap), such a band is unlike the tape and the
// plateau of the width last settled is taken. Bars: a line within 2 mm and 1 deg at the origin
// and of the tape's width within 5 mm (the band followed was 260 mm off, 53 deg, 41 mm wide).
// Left: with the shadow's edge in 10 other places (directions 0.3-2.8 rad either way, offsets
// 0-0.4) the tape is still missed, or a band or a line of one edge per chord followed, settled
// width or not (agv evaluate seed 18, sequence 4).
TEST(LineEstimator, AShadowsEdgeAcrossWideTapeIsNotTakenForTheTape) {
  const CameraModel camera(testing::default_intrinsics(),
                           testing::straight_down_mount(0.30, 0.0, 0.13));
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].width_m = 0.097;
  scene.tapes[0].color_bgr = {225.0, 228.0, 230.0};
  scene.floor.color_bgr = {60.0, 62.0, 64.0};
  scene.effects.shadow_darkness = 0.45;
  scene.effects.shadow_softness = 0.01;
  scene.effects.shadow_direction_rad = 2.2;
  scene.effects.shadow_offset = 0.0;
  FollowHistory history;
  for (int i = 0; i < 5; ++i) history.width.update(0.097);
  for (double w : {0.103, 0.109, 0.116, 0.123, 0.130, 0.137}) history.width.update(w);
  for (int i = 0; i < 9; ++i) history.width.update(0.097);
  ASSERT_FALSE(history.width.settled_width_m().has_value());
  LineEstimator::Options options = testing::hinted(scene);
  options.tape.width_m = 0.0;
  const LineEstimator estimator(camera, options);
  const pipeline::FrameRenderer renderer(camera, scene);
  const struct {
    Pose2 pose;
    int frame;  // the render's noise
  } cases[] = {{{0.0, 0.0, deg_to_rad(1.0)}, 0}, {{0.4, 0.001, deg_to_rad(-0.5)}, 4}};
  for (const auto& c : cases) {
    const LineMeasurement m = estimator.estimate(renderer.render(c.pose, {0.3, 0.0, 0.0}, c.frame),
                                                 0.0, nullptr, &history);
    ASSERT_TRUE(m.line_found) << c.frame;
    EXPECT_NEAR(m.e_d_m, c.pose.y_m, 0.002) << c.frame;
    EXPECT_NEAR(rad_to_deg(m.e_theta_rad), rad_to_deg(c.pose.yaw_rad), 1.0) << c.frame;
    EXPECT_NEAR(m.tape_width_m, 0.097, 0.005) << c.frame;
  }
}

// A line running into an arc of R 0.3 m in the middle of the view (0.30 m ahead), the vehicle
// on the line: the errors at the origin are the line's, carried back (the arc starts ahead of
// the vehicle), not those of one arc fitted across the joint. Bars: within 1 mm and 0.5 deg on
// every frame (one arc through the joint is 2-5 mm and 1-3 deg off here).
TEST(LineEstimator, ALineIntoAnArcInViewIsCarriedBackAsTheLine) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].path =
      control::Path::starting_at({-2.0, 0.0, 0.0}).add_line(2.3).add_arc(0.3, deg_to_rad(90.0));
  const pipeline::FrameRenderer renderer(camera, scene);
  const LineEstimator estimator(camera, testing::hinted(scene));
  for (int i = 0; i < 6; ++i) {
    const Pose2 pose{-0.02 + 0.01 * i, 0.004 * std::sin(i), deg_to_rad(2.0) * std::cos(i)};
    const LineMeasurement m = estimator.estimate(renderer.render(pose, {0.3, 0.0, 0.0}, i), 0.0);
    ASSERT_TRUE(m.line_found) << i;
    // Truth for the line along x: e_theta = yaw, e_d = y.
    EXPECT_NEAR(m.e_d_m, pose.y_m, 0.001) << i;
    EXPECT_NEAR(rad_to_deg(m.e_theta_rad), rad_to_deg(pose.yaw_rad), 0.5) << i;
  }
}

// A configured width is a hint: 50 mm tape with 25 mm configured (the real case of a user who
// kept the default) is found on every frame and its width measured (within 5 %, as above).
TEST(LineEstimator, AConfiguredWidthIsAHint) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  pipeline::Scene scene = testing::straight_tape_scene();
  scene.tapes[0].width_m = 0.05;
  LineEstimator::Options wrong;
  wrong.tape.width_m = 0.025;
  const pipeline::FrameRenderer renderer(camera, scene);
  const LineEstimator estimator(camera, wrong);
  for (int i = 0; i < 8; ++i) {
    const Pose2 pose{0.2 * i, 0.02 * std::sin(i), deg_to_rad(6.0) * std::cos(i)};
    const LineMeasurement m = estimator.estimate(renderer.render(pose, {0.3, 0.0, 0.0}, i), 0.0);
    ASSERT_TRUE(m.line_found) << i;
    EXPECT_NEAR(m.tape_width_m, 0.05, 0.0025) << i;
    EXPECT_NEAR(m.e_d_m, pose.y_m, 0.001) << i;
  }
}

// Frames with no tape must never give a line, whatever the floor.
TEST(LineEstimator, NeverReportsALineOnFramesWithoutTape) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  for (int variant = 0; variant < 3; ++variant) {
    pipeline::Scene scene = testing::straight_tape_scene(100 + variant);
    scene.tapes[0].path = control::Path::starting_at({50.0, 50.0, 0.0}).add_line(1.0);  // far away
    scene.floor.texture_contrast = 0.05 + 0.1 * variant;
    scene.effects.noise_sigma = 2.0 + 3.0 * variant;
    LineEstimator::Options hint = testing::hinted(scene), no_hint;
    no_hint.tape.width_m = 0.025;
    for (const LineEstimator::Options* options : {&hint, &no_hint}) {
      const Accuracy a = measure(camera, scene, *options, 15, false, 50 + variant);
      EXPECT_EQ(a.found, 0) << "variant " << variant
                            << (options->tape.color_bgr ? " with hint" : " without hint");
    }
  }
}

// The same from 0.17 m up without a width given, on floors of coarser texture, where the search
// may also use the widest bar beyond the ladder (see AWideTapeFromALowCameraIsFound). (The frame
// of agv evaluate's seed 2 on which that bar, tried after any refusal, gave a line is not
// reproduced here: these pass with it too.)
TEST(LineEstimator, NeverReportsALineOnFramesWithoutTapeFromALowCamera) {
  const CameraModel camera(testing::default_intrinsics(),
                           testing::straight_down_mount(0.30, 0.0, 0.17));
  for (int variant = 0; variant < 4; ++variant) {
    pipeline::Scene scene = testing::straight_tape_scene(200 + variant);
    scene.tapes[0].path = control::Path::starting_at({50.0, 50.0, 0.0}).add_line(1.0);  // far away
    scene.floor.texture_contrast = 0.1 + 0.1 * variant;
    scene.effects.noise_sigma = 2.0 + 2.0 * variant;
    LineEstimator::Options unknown;
    unknown.tape.width_m = 0.0;
    const Accuracy a = measure(camera, scene, unknown, 25, false, 70 + variant);
    EXPECT_EQ(a.found, 0) << "variant " << variant;
  }
}

TEST(LineEstimator, RejectsFramesOfTheWrongSizeOrType) {
  const CameraModel camera(testing::default_intrinsics(), testing::straight_down_mount());
  const LineEstimator estimator(camera, LineEstimator::Options{});
  LineDetection details;
  EXPECT_FALSE(estimator.estimate(cv::Mat(), 0.0, &details).line_found);
  EXPECT_NE(details.rejected_because.find("empty"), std::string::npos);
  EXPECT_FALSE(
      estimator.estimate(cv::Mat(240, 320, CV_8UC3, cv::Scalar(100, 100, 100)), 0.0, &details)
          .line_found);
  EXPECT_NE(details.rejected_because.find("size"), std::string::npos);
  EXPECT_FALSE(
      estimator.estimate(cv::Mat(480, 640, CV_16UC1, cv::Scalar(100)), 0.0, &details).line_found);
  EXPECT_NE(details.rejected_because.find("8-bit"), std::string::npos);
}

}  // namespace
}  // namespace agv::perception

namespace agv::perception {
namespace {

// A Y fork at its split, rendered by `agv evaluate`'s sequences (seed 1, sequence 8, frame 105:
// 44 mm red tape on a dark floor, camera 0.13 m up, the branch leaving 47 deg to the right on
// R 0.75 m; the vehicle 1.1 mm right of the branch it drives, turned -0.57 deg; files in
// data/fork_split). Where the legs still touch, chords from one leg's outer edge to the other's
// read as tape a width aside from both, with no chord of one tape's width; that reading is no
// line (it was followed: 43 mm off), and the way chosen (right) is measured within 2 mm.
TEST(LineEstimator, AForkSplitGivesNoPhantomTapeBetweenItsLegs) {
  const std::string dir = std::string(AGV_SOURCE_DIR) + "/tests/perception/data/fork_split/";
  const CameraFile file = load_camera_file(dir + "camera.yaml");
  const cv::Mat frame = cv::imread(dir + "frame105.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(frame.empty());
  LineEstimator::Options options;
  options.tape.width_m = 0.0;
  options.branch = BranchChoice::kRight;
  const LineEstimator estimator(camera_model_of(file, dir + "camera.yaml"), options);
  LineDetection detection;
  const LineMeasurement m = estimator.estimate(frame, 0.0, &detection);
  ASSERT_TRUE(m.line_found) << detection.rejected_because;
  for (const DetectedLine& line : detection.lines) EXPECT_FALSE(line.clean_chords.empty());
  EXPECT_NEAR(m.e_d_m, -0.0011, 0.002);
}

}  // namespace
}  // namespace agv::perception
