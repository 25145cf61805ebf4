#include "tools/detect_tags_command.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "common/input_error.h"
#include "perception/apriltag_detector.h"
#include "pipeline/dataset.h"
#include "pipeline/evaluation/output_folder.h"

namespace agv::tools {
namespace fs = std::filesystem;

void add_detect_tags_command(CLI::App& app, DetectTagsArgs& args) {
  CLI::App* sub = app.add_subcommand(
      "detect-tags",
      "Finds every AprilTag in a folder of images or a video (AprilTag 3 library). Writes "
      "detections.csv (file,family,id,hamming,decision_margin,x0_px,y0_px,...,y3_px: corners in "
      "the library's order, OpenCV's pixel convention) and one annotated PNG per image (outline, "
      "corner order 0-3, id and decision margin); prints one line: images, tags, ids seen. Check "
      "prints and lighting with it before `agv calibrate mount`.");
  sub->add_option("input", args.input, "Folder of PNG/JPEG images, or a video file")->required();
  sub->add_option("--family", args.family,
                  "Tag family: tag36h11, tag25h9, tag16h5, tagCircle21h7, tagCircle49h12, "
                  "tagStandard41h12, tagStandard52h13")
      ->capture_default_str();
  sub->add_option("--out", args.out,
                  "Output folder (default runs/<date>-<time>); an existing one is replaced only "
                  "with --force");
  sub->add_flag("!--no-refine-edges", args.refine_edges,
                "Corners from the quads alone, without the library's edge refinement (which "
                "moves corners of small, blurred tags by up to about 1 px)");
  sub->add_flag("--force", args.force, "Replace an existing output folder");
  sub->add_flag("--json", args.json, "Print the summary as JSON");
  sub->add_flag("--quiet", args.quiet, "No progress");
}

namespace {

cv::Mat annotated(const cv::Mat& image, const std::vector<perception::TagDetection>& tags) {
  cv::Mat out;
  if (image.channels() == 1) {
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  } else {
    out = image.clone();
  }
  const double scale = std::max(0.4, out.cols / 1600.0);
  for (const perception::TagDetection& t : tags) {
    for (int k = 0; k < 4; ++k) {
      cv::line(out, t.corners_px[k], t.corners_px[(k + 1) % 4], cv::Scalar(0, 255, 0), 2,
               cv::LINE_AA);
      cv::putText(out, std::to_string(k), t.corners_px[k] + cv::Point2d(3, -3),
                  cv::FONT_HERSHEY_SIMPLEX, 0.8 * scale, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    }
    cv::putText(out, cv::format("id %d m %.0f", t.id, t.decision_margin),
                t.centre + cv::Point2d(-20 * scale, 5), cv::FONT_HERSHEY_SIMPLEX, 0.9 * scale,
                cv::Scalar(255, 0, 0), 2, cv::LINE_AA);
  }
  return out;
}

}  // namespace

int run_detect_tags(const DetectTagsArgs& args) {
  perception::AprilTagDetector::Options options;
  options.family = args.family;
  options.refine_edges = args.refine_edges;
  std::unique_ptr<perception::AprilTagDetector> made;
  try {
    made = std::make_unique<perception::AprilTagDetector>(options);
  } catch (const std::invalid_argument& e) {
    throw InputError("--family " + args.family + ": " + e.what());
  }
  const perception::AprilTagDetector& detector = *made;
  if (!fs::exists(args.input)) throw InputError(args.input + ": no such folder or video file");
  pipeline::OutputFolder folder(args.out, "detections.csv", args.force);

  std::ofstream csv(folder.file("detections.csv"));
  csv << "file,family,id,hamming,decision_margin,x0_px,y0_px,x1_px,y1_px,x2_px,y2_px,x3_px,"
         "y3_px\n";
  int images = 0, tags = 0;
  std::set<int> ids;
  nlohmann::json per_image = nlohmann::json::array();
  // `grey`: the image decoded straight to grey where it comes from a file (the decoder's own
  // luma, as the AprilTag library's tools read images), else converted.
  auto detect = [&](const cv::Mat& image, cv::Mat grey, const std::string& name) {
    if (grey.empty()) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    const std::vector<perception::TagDetection> found = detector.detect(grey);
    for (const perception::TagDetection& t : found) {
      csv << name << ',' << t.family << ',' << t.id << ',' << t.hamming << ','
          << cv::format("%.3f", t.decision_margin);
      for (const cv::Point2d& c : t.corners_px) csv << cv::format(",%.4f,%.4f", c.x, c.y);
      csv << '\n';
      ids.insert(t.id);
    }
    cv::imwrite(folder.file(fs::path(name).stem().string() + "_tags.png").string(),
                annotated(image, found));
    ++images;
    tags += static_cast<int>(found.size());
    nlohmann::json ids_here = nlohmann::json::array();
    for (const perception::TagDetection& t : found) ids_here.push_back(t.id);
    per_image.push_back({{"file", name}, {"tags", found.size()}, {"ids", ids_here}});
    if (!args.quiet && !args.json)
      std::fprintf(stderr, "\r%s: %zu tags   ", name.c_str(), found.size());
  };
  if (fs::is_directory(args.input)) {
    const std::vector<fs::path> files = pipeline::image_files_in(args.input);
    if (files.empty()) throw InputError(args.input + ": no images (PNG, JPEG, BMP, TIFF) in it");
    for (const fs::path& file : files) {
      const cv::Mat image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
      if (image.empty() || image.depth() != CV_8U)
        throw InputError(file.string() + ": cannot be read as an 8-bit image");
      cv::Mat bgr = image;
      if (image.channels() == 4) cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
      detect(bgr, cv::imread(file.string(), cv::IMREAD_GRAYSCALE), file.filename().string());
    }
  } else {
    cv::VideoCapture video(args.input);
    if (!video.isOpened()) throw InputError(args.input + ": cannot be opened as a video");
    cv::Mat frame;
    for (int index = 0; video.read(frame); ++index)
      detect(frame, cv::Mat(), cv::format("frame_%06d.png", index));
    if (images == 0) throw InputError(args.input + ": the video has no frames");
  }
  if (!args.quiet && !args.json) std::fprintf(stderr, "\n");
  csv.close();
  if (!csv) throw InputError(folder.file("detections.csv").string() + ": cannot be written");
  folder.commit();

  std::string id_list;
  for (int id : ids) id_list += (id_list.empty() ? "" : ", ") + std::to_string(id);
  if (args.json) {
    nlohmann::json j;
    j["images"] = images;
    j["tags"] = tags;
    j["ids"] = std::vector<int>(ids.begin(), ids.end());
    j["family"] = args.family;
    j["per_image"] = per_image;
    j["output"] = folder.target().string();
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("images %d | tags %d (%s) | ids %s | output: %s\n", images, tags,
                args.family.c_str(), id_list.empty() ? "none" : id_list.c_str(),
                folder.target().string().c_str());
  }
  return 0;
}

}  // namespace agv::tools
