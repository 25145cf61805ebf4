#include "pipeline/evaluation/top_view_table.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "control/path.h"

namespace agv::pipeline {
namespace {

namespace fs = std::filesystem;

struct Row {
  std::string kind;
  double x_m, y_m;
};

std::vector<Row> read_table(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "kind,x_m,y_m");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    Row row;
    std::string x, y;
    std::getline(fields, row.kind, ',');
    std::getline(fields, x, ',');
    std::getline(fields, y, ',');
    row.x_m = std::stod(x);
    row.y_m = std::stod(y);
    rows.push_back(row);
  }
  return rows;
}

// The vehicle at (1, 2) facing +y (yaw 90 deg): a tape laid from under it along +y lies along
// its x axis (forward) at y = 0, worked out by hand, not through the code's transform; a tape 10
// m away and a remembered point 0.9 m away lie beyond the view's reach; the chords of the line
// followed and of the other line keep their kinds.
TEST(TopViewTable, PutsEveryPointInTheVehicleFrameByKind) {
  const fs::path file =
      fs::temp_directory_path() / ("agv_top_view_" + std::to_string(::getpid()) + ".csv");
  TapeStrip ahead, far;
  ahead.path = control::Path::starting_at({1.0, 2.0, M_PI / 2.0}).add_line(0.3);
  far.path = control::Path::starting_at({11.0, 12.0, 0.0}).add_line(0.3);
  perception::LineDetection detection;
  detection.chords = {{{0.2, 0.01}, {0.2, -0.01}}, {{0.3, 0.07}, {0.3, 0.03}}};
  detection.lines.resize(2);
  detection.lines[0].chords = {0};
  detection.lines[1].chords = {1};
  detection.followed = 1;
  write_top_view_table(file.string(), {1.0, 2.0, M_PI / 2.0}, {{0.1, 0.02}, {0.9, 0.0}}, detection,
                       {ahead, far});
  const std::vector<Row> rows = read_table(file);
  fs::remove(file);

  std::map<std::string, int> count;
  for (const Row& row : rows) {
    ++count[row.kind];
    if (row.kind == "tape_laid") {
      EXPECT_NEAR(row.y_m, 0.0, 1e-6);
      EXPECT_GE(row.x_m, -1e-6);
      EXPECT_LE(row.x_m, 0.3 + 1e-6);
    } else if (row.kind == "remembered") {
      EXPECT_NEAR(row.x_m, 0.1, 1e-6);
      EXPECT_NEAR(row.y_m, 0.02, 1e-6);
    } else if (row.kind == "followed") {
      EXPECT_NEAR(row.x_m, 0.3, 1e-6);
      EXPECT_NEAR(row.y_m, 0.05, 1e-6);
    } else if (row.kind == "other_line") {
      EXPECT_NEAR(row.x_m, 0.2, 1e-6);
      EXPECT_NEAR(row.y_m, 0.0, 1e-6);
    } else {
      ADD_FAILURE() << "unknown kind " << row.kind;
    }
  }
  EXPECT_GE(count["tape_laid"], 150);  // every 2 mm over 0.3 m
  EXPECT_LE(count["tape_laid"], 151);
  EXPECT_EQ(count["remembered"], 1);
  EXPECT_EQ(count["followed"], 1);
  EXPECT_EQ(count["other_line"], 1);
}

TEST(TopViewTable, SaysWhenItCannotWrite) {
  EXPECT_THROW(write_top_view_table("/nonexistent-folder/top.csv", {}, {}, {}, {}),
               std::runtime_error);
}

}  // namespace
}  // namespace agv::pipeline
