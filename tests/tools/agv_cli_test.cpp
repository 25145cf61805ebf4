// End-to-end: the `agv` program as a user runs it.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run(const std::string& arguments) {
  const std::string command = std::string(AGV_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

class AgvCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("agv_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(AgvCli, DefaultSimulationWritesItsResults) {
  const Result r = run("simulate --quiet --out " + path("run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("settle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("output: " + path("run")), std::string::npos) << r.output;
  for (const char* file : {"trace.csv", "frames.csv", "summary.json", "path.csv", "camera.yaml",
                           "errors.png", "path.png"}) {
    EXPECT_TRUE(fs::exists(dir_ / "run" / file)) << file;
  }
  std::ifstream in(dir_ / "run" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  for (const char* key :
       {"settle_time_s", "max_abs_e_d_m", "max_abs_e_theta_rad", "rms_e_d_m", "rms_e_theta_rad",
        "overshoot_e_d_m", "max_abs_v_lateral_m_s", "max_abs_accel_m_s2", "limit_violations",
        "frames", "frames_lost", "perception_rms_e_d_m", "perception_rms_e_theta_rad",
        "coverage_area_m2"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(summary["limit_violations"], 0);
  EXPECT_LE(summary["settle_time_s"].get<double>(), 1.2);
  // errors.png is a real PNG.
  std::ifstream png(dir_ / "run" / "errors.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

TEST_F(AgvCli, JsonSummaryOnStdout) {
  const Result r =
      run("simulate --quiet --no-plots --json --set duration_s=1 --out " + path("run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const size_t brace = r.output.find('{');
  ASSERT_NE(brace, std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(r.output.substr(brace))["frames"], 11);
}

// Bad input: one message naming the file or option and the key, exit code 2, no output folder.
TEST_F(AgvCli, BadInputExitsWithCode2AndLeavesNoResult) {
  std::ofstream(path("typo.yaml")) << "controller:\n  ts: 0.1\n";
  std::ofstream(path("bad_camera.yaml")) << "camera: " << path("missing_camera.yaml") << "\n";
  const std::pair<std::string, std::string> cases[] = {
      {"--scenario " + path("no_such.yaml"), "no_such.yaml"},
      {"--scenario " + path("typo.yaml"), "controller.ts"},
      {"--scenario " + path("bad_camera.yaml"), "missing_camera.yaml"},
      {"--set controller.ts_s=abc", "controller.ts_s"},
      {"--set duration_s=nan", "duration_s"},
      {"--set nonsense", "key=value"},
  };
  for (const auto& [arguments, expected] : cases) {
    const Result r = run("simulate --quiet " + arguments + " --out " + path("out"));
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << arguments << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << arguments;
  }
  // Nothing half-written is left beside the target either.
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
  }
  EXPECT_EQ(run("simulate --no-such-option").exit_code, 2);
  EXPECT_EQ(run("").exit_code, 2);
}

TEST_F(AgvCli, HelpTellsWhatItDoes) {
  const Result r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("simulate"), std::string::npos);
  EXPECT_NE(r.output.find("bench"), std::string::npos);
  const Result s = run("simulate --help");
  EXPECT_NE(s.output.find("--scenario"), std::string::npos);
  EXPECT_NE(s.output.find("--set"), std::string::npos);
}

TEST_F(AgvCli, BenchPrintsTheDesignKeys) {
  const Result r = run("bench --frames 12 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  for (const char* key :
       {"render_us_median", "perceive_us_median", "perceive_us_p99",
        "baseline_canny_hough_us_median", "control_us_median", "closed_loop_fps"}) {
    EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j[key].get<double>(), 0.0) << key;
  }
}

}  // namespace
