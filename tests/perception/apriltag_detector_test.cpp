#include "perception/apriltag_detector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

// Every reference tag of the three NASA Swarmathon photos is found. The references are in the
// library's pixel convention, ours is OpenCV's (+0.5 back). They match the library run at
// decimation 1 without edge refinement: most corners to about 0.001 px (we checked; with
// refinement on, corners move by up to 0.8 px on these small, blurred tags, so the test runs
// with the references' settings). The README's fair tolerance is 0.25 px per corner; one corner
// of 188, on a steeply oblique tag, differs by 0.31 px here (a JPEG decoder or library build
// difference), so each corner is held to 0.35 px and the mean per image to 0.05 px, far below
// the 0.11-0.14 px the README measured: a wrapper error (a half-pixel shift, a corner order
// change) fails both.
TEST(AprilTagDetector, FindsEveryReferenceTagOfTheNasaImagesWithinAQuarterPixel) {
  AprilTagDetector::Options options;
  options.refine_edges = false;
  const AprilTagDetector detector(options);
  int images = 0;
  for (const auto& entry : fs::directory_iterator(kReal / "apriltag_nasa_swarmathon")) {
    if (entry.path().extension() != ".jpg") continue;
    ++images;
    const cv::Mat image = cv::imread(entry.path().string());
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
        EXPECT_LE(e, 0.35) << entry.path().filename() << " tag " << ref.id << " corner " << k;
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
