#include "pipeline/open_frame_source.h"

#include <filesystem>

#include "common/input_error.h"
#include "pipeline/dataset.h"
#include "pipeline/dataset_source.h"
#include "pipeline/live_source.h"
#include "pipeline/video_source.h"

namespace agv::pipeline {
namespace fs = std::filesystem;

namespace {

bool names_live_source(const std::string& spec) {
  return spec.find("://") != std::string::npos || spec.find('!') != std::string::npos ||
         spec.rfind("/dev/video", 0) == 0 ||
         (!spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos);
}

perception::CameraFile camera_for(const std::string& spec, const std::string& camera_path,
                                  const std::string& what) {
  if (camera_path.empty())
    throw InputError(spec + ": " + what + " carries no calibration; give one with --camera FILE");
  return perception::load_camera_file(camera_path);
}

}  // namespace

OpenedSource open_frame_source(const std::string& spec, const std::string& camera_path, double fps,
                               bool pass_bad_frames) {
  OpenedSource opened;
  std::error_code error;
  if (fs::is_directory(spec, error)) {
    Dataset dataset = open_dataset(spec, camera_path, fps, pass_bad_frames);
    opened.kind = dataset.manifest.empty() ? "image folder" : "dataset";
    opened.camera = dataset.camera;
    opened.camera_name = dataset.camera_name;
    opened.has_truth = dataset.has_truth;
    opened.source = std::make_unique<DatasetSource>(std::move(dataset), pass_bad_frames);
    return opened;
  }
  if (fs::exists(spec, error) && !looks_like_video(spec) && !names_live_source(spec)) {
    throw InputError(spec +
                     ": is a file; expected a dataset folder (frames/, manifest.csv, "
                     "camera.yaml), a folder of images, a video (.avi, .mp4, .mkv, .mov, .webm) "
                     "or a live source");
  }
  if (fs::exists(spec, error) && looks_like_video(spec)) {
    opened.kind = "video file";
    opened.camera = camera_for(spec, camera_path, "a video");
    opened.source = std::make_unique<VideoSource>(spec, opened.camera.intrinsics, pass_bad_frames);
  } else if (names_live_source(spec)) {
    opened.kind = LiveSource::kind_of(spec);
    opened.camera = camera_for(spec, camera_path, "a live " + opened.kind);
    opened.source = std::make_unique<LiveSource>(spec, opened.camera.intrinsics);
  } else {
    throw InputError(spec +
                     ": no such dataset folder, image folder or video file (nor a live source: "
                     "/dev/videoN, a device index, a GStreamer pipeline with '!', a URL)");
  }
  opened.camera_name = camera_path;
  return opened;
}

}  // namespace agv::pipeline
