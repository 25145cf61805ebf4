#include "perception/apriltag_detector.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>
}

namespace agv::perception {

// Outside the anonymous namespace: AprilTagDetector::Impl holds a pointer to one.
struct AprilTagFamilyFunctions {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

namespace {

constexpr AprilTagFamilyFunctions kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
};

// The library's pixel centres sit at +0.5 from OpenCV's.
cv::Point2d to_opencv(const double p[2]) { return {p[0] - 0.5, p[1] - 0.5}; }

}  // namespace

struct AprilTagDetector::Impl {
  const AprilTagFamilyFunctions* functions = nullptr;
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;

  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
    if (family) functions->destroy(family);
  }
};

AprilTagDetector::AprilTagDetector(const Options& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  for (const AprilTagFamilyFunctions& f : kFamilies) {
    if (options.family == f.name) impl_->functions = &f;
  }
  if (!impl_->functions)
    throw std::invalid_argument("unknown AprilTag family '" + options.family + "'");
  if (!(options.decimation >= 1.0 && options.decimation <= 8.0))
    throw std::invalid_argument("AprilTag decimation must be in [1, 8]");
  if (!(options.sigma >= 0.0 && options.sigma <= 10.0))
    throw std::invalid_argument("AprilTag sigma must be in [0, 10]");
  if (options.threads < 1 || options.threads > 64)
    throw std::invalid_argument("AprilTag threads must be in [1, 64]");
  if (options.max_hamming < 0 || options.max_hamming > 3)
    throw std::invalid_argument("AprilTag max_hamming must be in [0, 3]");
  impl_->family = impl_->functions->create();
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family, options.max_hamming);
  impl_->detector->quad_decimate = static_cast<float>(options.decimation);
  impl_->detector->quad_sigma = static_cast<float>(options.sigma);
  impl_->detector->nthreads = options.threads;
  impl_->detector->refine_edges = options.refine_edges;
}

AprilTagDetector::AprilTagDetector() : AprilTagDetector(Options{}) {}
AprilTagDetector::~AprilTagDetector() = default;
AprilTagDetector::AprilTagDetector(AprilTagDetector&&) noexcept = default;
AprilTagDetector& AprilTagDetector::operator=(AprilTagDetector&&) noexcept = default;

std::vector<TagDetection> AprilTagDetector::detect(const cv::Mat& image) const {
  std::vector<TagDetection> tags;
  if (image.empty() || image.depth() != CV_8U) return tags;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 1) {
    grey = image.isContinuous() ? image : image.clone();
  } else {
    return tags;
  }
  image_u8_t view{grey.cols, grey.rows, static_cast<int32_t>(grey.step[0]), grey.data};
  zarray_t* found = apriltag_detector_detect(impl_->detector, &view);
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(found, i, &d);
    TagDetection tag;
    tag.family = impl_->functions->name;
    tag.id = d->id;
    tag.hamming = d->hamming;
    tag.decision_margin = d->decision_margin;
    tag.centre = to_opencv(d->c);
    for (int k = 0; k < 4; ++k) tag.corners_px[k] = to_opencv(d->p[k]);
    tags.push_back(tag);
  }
  apriltag_detections_destroy(found);
  std::sort(tags.begin(), tags.end(), [](const TagDetection& a, const TagDetection& b) {
    return a.id != b.id ? a.id < b.id : a.centre.x < b.centre.x;
  });
  return tags;
}

cv::Mat AprilTagDetector::tag_image(int id) const {
  if (id < 0 || id >= tag_count()) throw std::invalid_argument("tag id out of range");
  image_u8_t* drawn = apriltag_to_image(impl_->family, id);
  cv::Mat copy(drawn->height, drawn->width, CV_8UC1, drawn->buf, drawn->stride);
  cv::Mat result = copy.clone();
  // image_u8_destroy is not exported by Debian's libapriltag.so; it frees the buffer and the
  // struct, both allocated with calloc by image_u8_create.
  std::free(drawn->buf);
  std::free(drawn);
  return result;
}

int AprilTagDetector::tag_count() const { return static_cast<int>(impl_->family->ncodes); }

int AprilTagDetector::size_cells() const { return impl_->family->width_at_border; }

std::vector<std::string> AprilTagDetector::families() {
  std::vector<std::string> names;
  for (const AprilTagFamilyFunctions& f : kFamilies) names.push_back(f.name);
  return names;
}

}  // namespace agv::perception
