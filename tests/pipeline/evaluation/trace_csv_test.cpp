#include "pipeline/evaluation/trace_csv.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace agv::pipeline {
namespace {

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// measurements.csv as DESIGN.md defines it: the required columns by name, one row per frame
// with as many cells as the header (a reason with commas in it must not add cells), the values
// in the right columns, and an empty reason where a line was found.
TEST(TraceCsv, MeasurementsHaveDesignsColumnsAndOneCellEach) {
  FrameRecord found;
  found.index = 3;
  found.stamp_s = 0.3;
  found.measurement.line_found = true;
  found.measurement.e_theta_rad = 0.0125;
  found.measurement.e_d_m = -0.004;
  found.measurement.confidence = 0.9;
  FrameRecord lost;
  lost.index = 4;
  lost.stamp_s = 0.4;
  lost.no_line_reason = "tape width 15 mm, not 25 mm, unlike the tape seen";
  std::ostringstream out;
  write_measurements_csv(out, {found, lost}, false);
  std::stringstream text(out.str());
  std::string header, row_found, row_lost;
  std::getline(text, header);
  std::getline(text, row_found);
  std::getline(text, row_lost);
  const std::vector<std::string> names = cells(header);
  auto column = [&](const std::string& name) {
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    ADD_FAILURE() << "no column " << name << " in " << header;
    return 0;
  };
  for (const char* name : {"index", "t_s", "line_found", "e_theta_rad", "e_d_m", "curvature_1_m",
                           "confidence", "tape_width_m", "no_line_reason"})
    column(name);
  const std::vector<std::string> a = cells(row_found), b = cells(row_lost);
  ASSERT_EQ(a.size(), names.size()) << row_found;
  ASSERT_EQ(b.size(), names.size()) << row_lost;
  EXPECT_EQ(a[column("index")], "3");
  EXPECT_EQ(a[column("line_found")], "1");
  EXPECT_DOUBLE_EQ(std::stod(a[column("e_theta_rad")]), 0.0125);
  EXPECT_DOUBLE_EQ(std::stod(a[column("e_d_m")]), -0.004);
  EXPECT_EQ(a[column("no_line_reason")], "");
  EXPECT_EQ(b[column("line_found")], "0");
  EXPECT_NE(b[column("no_line_reason")].find("tape width 15 mm"), std::string::npos);
}

}  // namespace
}  // namespace agv::pipeline
