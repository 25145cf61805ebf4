#pragma once

#include "pipeline/dataset.h"
#include "pipeline/frame_source.h"

namespace agv::pipeline {

// The frames of a dataset folder (with manifest) or a bare folder of images, in time order,
// with the manifest's ground truth and wheel odometry where it has them.
class DatasetSource : public FrameSource {
 public:
  // pass_bad_frames: a frame that cannot be read, or is of the wrong size or type, comes back
  // with its problem set instead of throwing InputError.
  DatasetSource(Dataset dataset, bool pass_bad_frames);

  std::optional<SourceFrame> next() override;
  void skip() override { ++next_row_; }
  std::optional<double> next_time_s() const override;
  double frame_period_s() const override { return frame_period_s_; }
  long frame_count() const override { return static_cast<long>(dataset_.rows.size()); }
  std::string describe() const override { return dataset_.root.string(); }
  const Dataset& dataset() const { return dataset_; }

 private:
  Dataset dataset_;
  bool pass_bad_frames_;
  double frame_period_s_;
  size_t next_row_ = 0;
};

// Brings a frame read from a file or a video to 8-bit BGR or grey (a 4-channel frame loses its
// alpha); the reason it cannot be used, when it cannot.
std::optional<std::string> usable_frame(cv::Mat* image, const perception::CameraIntrinsics& camera);

}  // namespace agv::pipeline
