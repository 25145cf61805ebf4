// End-to-end: agv track on a video in real time, stopped by Ctrl-C, sending commands over UDP,
// on a live GStreamer pipeline; agv replay on a bare folder of real images.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <thread>
#include <vector>

#include "support/agv_process.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using agv::testing::run_agv;

std::vector<nlohmann::json> read_jsonl(const fs::path& file) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// Commands streamed so far by a run writing to `out` (into its temporary folder beside it,
// which OutputFolder renames into place at the end).
int commands_streamed(const fs::path& out) {
  int lines = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(out.parent_path())) {
    if (entry.path().filename().string().rfind("." + out.filename().string() + ".partial-", 0) != 0)
      continue;
    std::ifstream in(entry.path() / "commands.jsonl");
    for (std::string line; std::getline(in, line);) ++lines;
  }
  return lines;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

bool is_stop(const nlohmann::json& command) {
  return command["v_x_m_s"].get<double>() == 0.0 && command["v_y_m_s"].get<double>() == 0.0 &&
         command["w_z_rad_s"].get<double>() == 0.0;
}

class AgvTrack : public agv::testing::ScratchFolderTest {
 protected:
  // A video of `repeats` times the 21 frames of a recorded 2 s run (10 frames/s), with the
  // recording's camera.yaml beside it.
  std::string make_video(int repeats) {
    if (!fs::exists(dir_ / "dataset")) {
      const auto r =
          run_agv("record --quiet --set duration_s=2.0 --format jpg --out " + path("dataset"));
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    const std::string video = path("run" + std::to_string(repeats) + ".avi");
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0,
                           cv::Size(640, 480));
    EXPECT_TRUE(writer.isOpened());
    for (int r = 0; r < repeats; ++r) {
      std::vector<fs::path> frames;
      for (const auto& entry : fs::directory_iterator(dir_ / "dataset" / "frames"))
        frames.push_back(entry.path());
      std::sort(frames.begin(), frames.end());
      for (const fs::path& frame : frames) writer.write(cv::imread(frame.string()));
    }
    return video;
  }
  std::string camera() const { return " --camera " + path("dataset/camera.yaml"); }
};

// A video played at its own frame rate: every frame measured (none dropped on an idle
// machine is not promised, so they are counted), one command a period, the measurement age
// under two frame periods at the median, and the end of the video ends the run with a stop.
TEST_F(AgvTrack, TracksAVideoInRealTimeAndStopsAtItsEnd) {
  const std::string video = make_video(1);
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_agv("track --quiet " + video + camera() + " --out " + path("track"));
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GE(wall_s, 1.9) << "did not play at the video's frame rate";
  const nlohmann::json s = read_json(dir_ / "track" / "summary.json");
  EXPECT_EQ(s["stop_reason"], "end of source");
  EXPECT_EQ(s["frames"].get<int>() + s["frames_dropped"].get<int>(), 21);
  EXPECT_GE(s["frames"].get<int>(), 15);
  // Fresh measurements: the age is at most a control period (0.1 s) plus the time perception
  // takes on this machine (measured in the same run: an ASan build on a loaded 2-core machine
  // takes several times the Release time), plus 50 ms of scheduling; a controller acting on
  // frames queued several periods late exceeds it.
  const double perceive_s = 1e-3 * s["timing"]["perceive_ms_p99"].get<double>();
  EXPECT_LT(s["tracking"]["measurement_age_s_median"].get<double>(), 0.1 + perceive_s + 0.05)
      << "perception p99 " << perceive_s << " s";
  EXPECT_NEAR(s["tracking"]["commands_per_s"].get<double>(), 10.0, 0.5);
  const std::vector<nlohmann::json> commands = read_jsonl(dir_ / "track" / "commands.jsonl");
  ASSERT_GE(commands.size(), 20u);
  for (const char* key :
       {"t_s", "v_x_m_s", "v_y_m_s", "w_z_rad_s", "line_found", "e_theta_rad", "e_d_m", "age_s"}) {
    EXPECT_TRUE(commands[5].contains(key)) << key;
  }
  EXPECT_TRUE(commands[5]["line_found"].get<bool>());
  EXPECT_TRUE(is_stop(commands.back()));
  EXPECT_FALSE(is_stop(commands[5]));
  for (const char* file : {"measurements.csv", "summary.json", "errors.png"})
    EXPECT_TRUE(fs::exists(dir_ / "track" / file)) << file;
}

// Ctrl-C while tracking a 10 s video: the program brakes the vehicle, writes every file
// complete, ends with a stop command and exits 0 within a second or so.
TEST_F(AgvTrack, CtrlCStopsCleanly) {
  const std::string video = make_video(5);
  const std::string out = path("interrupted");
  const std::string log = path("log.txt");
  std::vector<std::string> args = {
      AGV_BINARY, "track", "--quiet", video, "--camera", path("dataset/camera.yaml"), "--out", out};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, AGV_BINARY, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // Interrupt once the run is under way (commands are streaming): a fixed wait would fire
  // before the handler is installed on a loaded machine.
  const auto started = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - started < std::chrono::seconds(30) &&
         commands_streamed(out) < 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_GE(commands_streamed(out), 5) << "the run never streamed 5 commands";
  const auto interrupted = std::chrono::steady_clock::now();
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  const double stop_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - interrupted).count();
  std::ifstream in(log);
  const std::string output((std::istreambuf_iterator<char>(in)), {});
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_EQ(WEXITSTATUS(status), 0) << output;
  EXPECT_LT(stop_s, 3.0);
  const nlohmann::json s = read_json(fs::path(out) / "summary.json");
  EXPECT_EQ(s["stop_reason"], "stopped");
  EXPECT_LT(s["frames"].get<int>(), 60);
  const std::vector<nlohmann::json> commands = read_jsonl(fs::path(out) / "commands.jsonl");
  ASSERT_GE(commands.size(), 5u);
  EXPECT_TRUE(is_stop(commands.back()));
  EXPECT_EQ(commands.size(), s["commands"].get<size_t>());
}

// --udp: each command also goes out as one datagram of JSON, the same lines as commands.jsonl
// (as fast as possible here, so that the test does not wait for the video's time).
TEST_F(AgvTrack, SendsEachCommandOverUdp) {
  const std::string video = make_video(1);
  const int receiver = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(receiver, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(receiver, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  socklen_t length = sizeof(address);
  getsockname(receiver, reinterpret_cast<sockaddr*>(&address), &length);
  const int rcvbuf = 1 << 20;
  setsockopt(receiver, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));
  const std::string udp = "127.0.0.1:" + std::to_string(ntohs(address.sin_port));
  const auto r = run_agv("track --quiet --as-fast-as-possible " + video + camera() + " --udp " +
                         udp + " --out " + path("udp"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<nlohmann::json> lines = read_jsonl(dir_ / "udp" / "commands.jsonl");
  std::vector<nlohmann::json> received;
  char buffer[2048];
  for (;;) {
    const ssize_t n = recv(receiver, buffer, sizeof(buffer), MSG_DONTWAIT);
    if (n <= 0) break;
    received.push_back(nlohmann::json::parse(std::string(buffer, n)));
  }
  close(receiver);
  ASSERT_EQ(received.size(), lines.size());
  for (size_t i = 0; i < lines.size(); ++i) EXPECT_EQ(received[i], lines[i]) << i;
  EXPECT_TRUE(is_stop(received.back()));

  const auto bad =
      run_agv("track --quiet " + video + camera() + " --udp nowhere --out " + path("bad_udp"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--udp nowhere"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad_udp"));
}

// A live GStreamer pipeline (Debian's OpenCV has the GStreamer backend): frames as they come,
// for --duration seconds; --as-fast-as-possible makes no sense for it and is refused.
TEST_F(AgvTrack, TracksALiveGStreamerPipeline) {
  make_video(1);
  const std::string pipeline =
      "\"videotestsrc pattern=black ! video/x-raw,width=640,height=480,framerate=30/1 ! "
      "videoconvert ! "
      "video/x-raw,format=BGR ! appsink\"";
  const auto r =
      run_agv("track --quiet " + pipeline + camera() + " --duration 1 --out " + path("live"));
  if (r.exit_code == 2 && r.output.find("cannot open") != std::string::npos)
    GTEST_SKIP() << "no GStreamer videotestsrc here: " << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = read_json(dir_ / "live" / "summary.json");
  EXPECT_EQ(s["source_kind"], "GStreamer pipeline");
  // Frames as they come: a second of a 30 frames/s source is about 30 frames, processed or
  // dropped (how many are processed depends on the build: a sanitizer build perceives a frame
  // in 50 ms or more on a loaded machine).
  EXPECT_GE(s["frames"].get<int>() + s["frames_dropped"].get<int>(), 10);
  EXPECT_GE(s["frames"].get<int>(), 3);
  // A black picture has no tape (the default colour bars would: stripes a tape's width apart
  // are tape to a search for tape of any width, which a configured width falls back to; snow
  // is costly enough to perceive that a sanitizer build sees too few frames in a second).
  EXPECT_EQ(s["frames_lost"], s["frames"]);
  EXPECT_TRUE(is_stop(read_jsonl(dir_ / "live" / "commands.jsonl").back()));
  const auto refused = run_agv("track --quiet --as-fast-as-possible " + pipeline + camera() +
                               " --out " + path("refused"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("live"), std::string::npos) << refused.output;
}

// A camera that stalls: raw frames piped into a GStreamer pipeline (fdsrc), 15 frames, then
// nothing for 1.5 s, then 15 more. The watchdog reports the camera thread silent, the vehicle is
// stopped (after the hold time, within its acceleration limit) while no frames come, and it
// drives on when they come again.
TEST_F(AgvTrack, AStallingSourceIsReportedAndTheVehicleStops) {
  make_video(1);
  const std::string command =
      std::string(AGV_BINARY) +
      " track --quiet \"fdsrc ! rawvideoparse width=640 height=480 format=bgr framerate=10/1 ! "
      "videoconvert ! video/x-raw,format=BGR ! appsink\"" +
      camera() + " --out " + path("stall") + " > " + path("stall.log") + " 2>&1";
  FILE* pipe = popen(command.c_str(), "w");
  ASSERT_NE(pipe, nullptr);
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(dir_ / "dataset" / "frames"))
    frames.push_back(entry.path());
  std::sort(frames.begin(), frames.end());
  auto send = [&](size_t from, size_t to) {
    for (size_t i = from; i < to; ++i) {
      const cv::Mat frame = cv::imread(frames[i % frames.size()].string());
      fwrite(frame.data, 1, frame.total() * frame.elemSize(), pipe);
      fflush(pipe);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  };
  send(0, 15);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  send(15, 30);
  const int status = pclose(pipe);
  std::ifstream log(path("stall.log"));
  const std::string output((std::istreambuf_iterator<char>(log)), {});
  if (WEXITSTATUS(status) == 2 && output.find("cannot open") != std::string::npos)
    GTEST_SKIP() << "no GStreamer fdsrc / rawvideoparse here: " << output;
  ASSERT_EQ(WEXITSTATUS(status), 0) << output;
  const nlohmann::json s = read_json(dir_ / "stall" / "summary.json");
  bool camera_reported = false;
  for (const auto& stall : s["tracking"]["watchdog_stalls"])
    camera_reported |= stall["thread"] == "camera" && stall["silent_for_s"].get<double>() >= 1.0;
  EXPECT_TRUE(camera_reported) << s["tracking"].dump();
  const std::vector<nlohmann::json> commands = read_jsonl(dir_ / "stall" / "commands.jsonl");
  bool stopped_in_stall = false, moving_after = false;
  for (size_t i = 1; i < commands.size(); ++i) {
    const bool stale = !commands[i]["age_s"].is_null() && commands[i]["age_s"].get<double>() > 0.8;
    if (stale && is_stop(commands[i])) stopped_in_stall = true;
    if (stopped_in_stall && commands[i]["v_x_m_s"].get<double>() > 0.1) moving_after = true;
    // Never faster than the acceleration limit allows (0.5 m/s^2 over 0.1 s), plus rounding.
    EXPECT_LE(
        std::abs(commands[i]["v_x_m_s"].get<double>() - commands[i - 1]["v_x_m_s"].get<double>()),
        0.05 + 1e-9);
  }
  EXPECT_TRUE(stopped_in_stall);
  EXPECT_TRUE(moving_after);
  EXPECT_TRUE(is_stop(commands.back()));
}

// A bare folder of real images (no manifest: name order, times from --fps) replayed with a
// camera file: one measurement per image, the columns of DESIGN.md, a command per period.
// A camera file whose tape width is wrong (30 mm; the tape of yellow_junction_worn is 40 mm):
// perception still finds the tape, and track says so once, as soon as 15 frames show it, not
// only when the run ends; summary.json keeps the warning.
TEST_F(AgvTrack, SaysOnceAndEarlyThatTheTapeIsWiderThanTheCameraFileSays) {
  fs::copy(fs::path(AGV_SOURCE_DIR) / "datasets" / "yellow_junction_worn", path("yellow"),
           fs::copy_options::recursive);
  std::ifstream in(fs::path(path("yellow")) / "camera.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const size_t at = text.find("tape_width_m:");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find('\n', at) - at, "tape_width_m: 0.03");
  std::ofstream(fs::path(path("yellow")) / "camera.yaml") << text;
  const auto r =
      run_agv("track --quiet --as-fast-as-possible " + path("yellow") + " --out " + path("track"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string said = "the tape measures";
  const size_t first = r.output.find(said);
  ASSERT_NE(first, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(said, first + 1), std::string::npos) << "said twice:\n" << r.output;
  EXPECT_NE(r.output.find("median of 15 frames"), std::string::npos) << r.output;
  const nlohmann::json s = read_json(dir_ / "track" / "summary.json");
  ASSERT_EQ(s["warnings"].size(), 1u);
  EXPECT_NE(s["warnings"][0].get<std::string>().find(said), std::string::npos);
  EXPECT_EQ(s["frames_lost"].get<int>(), 0);
}

// Replaying for a vehicle whose drive cannot make the sideways speed the chosen law commands
// (dual steer rear_drive with finite_step): the run says so once on stderr and in summary.json.
TEST_F(AgvTrack, ADriveThatCannotMoveSidewaysWithASidewaysLawIsWarnedOf) {
  const auto r = run_agv("replay --quiet --no-video " + std::string(AGV_SOURCE_DIR) +
                         "/datasets/blue_concrete_straight --set vehicle.kind=dual_steer --set "
                         "vehicle.dual_steer.drive_form=rear_drive --out " +
                         path("replay"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string said = "rear_drive cannot move its reference point sideways";
  const size_t first = r.output.find(said);
  ASSERT_NE(first, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(said, first + 1), std::string::npos) << "said twice:\n" << r.output;
  const nlohmann::json s = read_json(dir_ / "replay" / "summary.json");
  ASSERT_EQ(s["warnings"].size(), 1u);
  EXPECT_NE(s["warnings"][0].get<std::string>().find(said), std::string::npos);
}

TEST_F(AgvTrack, ReplaysABareFolderOfRealImages) {
  const std::string images = std::string(AGV_SHARED_DIR) + "/data/real/rcj_black_tape_topdown";
  const auto r = run_agv("replay --quiet --no-video " + images + " --camera " + AGV_SOURCE_DIR +
                         "/datasets/cameras/rcj_topdown.yaml --fps 5 --out " + path("real"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir_ / "real" / "measurements.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("index,t_s,line_found,e_theta_rad,e_d_m,curvature_1_m,confidence,"
                         "tape_width_m,no_line_reason",
                         0),
            0u)
      << header;
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 6);
  const nlohmann::json s = read_json(dir_ / "real" / "summary.json");
  EXPECT_EQ(s["source_kind"], "image folder");
  EXPECT_EQ(s["frames_lost"].get<int>(), 0);                            // every frame shows tape
  EXPECT_EQ(read_jsonl(dir_ / "real" / "commands.jsonl").size(), 11u);  // 0 .. 1.0 s every 0.1 s
  const auto no_fps = run_agv("replay --quiet " + images + " --camera " + AGV_SOURCE_DIR +
                              "/datasets/cameras/rcj_topdown.yaml --out " + path("x"));
  EXPECT_EQ(no_fps.exit_code, 2);
  EXPECT_NE(no_fps.output.find("--fps"), std::string::npos) << no_fps.output;
}

}  // namespace
