// Seeded random-mutation fuzzing (issue 8) of the inputs that come from outside: scenario YAML,
// camera YAML, manifest CSV and frame files. Each input from tests/fuzz/corpus is mutated many
// times (bit flips, cut, repeated and truncated ranges, numbers replaced by NaN, Inf, negative,
// huge or non-numeric text, YAML/CSV syntax characters inserted) and fed to the loader. Contract:
// it either accepts the input or throws InputError; any other exception fails the test (and a
// crash or sanitizer report fails the run). The input that broke it is written next to the
// test's working directory as fuzz_failure_<target>.bin to reproduce.
//
// Budget: AGV_FUZZ_ITERATIONS mutations per corpus file (default 150). Seeds: AGV_FUZZ_SEED
// (default 0) mixed with each corpus file's name, printed for every file; the same seed gives the
// same inputs on every run, and a failure names the seed and mutation to replay it with.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "common/input_error.h"
#include "perception/camera_file.h"
#include "pipeline/config/builtin_files.h"
#include "pipeline/config/scenario_loader.h"
#include "pipeline/dataset.h"
#include "pipeline/dataset_source.h"
#include "pipeline/perceiver.h"

namespace agv {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(AGV_SOURCE_DIR) / "tests" / "fuzz" / "corpus";

int iterations() {
  const char* text = std::getenv("AGV_FUZZ_ITERATIONS");
  return text ? std::max(1, std::atoi(text)) : 150;
}

// The run's base seed (AGV_FUZZ_SEED, default 0).
std::uint64_t base_seed() {
  const char* text = std::getenv("AGV_FUZZ_SEED");
  return text ? std::strtoull(text, nullptr, 10) : 0;
}

// The generator's seed for one corpus file: the base seed mixed with the file's name.
std::uint64_t seed_for(const std::string& name) {
  return base_seed() ^ std::hash<std::string>{}(name);
}

std::string replay_hint(const std::string& name, int mutation) {
  return " [" + name + " seed " + std::to_string(seed_for(name)) + ", mutation " +
         std::to_string(mutation) + "; replay: AGV_FUZZ_SEED=" + std::to_string(base_seed()) + "]";
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

// One random edit of the input.
std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  static const std::vector<std::string> numbers = {
      "nan", ".nan", "inf",   "-inf",   "-1",
      "0",   "-0",   "1e308", "-1e308", "1e-320",
      "abc", "",     "[]",    "{}",     "9999999999999999999999"};
  static const std::vector<std::string> syntax = {
      ":",  "[",        "]", "{",  "}",    "\n", "- ",          "\"",    "'", "&a",
      "*a", "!!binary", ",", "\t", "\r\n", "#",  "%YAML:1.0\n", "---\n", "\0"};
  switch (rng() % 6) {
    case 0:  // flip bits of a few bytes
      for (int k = 0; k < 1 + static_cast<int>(rng() % 4) && !s.empty(); ++k)
        s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
      break;
    case 1: {  // cut a range
      const size_t at = pick(s.size()), n = pick(std::min<size_t>(64, s.size() - at) + 1);
      s.erase(at, n);
      break;
    }
    case 2: {  // repeat a range
      const size_t at = pick(s.size()), n = pick(std::min<size_t>(64, s.size() - at) + 1);
      s.insert(at, s.substr(at, n));
      break;
    }
    case 3:  // truncate
      s.resize(pick(s.size() + 1));
      break;
    case 4: {  // replace a number by a bad one
      std::vector<size_t> starts;
      for (size_t i = 0; i < s.size(); ++i) {
        const bool digit = (s[i] >= '0' && s[i] <= '9');
        if (digit && (i == 0 || !((s[i - 1] >= '0' && s[i - 1] <= '9') || s[i - 1] == '.')))
          starts.push_back(i);
      }
      if (starts.empty()) break;
      const size_t at = starts[pick(starts.size())];
      size_t end = at;
      while (end < s.size() &&
             ((s[end] >= '0' && s[end] <= '9') || s[end] == '.' || s[end] == 'e' || s[end] == '-'))
        ++end;
      s.replace(at, end - at, numbers[pick(numbers.size())]);
      break;
    }
    default:  // insert syntax
      s.insert(pick(s.size() + 1), syntax[pick(syntax.size())]);
      break;
  }
  return s;
}

// Runs `load` on `iterations()` mutations of each corpus file of `target`; fails on anything
// but success or InputError.
template <typename Load>
void fuzz(const std::string& target, Load load) {
  std::vector<fs::path> seeds;
  for (const auto& entry : fs::directory_iterator(kCorpus / target)) seeds.push_back(entry.path());
  std::sort(seeds.begin(), seeds.end());
  ASSERT_FALSE(seeds.empty()) << target;
  int accepted = 0, rejected = 0;
  for (const fs::path& seed : seeds) {
    const std::string original = read_file(seed);
    // The unmutated seed must load: otherwise the fuzzing only ever tests the rejection path.
    ASSERT_NO_THROW(load(original, seed)) << seed;
    const std::string name = seed.filename().string();
    std::printf("%s/%s: seed %llu\n", target.c_str(), name.c_str(),
                static_cast<unsigned long long>(seed_for(name)));
    std::mt19937_64 rng(seed_for(name));
    for (int i = 0; i < iterations(); ++i) {
      std::string input = original;
      const int edits = 1 + static_cast<int>(rng() % 3);
      for (int e = 0; e < edits; ++e) input = mutate(input, rng);
      try {
        load(input, seed);
        ++accepted;
      } catch (const InputError&) {
        ++rejected;
      } catch (const std::exception& e) {
        write_file("fuzz_failure_" + target + ".bin", input);
        FAIL() << target << ": not an InputError: " << e.what() << replay_hint(name, i);
      }
    }
  }
  std::printf("%s: %d mutated inputs accepted, %d rejected with InputError\n", target.c_str(),
              accepted, rejected);
  EXPECT_GT(rejected, 0) << "the mutations never reached the checks";
}

class MutationFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("agv_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(MutationFuzz, ScenarioYaml) {
  fuzz("scenario", [](const std::string& text, const fs::path& seed) {
    const pipeline::Scenario s = pipeline::load_scenario(
        {text, seed.filename().string(), "", pipeline::builtin_files()}, {});
    // Accepted means usable: the numbers the loop divides by or steps with are sane.
    if (!(s.duration_s > 0.0 && s.controller.ts_s > 0.0 && std::isfinite(s.path_speed_m_s)))
      throw std::logic_error("accepted a scenario with unusable timing");
  });
}

TEST_F(MutationFuzz, CameraYaml) {
  fuzz("camera", [](const std::string& text, const fs::path& seed) {
    const perception::CameraFile camera =
        perception::parse_camera_text(text, seed.filename().string());
    if (camera.mount) (void)perception::camera_model_of(camera, seed.filename().string());
  });
}

TEST_F(MutationFuzz, ManifestCsv) {
  const fs::path dataset = dir_ / "dataset";
  fs::create_directories(dataset / "frames");
  fs::copy_file(fs::path(AGV_SOURCE_DIR) / "datasets" / "blue_concrete_straight" / "camera.yaml",
                dataset / "camera.yaml");
  for (int i = 0; i < 6; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "frames/%06d.jpg", i);
    fs::copy_file(kCorpus / "frame" / "tape.jpg", dataset / name);
  }
  fuzz("manifest", [&](const std::string& text, const fs::path&) {
    write_file(dataset / "manifest.csv", text);
    (void)pipeline::open_dataset(dataset.string(), "", 0.0, false);
  });
}

// The frame path of replay: a dataset of one frame whose file is mutated (JPEG, and PNG made
// from it), read, checked and measured. Checked: the unmutated frame loads and gives the line
// (the blue tape it shows); a mutated file is either rejected with InputError or measured
// (a corrupt JPEG often still decodes, into garbage blocks) into a well-formed measurement:
// finite errors, confidence in [0, 1], a reason when no line; and some mutations are rejected
// (the checks are reached).
TEST_F(MutationFuzz, FrameFiles) {
  const fs::path dataset = dir_ / "frames_dataset";
  fs::create_directories(dataset / "frames");
  fs::copy_file(fs::path(AGV_SOURCE_DIR) / "datasets" / "blue_concrete_straight" / "camera.yaml",
                dataset / "camera.yaml");
  // A PNG seed beside the JPEG one, made here (the corpus keeps only the small JPEG).
  const fs::path png_seed = dir_ / "png_seed";
  fs::create_directories(png_seed);
  cv::imwrite((png_seed / "tape.png").string(),
              cv::imread((kCorpus / "frame" / "tape.jpg").string()));
  int all_rejected = 0, all_measured_mutated = 0;
  for (const fs::path& seed : {kCorpus / "frame" / "tape.jpg", png_seed / "tape.png"}) {
    const std::string extension = seed.extension().string();
    const std::string name = seed.filename().string();
    write_file(dataset / "manifest.csv", "index,t_s,file\n0,0.0,frames/000000" + extension + "\n");
    const std::string original = read_file(seed);
    std::printf("frame/%s: seed %llu\n", name.c_str(),
                static_cast<unsigned long long>(seed_for(name)));
    std::mt19937_64 rng(seed_for(name));
    // Each run builds replay's floor map (~0.3 s): a fifth of the budget.
    const int runs = std::max(2, iterations() / 5);
    int rejected = 0, measured = 0;
    for (int i = 0; i < runs; ++i) {
      write_file(dataset / "frames" / ("000000" + extension),
                 i == 0 ? original : mutate(original, rng));
      try {
        pipeline::Dataset d = pipeline::open_dataset(dataset.string(), "", 0.0, false);
        const perception::CameraModel camera = perception::camera_model_of(d.camera, "camera");
        pipeline::DatasetSource source(std::move(d), /*pass_bad_frames=*/false);
        perception::LineEstimator::Options options;
        options.tape.width_m = 0.025;
        pipeline::ImagePerceiver perceiver(camera, options, /*path_memory=*/false);
        perception::LineDetection seen;
        const LineMeasurement m = perceiver.measure(*source.next(), &seen);
        ++measured;
        if (i == 0) {
          EXPECT_TRUE(m.line_found) << "the unmutated frame " << name;
        }
        if (m.line_found) {
          EXPECT_TRUE(std::isfinite(m.e_d_m) && std::isfinite(m.e_theta_rad) &&
                      std::isfinite(m.curvature_1_m))
              << replay_hint(name, i);
          EXPECT_TRUE(m.confidence >= 0.0 && m.confidence <= 1.0) << replay_hint(name, i);
        } else {
          EXPECT_FALSE(seen.rejected_because.empty()) << replay_hint(name, i);
        }
      } catch (const InputError& e) {
        if (i == 0)
          ADD_FAILURE() << "the unmutated frame " << name << " was rejected: " << e.what();
        ++rejected;
      } catch (const std::exception& e) {
        write_file("fuzz_failure_frame" + extension,
                   read_file(dataset / "frames" / ("000000" + extension)));
        FAIL() << "frame" << extension << ": not an InputError: " << e.what()
               << replay_hint(name, i);
      }
    }
    std::printf("frame%s: %d of %d mutated files rejected with InputError, %d measured\n",
                extension.c_str(), rejected, runs, measured);
    all_rejected += rejected;
    all_measured_mutated += measured - 1;
  }
  // A corrupt JPEG nearly always decodes; a corrupt PNG nearly never (its CRCs).
  EXPECT_GT(all_rejected, 0) << "the mutations never reached the frame checks";
  EXPECT_GT(all_measured_mutated, 0) << "no mutated frame was measured";
}

}  // namespace
}  // namespace agv
