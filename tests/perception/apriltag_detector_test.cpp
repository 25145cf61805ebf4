#include "perception/apriltag_detector.h"

#include "common/angles.h"
#include "common/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace agv::perception {
namespace {

namespace fs = std::filesystem;
const fs::path kReal = fs::path(AGV_SHARED_DIR) / "data" / "real";

struct ReferenceTag {
  int id;
  std::array<cv::Point2d, 4> corners;  // the library's pixel convention
};

// Lines "id, (x y), (x y), (x y), (x y)".
std::vector<ReferenceTag> read_reference(const fs::path& file) {
  std::ifstream in(file);
  std::vector<ReferenceTag> tags;
  for (std::string line; std::getline(in, line);) {
    for (char& c : line) {
      if (c == '(' || c == ')' || c == ',') c = ' ';
    }
    std::istringstream fields(line);
    ReferenceTag tag{};
    if (!(fields >> tag.id)) continue;
    bool complete = true;
    for (cv::Point2d& corner : tag.corners) complete = complete && (fields >> corner.x >> corner.y);
    if (complete) tags.push_back(tag);
  }
  return tags;
}

// Every reference tag of the three NASA Swarmathon photos is found, each corner within the
// README's fair 0.25 px. The references are in the library's pixel convention, ours is
// OpenCV's (+0.5 back). They match the library run at decimation 1 without edge refinement on
// the JPEG decoded straight to grey (libjpeg's own luma, as the library's demo reads images):
// most corners to about 0.001 px. Decoding to colour and converting with OpenCV's weights moves
// one oblique corner by 0.31 px; edge refinement (on by default) moves corners of these small,
// blurred tags by up to 0.8 px, so the test runs with the references' settings. The mean per
// image is held to 0.05 px, far below the 0.11-0.14 px the README measured: a wrapper error (a
// half-pixel shift, a corner order change) fails both.
TEST(AprilTagDetector, FindsEveryReferenceTagOfTheNasaImagesWithinAQuarterPixel) {
  AprilTagDetector::Options options;
  options.refine_edges = false;
  const AprilTagDetector detector(options);
  int images = 0;
  for (const auto& entry : fs::directory_iterator(kReal / "apriltag_nasa_swarmathon")) {
    if (entry.path().extension() != ".jpg") continue;
    ++images;
    const cv::Mat image = cv::imread(entry.path().string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << entry.path();
    const std::vector<ReferenceTag> reference =
        read_reference(fs::path(entry.path()).replace_extension(".txt"));
    ASSERT_FALSE(reference.empty()) << entry.path();
    const std::vector<TagDetection> found = detector.detect(image);
    double sum_px = 0.0, worst_px = 0.0;
    int matched = 0;
    for (const ReferenceTag& ref : reference) {
      const TagDetection* best = nullptr;
      double best_px = 1e9;
      for (const TagDetection& tag : found) {
        if (tag.id != ref.id) continue;
        double worst = 0.0;
        for (int k = 0; k < 4; ++k) {
          const cv::Point2d ours = tag.corners_px[k] + cv::Point2d(0.5, 0.5);
          worst = std::max(worst, cv::norm(ours - ref.corners[k]));
        }
        if (worst < best_px) {
          best_px = worst;
          best = &tag;
        }
      }
      ASSERT_NE(best, nullptr) << entry.path().filename() << ": tag " << ref.id << " not found";
      for (int k = 0; k < 4; ++k) {
        const double e = cv::norm(best->corners_px[k] + cv::Point2d(0.5, 0.5) - ref.corners[k]);
        EXPECT_LE(e, 0.25) << entry.path().filename() << " tag " << ref.id << " corner " << k;
        sum_px += e;
        worst_px = std::max(worst_px, e);
        ++matched;
      }
    }
    EXPECT_EQ(found.size(), reference.size()) << entry.path().filename();
    EXPECT_LE(sum_px / matched, 0.05) << entry.path().filename();
    std::printf("%s: %zu tags, mean corner error %.3f px, worst %.3f px\n",
                entry.path().filename().c_str(), reference.size(), sum_px / matched, worst_px);
  }
  EXPECT_EQ(images, 3);
}

// The yaw of a tag pose as the rotation-set test measures it: the angle between the tag's
// normal and the line of sight to it, about the camera's vertical axis (degrees, the file
// names' sign; the line of sight takes out the tag's ~2.3 deg offset from the optical axis).
double yaw_to_line_of_sight_deg(const cv::Vec3d& rotation, const cv::Vec3d& translation_m) {
  cv::Matx33d r;
  cv::Rodrigues(rotation, r);
  const double normal_deg = rad_to_deg(std::atan2(r(0, 2), r(2, 2)));
  const double line_of_sight_deg = rad_to_deg(std::atan2(translation_m[0], translation_m[2]));
  return -(normal_deg - line_of_sight_deg);
}

// apriltag_rotation_set: one tag (id 76, 65 mm) turned about the vertical axis through its
// centre by the yaw in the file name (real Duckiebot images; the tag turned by hand - the
// dataset's author tested them with a 5 deg tolerance). Pose from the detected corners: IPPE
// for a square, test_info.yaml's K, the solution with the smaller reprojection error.
// Tolerance: the 2 deg where the tag is turned >= 30 deg (10 images); nearer face-on,
// 2 deg or 2 sigma of the yaw that the image itself allows, whichever is larger. sigma = (d yaw / d
// corners, from the pose Jacobian) x (the image's own corner misfit: reprojection RMS x sqrt(8 / 2)
// for 8 coordinates and 6 pose parameters). Near face-on a 100-pixel tag's yaw moves its corners by
// only ~0.3 px per degree (about 3 deg per px), and these images misfit a square by ~1 px there
// (lens model, printing): sigma 2.4-6.4 deg at -20..+10 deg, 0.3-1.6 deg at |yaw| >= 30 deg
// (measured). The corners must still fit a square to 1.5 px, so a detector that returns bad corners
// fails.
TEST(AprilTagDetector, YawOfTheRotationSetMatchesTheFileNames) {
  const AprilTagDetector detector(AprilTagDetector::Options{});
  const cv::Matx33d camera(329.8729619143081, 0.0, 528.0, 0.0, 332.94611303946357, 396.0, 0.0, 0.0,
                           1.0);
  const double half_m = 0.065 / 2;
  const std::vector<cv::Point3d> square{{-half_m, half_m, 0.0},
                                        {half_m, half_m, 0.0},
                                        {half_m, -half_m, 0.0},
                                        {-half_m, -half_m, 0.0}};

  for (int yaw_deg = -70; yaw_deg <= 70; yaw_deg += 10) {
    const fs::path file = kReal / "apriltag_rotation_set" /
                          ("test_image_rotation_" + std::to_string(yaw_deg) + ".png");
    const cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << file;
    const std::vector<TagDetection> found = detector.detect(image);
    ASSERT_EQ(found.size(), 1u) << file;
    EXPECT_EQ(found[0].id, 76);
    const std::vector<cv::Point2d> corners(found[0].corners_px.begin(), found[0].corners_px.end());
    std::vector<cv::Mat> rotations, translations;
    cv::Mat reprojection_px;
    cv::solvePnPGeneric(square, corners, camera, cv::noArray(), rotations, translations, false,
                        cv::SOLVEPNP_IPPE_SQUARE, cv::noArray(), cv::noArray(), reprojection_px);
    ASSERT_FALSE(rotations.empty()) << file;
    const cv::Vec3d rotation(rotations[0]), translation_m(translations[0]);
    const double measured_deg = yaw_to_line_of_sight_deg(rotation, translation_m);
    const double misfit_px = reprojection_px.at<double>(0);
    EXPECT_LE(misfit_px, 1.5) << file;

    // sigma: the pose covariance per px^2 of corner noise, (J^T J)^-1, carried to the yaw.
    std::vector<cv::Point2d> projected;
    cv::Mat jacobian;
    cv::projectPoints(square, rotation, translation_m, camera, cv::noArray(), projected, jacobian);
    const cv::Mat pose_jacobian = jacobian.colRange(0, 6);
    const cv::Mat covariance_per_px2 = (pose_jacobian.t() * pose_jacobian).inv();
    cv::Mat yaw_gradient(1, 6, CV_64F);
    for (int i = 0; i < 6; ++i) {
      const double step = 1e-6;
      cv::Vec3d r_plus = rotation, r_minus = rotation, t_plus = translation_m,
                t_minus = translation_m;
      (i < 3 ? r_plus[i] : t_plus[i - 3]) += step;
      (i < 3 ? r_minus[i] : t_minus[i - 3]) -= step;
      yaw_gradient.at<double>(i) =
          (yaw_to_line_of_sight_deg(r_plus, t_plus) - yaw_to_line_of_sight_deg(r_minus, t_minus)) /
          (2 * step);
    }
    const double deg_per_px =
        std::sqrt(cv::Mat(yaw_gradient * covariance_per_px2 * yaw_gradient.t()).at<double>(0));
    const double sigma_deg = deg_per_px * misfit_px * std::sqrt(8.0 / 2.0);
    const double tolerance_deg = std::abs(yaw_deg) >= 30 ? 2.0 : std::max(2.0, 2.0 * sigma_deg);

    EXPECT_NEAR(measured_deg, yaw_deg, tolerance_deg) << file << " sigma " << sigma_deg;
    std::printf(
        "rotation set: yaw %+3d deg measured %+7.2f deg (reprojection %.2f px, "
        "%.1f deg/px, sigma %.2f deg)\n",
        yaw_deg, measured_deg, misfit_px, deg_per_px, sigma_deg);
  }
}

// Real photos other than shared/data/real (datasets/tags/marburg_36h11: a Nikon D80's photos of a
// printed tag36h11 sheet face on, close, and oblique with shallow focus; LGPL-2.1, README beside
// them) against an independent detector: OpenCV's ArUco module with DICT_APRILTAG_36h11 (its own
// quad finder, decoder and sub-pixel refinement: cornerSubPix on the corners, not AprilTag's edge
// fit). Its bitmap is the library's tag turned by 180 deg, so its corner k is ours [1, 0, 3, 2][k];
// both in OpenCV's pixel convention. Every tag the reference finds must be found with its id.
// Tolerances: on the sharp photos (sheet, close) 0.5 px median and 0.75 px at the 95th
// percentile: a wrapper error (the +0.5 px convention: 0.71 px on every corner; a corner order
// turned by one: the tag's side) fails both, while the two refinements may differ by a few
// tenths. On the oblique photo the tags' far edges are out of focus and the two refinements
// disagree by about 1 px (median 1.09, p95 4.2 px measured); a straight-line check of the
// sheet's rows and columns (not kept) found neither more right (1.9 px ours, 1.5 px ArUco over
// the same tags, and 1.0 against 0.9 px on the sharp sheet, where paper and lens bend the rows),
// so there only the median is held, to 1.5 px, against a wrong order or a wrong tag.
TEST(AprilTagDetector, RealPhotosAgreeWithOpenCvsArucoApriltagDictionary) {
  const fs::path folder = fs::path(AGV_SOURCE_DIR) / "datasets" / "tags" / "marburg_36h11";
  const AprilTagDetector detector;  // agv detect-tags' defaults
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_APRILTAG_36h11);
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  parameters->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  const int kOursOfTheirs[4] = {1, 0, 3, 2};
  struct Photo {
    const char* name;
    bool sharp;
  };
  int reference_tags = 0;
  for (const Photo photo :
       {Photo{"sheet.jpg", true}, Photo{"close.jpg", true}, Photo{"oblique.jpg", false}}) {
    const cv::Mat image = cv::imread((folder / photo.name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << folder / photo.name;
    std::vector<std::vector<cv::Point2f>> their_corners;
    std::vector<int> their_ids;
    cv::aruco::detectMarkers(image, dictionary, their_corners, their_ids, parameters);
    const std::vector<TagDetection> ours = detector.detect(image);
    std::vector<double> differences_px;
    for (size_t i = 0; i < their_ids.size(); ++i) {
      const auto same = std::find_if(ours.begin(), ours.end(),
                                     [&](const TagDetection& t) { return t.id == their_ids[i]; });
      ASSERT_NE(same, ours.end()) << photo.name << ": tag " << their_ids[i] << " not found";
      for (int k = 0; k < 4; ++k) {
        const cv::Point2d theirs(their_corners[i][k].x, their_corners[i][k].y);
        differences_px.push_back(cv::norm(same->corners_px[kOursOfTheirs[k]] - theirs));
      }
    }
    reference_tags += static_cast<int>(their_ids.size());
    const double median_px = percentile(differences_px, 0.5);
    const double p95_px = percentile(differences_px, 0.95);
    std::printf("%s: reference %zu tags, ours %zu, corner difference median %.3f px, p95 %.3f px\n",
                photo.name, their_ids.size(), ours.size(), median_px, p95_px);
    ASSERT_FALSE(differences_px.empty()) << photo.name;
    if (photo.sharp) {
      EXPECT_LE(median_px, 0.5) << photo.name;
      EXPECT_LE(p95_px, 0.75) << photo.name;
    } else {
      EXPECT_LE(median_px, 1.5) << photo.name;
    }
  }
  EXPECT_GE(reference_tags, 90);  // 80 on the sheet, 3 close, 17 oblique
}

TEST(AprilTagDetector, RejectsUnknownFamiliesAndDrawsTags) {
  AprilTagDetector::Options options;
  options.family = "tag99h99";
  EXPECT_THROW(AprilTagDetector{options}, std::invalid_argument);
  options.max_hamming = 0;  // the big families' decode tables for 2 bits take a minute to build
  for (const std::string& family : AprilTagDetector::families()) {
    options.family = family;
    const AprilTagDetector detector(options);
    EXPECT_GT(detector.tag_count(), 0) << family;
    EXPECT_FALSE(detector.tag_image(0).empty()) << family;
  }
  // A drawn tag36h11 tag, enlarged with a white margin, is detected with its id.
  const AprilTagDetector detector;
  cv::Mat tag = detector.tag_image(5), big;
  cv::resize(tag, big, cv::Size(), 20, 20, cv::INTER_NEAREST);
  cv::copyMakeBorder(big, big, 40, 40, 40, 40, cv::BORDER_CONSTANT, cv::Scalar(255));
  const std::vector<TagDetection> found = detector.detect(big);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 5);
}

}  // namespace
}  // namespace agv::perception
