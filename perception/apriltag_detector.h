#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace agv::perception {

// One AprilTag found in an image. Pixel coordinates follow OpenCV's convention (the centre of
// pixel (0, 0) at (0, 0)); the library's own convention (+0.5) is converted in the wrapper.
// Corners in the library's order: counter-clockwise around the tag as seen in the image, the
// first at the tag's (-1, +1) corner of its ideal square (x right, y down in the tag image:
// bottom-left, bottom-right, top-right, top-left).
struct TagDetection {
  std::string family;
  int id = 0;
  int hamming = 0;                        // bits corrected
  double decision_margin = 0.0;           // decoding quality (higher is better)
  cv::Point2d centre;                     // pixels
  std::array<cv::Point2d, 4> corners_px;  // pixels
};

// The AprilTag 3 C library (Debian libapriltag-dev), wrapped: the detector and its family own
// their C objects; everything outside this file sees value types.
class AprilTagDetector {
 public:
  struct Options {
    std::string family = "tag36h11";  // tag36h11, tag25h9, tag16h5, tagCircle21h7,
                                      // tagCircle49h12, tagStandard41h12, tagStandard52h13,
                                      // tagCustom48h12
    double decimation = 1.0;          // quad detection on a downsampled image (faster, coarser)
    double sigma = 0.0;               // Gaussian blur before quad detection (noisy images: 0.8)
    int threads = 1;
    bool refine_edges = true;
    // Bits the decoder may correct (more: more false tags, more memory; for the 48- and 52-bit
    // families, 2 bits take about a minute and gigabytes to set up: use 0 or 1 there).
    int max_hamming = 2;
  };

  // Throws std::invalid_argument for an unknown family or an option out of range.
  AprilTagDetector();  // tag36h11, decimation 1, one thread
  explicit AprilTagDetector(const Options& options);
  ~AprilTagDetector();
  AprilTagDetector(AprilTagDetector&&) noexcept;
  AprilTagDetector& operator=(AprilTagDetector&&) noexcept;

  // Tags in an 8-bit grey or BGR image, sorted by id then x. Not thread-safe on one detector.
  std::vector<TagDetection> detect(const cv::Mat& image) const;

  // The tag's pattern as the library draws it: a grey image of (black border + data) cells, one
  // pixel per cell, including the white outer border for the families that have one. For
  // rendering tags on the floor.
  cv::Mat tag_image(int id) const;
  int tag_count() const;
  // Cells across the tag's size as AprilTag measures it (the black border square for
  // tag36h11: 8 of its 10 cells): the side of one cell is size_m / size_cells().
  int size_cells() const;
  const Options& options() const { return options_; }

  static std::vector<std::string> families();

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace agv::perception
