#include "pipeline/evaluation/output_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "common/input_error.h"

namespace agv::pipeline {
namespace {

namespace fs = std::filesystem;

class OutputFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("agv_output_folder_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Everything in the scratch folder (temporary folders included).
  int entries() const {
    return static_cast<int>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

// A run that fails before commit() leaves nothing that looks like a result: no target, and no
// temporary folder beside it.
TEST_F(OutputFolderTest, WithoutCommitNothingIsLeft) {
  {
    OutputFolder out((dir_ / "run").string());
    std::ofstream(out.file("summary.json")) << "{}";
    EXPECT_FALSE(fs::exists(dir_ / "run"));  // written under another name until commit
  }
  EXPECT_EQ(entries(), 0);
}

TEST_F(OutputFolderTest, CommitPutsTheFilesInPlace) {
  {
    OutputFolder out((dir_ / "run").string());
    std::ofstream(out.file("summary.json")) << "{}";
    out.commit();
  }
  EXPECT_TRUE(fs::exists(dir_ / "run" / "summary.json"));
  EXPECT_EQ(entries(), 1);
}

// An existing result is replaced only with `replace`; a folder without the marker never is.
TEST_F(OutputFolderTest, ReplacesOnlyAPreviousResultAndOnlyWhenAsked) {
  fs::create_directories(dir_ / "run");
  std::ofstream(dir_ / "run" / "summary.json") << "{\"old\": 1}";
  EXPECT_THROW(OutputFolder((dir_ / "run").string()), InputError);
  {
    OutputFolder out((dir_ / "run").string(), "summary.json", /*replace=*/true);
    std::ofstream(out.file("frames.csv")) << "t_s\n";
    out.commit();
  }
  EXPECT_TRUE(fs::exists(dir_ / "run" / "frames.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "run" / "summary.json"));  // the old result is gone whole

  fs::create_directories(dir_ / "photos");
  std::ofstream(dir_ / "photos" / "holiday.jpg") << "not a result";
  EXPECT_THROW(OutputFolder((dir_ / "photos").string(), "summary.json", true), InputError);
  EXPECT_TRUE(fs::exists(dir_ / "photos" / "holiday.jpg"));
}

// An empty existing folder is simply used.
TEST_F(OutputFolderTest, AnEmptyFolderIsUsed) {
  fs::create_directories(dir_ / "empty");
  OutputFolder out((dir_ / "empty").string());
  std::ofstream(out.file("summary.json")) << "{}";
  out.commit();
  EXPECT_TRUE(fs::exists(dir_ / "empty" / "summary.json"));
}

}  // namespace
}  // namespace agv::pipeline
