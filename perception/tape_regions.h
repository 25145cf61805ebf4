#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "perception/contrast_axis.h"

namespace agv::perception {

// A connected blob of tape-like pixels found on the downsampled contrast image.
struct TapeRegion {
  int label = 0;
  int area_small_px = 0;
  cv::Rect box_small;       // bounding box in the downsampled image
  cv::Point2d centroid_px;  // full-resolution pixel coordinates
  cv::Point2d direction;    // unit vector of the major axis in the image
  double length_px = 0.0;   // extent along the major axis, full resolution
  double width_px = 0.0;    // mean extent across it (area / length)
  double spread_px = 0.0;   // extent across it from the second moments (a band: its width;
                            // a corner or a crossing: much more than width_px)
};

// The coarse stage of line detection: where in the image the tape may be.
struct TapeRegions {
  int downsample = 4;
  cv::Mat contrast_small;           // CV_32F contrast on the downsampled frame
  cv::Mat bar_small;                // CV_32F bar-detector response (see find_tape_regions)
  cv::Mat labels_small;             // CV_32S, 0 = background
  float threshold = 0.5f;           // contrast level separating tape from floor
  float floor_level = 0.0f;         // median contrast of the floor
  float tape_level = 1.0f;          // median contrast of the tape-like pixels
  float floor_noise = 0.0f;         // robust standard deviation of the floor contrast
  std::vector<TapeRegion> regions;  // largest first
};

// Finds where tape may be on a downsampled frame. A bar detector tuned to the tape's width in
// the image (bar_widths_small_px, one or more candidate widths) responds to a band of that width
// brighter (in contrast) than the floor on both sides: the mean over the band minus the mean
// over the two flanks, along rows and along columns, the larger kept. Floor texture, shading
// and illumination gradients, which vary slowly across a tape width, cancel out. The response
// is thresholded half-way between floor and tape (ISODATA) and its connected regions of at
// least min_area_small_px pixels are returned. With no bar widths the response is the contrast
// itself: the plateau of tape wider than any bar that fits the view (a bar there answers only
// to its edges), against a floor that is level over the view.
TapeRegions find_tape_regions(const cv::Mat& small_frame, const ContrastAxis& axis, int downsample,
                              const std::vector<double>& bar_widths_small_px,
                              int min_area_small_px);

}  // namespace agv::perception
