#include "pipeline/live_source.h"

#include <algorithm>
#include <cctype>
#include <opencv2/videoio.hpp>

#include "common/input_error.h"
#include "pipeline/dataset_source.h"

namespace agv::pipeline {
namespace {

bool all_digits(const std::string& text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), ::isdigit);
}

// Opens what the spec names with the backend it needs.
bool open_capture(cv::VideoCapture* capture, const std::string& spec) {
  if (all_digits(spec)) return capture->open(std::stoi(spec), cv::CAP_V4L2);
  if (spec.rfind("/dev/video", 0) == 0) return capture->open(spec, cv::CAP_V4L2);
  if (spec.find('!') != std::string::npos) return capture->open(spec, cv::CAP_GSTREAMER);
  return capture->open(spec, cv::CAP_ANY);
}

}  // namespace

std::string LiveSource::kind_of(const std::string& spec) {
  if (all_digits(spec) || spec.rfind("/dev/video", 0) == 0) return "V4L2 device";
  if (spec.find('!') != std::string::npos) return "GStreamer pipeline";
  return "network stream";
}

LiveSource::LiveSource(const std::string& spec, const perception::CameraIntrinsics& camera)
    : spec_(spec),
      camera_(camera),
      capture_(std::make_shared<cv::VideoCapture>()),
      shared_(std::make_shared<Shared>()) {
  if (!open_capture(capture_.get(), spec)) {
    throw InputError(spec + ": cannot open the " + kind_of(spec) +
                     (kind_of(spec) == "GStreamer pipeline"
                          ? " (does it end in appsink, and is OpenCV built with GStreamer?)"
                          : ""));
  }
  const double fps = capture_->get(cv::CAP_PROP_FPS);
  if (fps > 0.0 && fps < 10000.0) frame_period_s_ = 1.0 / fps;
}

LiveSource::~LiveSource() {
  interrupt();
  if (!grabber_.joinable()) return;
  // A driver may block in read() for ever (an unplugged camera): give the grabber a second,
  // then leave it; it holds its own references to what it uses.
  std::unique_lock<std::mutex> lock(shared_->mutex);
  const bool done = shared_->changed.wait_for(lock, std::chrono::seconds(1),
                                              [this] { return shared_->grabber_done; });
  lock.unlock();
  if (done) {
    grabber_.join();
  } else {
    grabber_.detach();
  }
}

void LiveSource::start(Clock::time_point origin) {
  grabber_ = std::thread(grab, shared_, capture_, camera_, spec_, origin);
}

void LiveSource::grab(std::shared_ptr<Shared> shared, std::shared_ptr<cv::VideoCapture> capture,
                      perception::CameraIntrinsics camera, std::string spec,
                      Clock::time_point origin) {
  for (std::uint64_t index = 0;; ++index) {
    {
      std::lock_guard<std::mutex> lock(shared->mutex);
      if (shared->stopping) break;
    }
    SourceFrame frame;
    const bool read = capture->read(frame.image);
    frame.t_s = std::chrono::duration<double>(Clock::now() - origin).count();  // on arrival
    frame.index = index;
    frame.label = "live frame " + std::to_string(index);
    std::lock_guard<std::mutex> lock(shared->mutex);
    if (!read) {
      shared->ended = true;  // the stream ended or the device went away
      break;
    }
    if (const auto problem = usable_frame(&frame.image, camera)) {
      shared->error = spec + " " + frame.label + ": the frame " + *problem;
      shared->ended = true;
      break;
    }
    if (shared->newest) ++shared->dropped;
    shared->newest = std::move(frame);
    ++shared->grabbed;
    shared->changed.notify_all();
  }
  std::lock_guard<std::mutex> lock(shared->mutex);
  shared->grabber_done = true;
  shared->changed.notify_all();
}

std::optional<SourceFrame> LiveSource::next() {
  std::unique_lock<std::mutex> lock(shared_->mutex);
  shared_->changed.wait(lock,
                        [this] { return shared_->newest || shared_->ended || shared_->stopping; });
  if (shared_->newest) {
    std::optional<SourceFrame> frame = std::move(shared_->newest);
    shared_->newest.reset();
    return frame;
  }
  if (!shared_->error.empty()) throw InputError(shared_->error);
  return std::nullopt;
}

void LiveSource::interrupt() {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  shared_->stopping = true;
  shared_->changed.notify_all();
}

std::uint64_t LiveSource::frames_dropped() const {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  return shared_->dropped;
}

}  // namespace agv::pipeline
