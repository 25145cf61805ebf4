#include "pipeline/dataset_source.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/input_error.h"

namespace agv::pipeline {
namespace {

// The median interval between frames (0.1 s for a single frame).
double median_interval_s(const std::vector<DatasetRow>& rows) {
  std::vector<double> intervals;
  for (size_t i = 1; i < rows.size(); ++i) intervals.push_back(rows[i].t_s - rows[i - 1].t_s);
  if (intervals.empty()) return 0.1;
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  return intervals[intervals.size() / 2];
}

}  // namespace

std::optional<std::string> usable_frame(cv::Mat* image,
                                        const perception::CameraIntrinsics& camera) {
  if (image->empty()) return "cannot be read or decoded";
  if (image->depth() != CV_8U) return "is not 8 bits per channel (e.g. a 16-bit image)";
  if (image->channels() == 4) cv::cvtColor(*image, *image, cv::COLOR_BGRA2BGR);
  if (image->channels() != 1 && image->channels() != 3)
    return "has " + std::to_string(image->channels()) + " channels";
  if (image->cols != camera.width_px || image->rows != camera.height_px) {
    return "is " + std::to_string(image->cols) + "x" + std::to_string(image->rows) +
           ", the camera file says " + std::to_string(camera.width_px) + "x" +
           std::to_string(camera.height_px);
  }
  return std::nullopt;
}

DatasetSource::DatasetSource(Dataset dataset, bool pass_bad_frames)
    : dataset_(std::move(dataset)),
      pass_bad_frames_(pass_bad_frames),
      frame_period_s_(median_interval_s(dataset_.rows)) {}

std::optional<double> DatasetSource::next_time_s() const {
  if (next_row_ >= dataset_.rows.size()) return std::nullopt;
  return dataset_.rows[next_row_].t_s;
}

std::optional<SourceFrame> DatasetSource::next() {
  if (next_row_ >= dataset_.rows.size()) return std::nullopt;
  const DatasetRow& row = dataset_.rows[next_row_++];
  SourceFrame frame;
  frame.index = static_cast<std::uint64_t>(row.index);
  frame.t_s = row.t_s;
  frame.label = row.file;
  frame.pose = row.pose;
  frame.truth = row.truth;
  frame.odometry = row.odometry;
  const std::string path = (dataset_.root / row.file).string();
  frame.image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (const auto problem = usable_frame(&frame.image, dataset_.camera.intrinsics)) {
    const std::string where =
        row.line > 0 ? path + " (" + dataset_.manifest + " line " + std::to_string(row.line) + ")"
                     : path;
    if (!pass_bad_frames_) throw InputError(where + ": the frame " + *problem);
    frame.problem = *problem;
    frame.image.release();
  }
  return frame;
}

}  // namespace agv::pipeline
