#include "pipeline/perceiver.h"

namespace agv::pipeline {

std::optional<Pose2> ImagePerceiver::odometry_of(const SourceFrame& frame,
                                                 perception::OdometryKind* kind) {
  *kind = perception::OdometryKind::wheels;
  if (frame.odometry) {
    ++wheel_frames_;
    return frame.odometry;
  }
  std::optional<Pose2> motion = floor_odometry_->motion(frame.image);
  if (motion) {
    ++floor_frames_;
    last_motion_ = motion;
    *kind = perception::OdometryKind::frames;
  } else if (last_motion_) {
    ++repeated_frames_;  // a featureless floor, or a frame the alignment missed
    motion = last_motion_;
    *kind = perception::OdometryKind::guess;
  } else {
    return std::nullopt;  // no motion read yet: nothing to place the remembered tape with
  }
  frame_odometry_ = frame_odometry_.compose(*motion);
  return frame_odometry_;
}

std::string ImagePerceiver::odometry_source() const {
  if (!memory_) return "none";
  if (wheel_frames_ > 0 && floor_frames_ == 0) return "wheel odometry";
  if (floor_frames_ == 0 && repeated_frames_ == 0) return "none";
  std::string source = "motion from the frames (" + std::to_string(floor_frames_) + " frames";
  if (repeated_frames_ > 0)
    source += ", " + std::to_string(repeated_frames_) + " too featureless: the last motion kept";
  if (wheel_frames_ > 0) source += ", " + std::to_string(wheel_frames_) + " with wheel odometry";
  return source + ")";
}

}  // namespace agv::pipeline
