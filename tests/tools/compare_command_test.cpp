// End-to-end: `agv compare` as a user runs it, on one machine and in shards.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/agv_process.h"

namespace {

namespace fs = std::filesystem;
using agv::testing::run_agv;
using AgvCompare = agv::testing::ScratchFolderTest;

// Three controllers on two short scenarios, one from camera frames and one from the pose (fast):
// 6 runs of 1 s. Monte Carlo runs use the pose scenario.
const char* kSuite = R"(name: small
seed: 5
controllers:
  - {name: shrinking, set: {controller.kind: finite_step}}
  - {name: fixed, set: {controller.kind: finite_step, controller.finite_step.horizon: fixed}}
  - {name: pid, about: "PID, the default gains", set: {controller.kind: pid}}
scenarios:
  - {name: table1, about: "Table 1, 1 s", set: {duration_s: 1.0}}
  - {name: table2, about: "Table 2, 1 s, pose input",
     set: {duration_s: 1.0, path_speed_m_s: 0.5, controller.input: pose}}
monte_carlo: {scenario: table2}
)";

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// table.csv without its last column (compute per period: measured, so it differs between runs).
std::string table_without_timing(const fs::path& file) {
  std::istringstream in(read(file));
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

class AgvCompareWithSuite : public AgvCompare {
 protected:
  void SetUp() override {
    AgvCompare::SetUp();
    std::ofstream(path("suite.yaml")) << kSuite;
  }
};

TEST_F(AgvCompareWithSuite, MergedShardsEqualTheSingleRun) {
  const auto single = run_agv("compare --quiet --jobs 2 --suite " + path("suite.yaml") + " --out " +
                              path("single"));
  ASSERT_EQ(single.exit_code, 0) << single.output;
  EXPECT_NE(single.output.find("6 runs"), std::string::npos) << single.output;
  for (const char* shard : {"1/3", "2/3", "3/3"}) {
    const std::string name = std::string("shard") + shard[0];
    const auto r = run_agv("compare --quiet --jobs 1 --suite " + path("suite.yaml") + " --shard " +
                           shard + " --out " + path(name));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir_ / name / "runs.jsonl"));
    EXPECT_FALSE(fs::exists(dir_ / name / "table.md"));  // a shard writes rows only
  }
  // In any order.
  const auto merged = run_agv("compare --quiet --merge " + path("shard3") + " " + path("shard1") +
                              " " + path("shard2") + " --out " + path("merged"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;

  const std::string table = table_without_timing(dir_ / "single" / "table.csv");
  EXPECT_EQ(table_without_timing(dir_ / "merged" / "table.csv"), table);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 7);  // header + 6 runs
  EXPECT_NE(table.find("table2,pid,"), std::string::npos);
  for (const char* scenario : {"table1", "table2"}) {
    const fs::path series = fs::path("series") / (std::string(scenario) + ".csv");
    EXPECT_EQ(read(dir_ / "merged" / series), read(dir_ / "single" / series)) << scenario;
    const fs::path png = fs::path("plots") / (std::string(scenario) + ".png");
    EXPECT_GT(fs::file_size(dir_ / "merged" / png), 10000u) << png;
  }
  const std::string page = read(dir_ / "merged" / "index.html");
  EXPECT_NE(page.find("plots/table2.png"), std::string::npos);
  EXPECT_NE(page.find("<td>fixed</td>"), std::string::npos);
  EXPECT_NE(read(dir_ / "merged" / "table.md").find("## table1"), std::string::npos);
  // The score matrix comes first: each controller with its line from the suite, each cell its
  // settle time as the table gives it; every table sorts.
  const size_t matrix = page.find("Settle time by controller and scenario");
  ASSERT_NE(matrix, std::string::npos);
  EXPECT_LT(matrix, page.find("id=\"table1\""));
  EXPECT_NE(page.find("PID, the default gains", matrix), std::string::npos);
  const size_t pid_row = table.find("table1,pid,") + std::string("table1,pid,").size();
  const std::string settle = table.substr(pid_row, table.find(',', pid_row) - pid_row);
  EXPECT_NE(
      page.find(">" + (settle.empty() ? std::string("never") : settle + " s") + "</td>", matrix),
      std::string::npos)
      << settle;
  EXPECT_NE(page.find("<table class=\"sortable\">"), std::string::npos);
}

TEST_F(AgvCompareWithSuite, MergeRefusesMissingRepeatedOrForeignShards) {
  const std::string suite = " --quiet --suite " + path("suite.yaml");
  ASSERT_EQ(run_agv("compare" + suite + " --shard 1/2 --out " + path("a")).exit_code, 0);
  ASSERT_EQ(run_agv("compare" + suite + " --shard 2/2 --seed 9 --out " + path("other")).exit_code,
            0);
  auto r = run_agv("compare --merge " + path("a") + " --out " + path("m"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("3 of 6 runs are missing"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("shards not given: 2 of 2"), std::string::npos) << r.output;
  r = run_agv("compare --merge " + path("a") + " " + path("other") + " --out " + path("m"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("another plan"), std::string::npos) << r.output;
  r = run_agv("compare --merge " + path("a") + " " + path("a") + " --out " + path("m"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("given twice"), std::string::npos) << r.output;
  r = run_agv("compare --merge " + path("nothing") + " --out " + path("m"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(path("nothing") + "/plan.json"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "m"));  // no partial result
}

TEST_F(AgvCompareWithSuite, MonteCarloReportsTheDistributionOfEveryController) {
  const auto r = run_agv("compare --quiet --suite " + path("suite.yaml") +
                         " --monte-carlo 4 --out " + path("mc"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "mc" / "distributions.png"));
  // monte_carlo.csv: 4 runs x 3 controllers; the summary's median of max |e_d| (after the
  // first measurement) per controller
  // is the middle of its 4 values by nearest rank (index round(0.5 * 3) = 2 of the sorted).
  std::istringstream runs(read(dir_ / "mc" / "monte_carlo.csv"));
  std::string line;
  std::getline(runs, line);
  std::map<std::string, std::vector<double>> max_e_d;
  while (std::getline(runs, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    const double initial_e_d_mm = std::stod(cells[3]);
    EXPECT_LE(std::abs(initial_e_d_mm), 20.0);         // the default suite's bound: 20 mm
    max_e_d[cells[1]].push_back(std::stod(cells[6]));  // after the first measurement
  }
  ASSERT_EQ(max_e_d.size(), 3u);
  std::istringstream summary(read(dir_ / "mc" / "summary.csv"));
  std::getline(summary, line);
  int rows = 0;
  while (std::getline(summary, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    std::vector<double> values = max_e_d.at(cells[0]);
    ASSERT_EQ(values.size(), 4u);
    std::sort(values.begin(), values.end());
    EXPECT_EQ(cells[1], "4");
    EXPECT_NEAR(std::stod(cells[6]), values[2], 0.006) << cells[0];  // 2 decimals vs 3
    EXPECT_NEAR(std::stod(cells[8]), values[3], 0.006) << cells[0];
    ++rows;
  }
  EXPECT_EQ(rows, 3);
}

TEST_F(AgvCompare, BadSuiteOrShardIsRefusedByName) {
  std::ofstream(path("bad.yaml")) << "controllers:\n  - {name: x, set: {controller.kind: lqr}}\n"
                                     "scenarios:\n  - {name: s}\n";
  auto r = run_agv("compare --quiet --suite " + path("bad.yaml") + " --out " + path("o"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("controller.kind"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lqr"), std::string::npos) << r.output;
  r = run_agv("compare --quiet --suite " + path("missing.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("missing.yaml"), std::string::npos) << r.output;
  r = run_agv("compare --quiet --shard 3/2 --out " + path("o"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--shard 3/2"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "o"));
}

}  // namespace
