#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace agv::perception {

// A linear map from pixel colour to "tape-ness": s = w . bgr + offset, about 0 on the floor and
// about 1 on the tape. Linear, so that it keeps the shape of blurred edges: a soft edge in the
// image is a soft edge in s, with its half-way point in the same place.
struct ContrastAxis {
  cv::Vec3f weights = {0, 0, 0};  // for grey images only weights[0] is used
  float offset = 0.0f;
  bool from_hint = false;  // the tape colour came from the caller, not the image

  float apply(const cv::Vec3b& bgr) const {
    return weights[0] * bgr[0] + weights[1] * bgr[1] + weights[2] * bgr[2] + offset;
  }
  float apply(unsigned char grey) const { return weights[0] * grey + offset; }
  // apply() to n consecutive pixels of `channels` (1 or 3) bytes each: the same values, in a
  // loop that vectorises.
  void apply_to_row(const unsigned char* pixels, int n, int channels, float* out) const;
};

// Estimates the axis from a (downsampled) frame: the floor colour is the per-channel median
// (the tape covers well under half of the view); the tape colour is `tape_hint_bgr` when given
// and distinct from the floor, otherwise the mean colour of the pixels that differ most from the
// floor, on their dominant side. Works for dark-on-light and light-on-dark tape, grey or colour
// frames. Returns nullopt when the frame is flat (nothing differs from the floor).
std::optional<ContrastAxis> estimate_contrast_axis(const cv::Mat& frame,
                                                   const std::optional<cv::Vec3d>& tape_hint_bgr);

// Chooses the colour axis along which the tape stands out as a bar of one of the expected
// widths (in pixels of the downsampled `frame`; the strongest response over them): candidates are
// the hint (if any), the direction of the pixels that differ most from the floor, darker, lighter,
// and six chroma directions; each is scored by how far the strongest response of a linear bar
// detector (mean over the bar minus the mean of its flanks, along rows and columns) stands above
// that response's robust spread. A broad shadow or a lit patch differs from the floor too, but is
// no bar. The axis is scaled so that the tape is about 1. Nullopt for a flat frame.
std::optional<ContrastAxis> choose_contrast_axis(const cv::Mat& frame,
                                                 const std::optional<cv::Vec3d>& tape_hint_bgr,
                                                 const std::vector<double>& bar_widths_px);

// The same, best first: up to max_axes axes, each pointing another way in colour than those
// before it (their weights more than 90 deg apart), for a search that finds no tape on the first
// (a glare spot or a blotch can stand out more than narrow tape). Empty for a flat frame.
std::vector<ContrastAxis> choose_contrast_axes(const cv::Mat& frame,
                                               const std::optional<cv::Vec3d>& tape_hint_bgr,
                                               const std::vector<double>& bar_widths_px,
                                               int max_axes);

}  // namespace agv::perception
