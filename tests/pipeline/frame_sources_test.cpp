// Frame sources: a bare folder of real images, a video file, a live GStreamer pipeline, and
// what each refuses.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <thread>

#include "common/input_error.h"
#include "pipeline/dataset_source.h"
#include "pipeline/live_source.h"
#include "pipeline/open_frame_source.h"
#include "pipeline/video_source.h"

namespace agv::pipeline {
namespace {

namespace fs = std::filesystem;

const std::string kRealFrames = std::string(AGV_SHARED_DIR) + "/data/real/rcj_black_tape_topdown";
const std::string kRcjCamera = std::string(AGV_SOURCE_DIR) + "/datasets/cameras/rcj_topdown.yaml";

class FrameSources : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("agv_sources_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// The six real frames, as a bare folder: name order, times from the frame rate, no truth.
TEST_F(FrameSources, BareFolderOfRealImagesInNameOrderAtTheFrameRate) {
  OpenedSource opened = open_frame_source(kRealFrames, kRcjCamera, 5.0, false);
  EXPECT_EQ(opened.kind, "image folder");
  EXPECT_FALSE(opened.has_truth);
  EXPECT_EQ(opened.source->frame_count(), 6);
  EXPECT_DOUBLE_EQ(opened.source->frame_period_s(), 0.2);
  const std::vector<std::string> names = {"90_left.png", "junc2.png",    "junc3.png",
                                          "junc4.png",   "junction.png", "straight.png"};
  for (size_t i = 0; i < names.size(); ++i) {
    ASSERT_TRUE(opened.source->next_time_s());
    EXPECT_NEAR(*opened.source->next_time_s(), 0.2 * i, 1e-12);
    const std::optional<SourceFrame> frame = opened.source->next();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->label, names[i]);
    EXPECT_EQ(frame->image.size(), cv::Size(640, 480));
    EXPECT_FALSE(frame->truth);
  }
  EXPECT_FALSE(opened.source->next());
  EXPECT_FALSE(opened.source->next_time_s());
}

// A bare folder needs its frame rate, anything but a dataset a camera file; each refusal
// names the path and what to give.
TEST_F(FrameSources, RefusalsSayWhatIsMissing) {
  auto message_of = [](const std::string& spec, const std::string& camera, double fps) {
    try {
      (void)open_frame_source(spec, camera, fps, false);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string no_fps = message_of(kRealFrames, kRcjCamera, 0.0);
  EXPECT_NE(no_fps.find("--fps"), std::string::npos) << no_fps;
  EXPECT_NE(no_fps.find("rcj_black_tape_topdown"), std::string::npos) << no_fps;
  const std::string no_camera = message_of(kRealFrames, "", 5.0);
  EXPECT_NE(no_camera.find("--camera"), std::string::npos) << no_camera;
  const std::string empty = (dir_ / "empty").string();
  fs::create_directories(empty);
  EXPECT_NE(message_of(empty, kRcjCamera, 5.0).find("no images"), std::string::npos);
  const std::string missing = message_of((dir_ / "nothing_here.avi").string(), kRcjCamera, 0.0);
  EXPECT_NE(missing.find("nothing_here.avi"), std::string::npos) << missing;
  EXPECT_NE(message_of("/dev/video97", kRcjCamera, 0.0).find("V4L2"), std::string::npos);
}

// A video file: its frames in order, timed by the container (10 frames/s here), the next
// frame's time known before it is read, the end known at the last frame.
TEST_F(FrameSources, VideoFileFramesAreTimedByTheContainer) {
  const std::string path = (dir_ / "clip.avi").string();
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0,
                           cv::Size(640, 480));
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 12; ++i) {
      cv::Mat frame(480, 640, CV_8UC3, cv::Scalar(200, 200, 200));
      cv::rectangle(frame, {20 * i, 0}, {20 * i + 40, 479}, cv::Scalar(20, 20, 20), cv::FILLED);
      writer.write(frame);
    }
  }
  perception::CameraIntrinsics camera;
  camera.width_px = 640;
  camera.height_px = 480;
  VideoSource video(path, camera, false);
  EXPECT_NEAR(video.frame_period_s(), 0.1, 1e-9);
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(video.next_time_s()) << i;
    EXPECT_NEAR(*video.next_time_s(), 0.1 * i, 1e-3) << i;
    const std::optional<SourceFrame> frame = video.next();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, static_cast<std::uint64_t>(i));
    // The dark bar moves 20 px a frame: the frames come in order.
    cv::Mat grey;
    cv::cvtColor(frame->image, grey, cv::COLOR_BGR2GRAY);
    EXPECT_LT(grey.at<unsigned char>(240, 20 * i + 20), 80) << i;
  }
  EXPECT_FALSE(video.next_time_s());
  EXPECT_FALSE(video.next());

  camera.width_px = 320;  // a calibration of another camera
  VideoSource wrong(path, camera, /*pass_bad_frames=*/true);
  const std::optional<SourceFrame> frame = wrong.next();
  ASSERT_TRUE(frame);
  EXPECT_NE(frame->problem.find("640x480"), std::string::npos) << frame->problem;
  EXPECT_THROW(VideoSource(path, camera, false), InputError);
}

// A live GStreamer pipeline (videotestsrc, 60 frames at 100 frames/s) read by a consumer that
// takes 40 ms a frame: frames are stamped on arrival in increasing order, and those it could
// not keep up with are dropped and counted rather than queued.
TEST_F(FrameSources, LiveGStreamerSourceKeepsOnlyTheNewestFrame) {
  perception::CameraIntrinsics camera;
  camera.width_px = 320;
  camera.height_px = 240;
  const std::string pipeline =
      "videotestsrc num-buffers=60 ! video/x-raw,width=320,height=240,framerate=100/1 ! "
      "videoconvert ! video/x-raw,format=BGR ! appsink sync=true";
  std::unique_ptr<LiveSource> source;
  try {
    source = std::make_unique<LiveSource>(pipeline, camera);
  } catch (const InputError& e) {
    GTEST_SKIP() << "no GStreamer videotestsrc / appsink here (Debian packages "
                    "gstreamer1.0-plugins-base, libopencv-videoio with GStreamer): "
                 << e.what();
  }
  EXPECT_TRUE(source->live());
  EXPECT_FALSE(source->next_time_s());
  source->start(FrameSource::Clock::now());
  int taken = 0;
  double last_t_s = -1.0;
  while (const std::optional<SourceFrame> frame = source->next()) {
    EXPECT_GT(frame->t_s, last_t_s);
    last_t_s = frame->t_s;
    EXPECT_EQ(frame->image.size(), cv::Size(320, 240));
    ++taken;
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
  EXPECT_GT(taken, 5);
  EXPECT_LT(taken, 40);
  EXPECT_EQ(taken + source->frames_dropped(), 60u);
}

}  // namespace
}  // namespace agv::pipeline
