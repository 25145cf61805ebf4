#include "tools/top_view_plots.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace agv::tools {
namespace {

namespace fs = std::filesystem;

// Each NAME_top.csv of the folder gets NAME_top.png beside it, a real picture; other files are
// left alone.
TEST(TopViewPlots, DrawsAPictureForEachTable) {
  const fs::path dir =
      fs::temp_directory_path() / ("agv_top_view_plots_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "sequence001_frame002_top.csv")
      << "kind,x_m,y_m\ntape_laid,0.1,0\ntape_laid,0.2,0.001\nremembered,0.1,0.0005\n"
         "followed,0.2,0.0002\nother_line,0.25,0.05\n";
  std::ofstream(dir / "sequence001_frame002.png") << "not touched";
  std::ofstream(dir / "notes_top.txt") << "not a table";
  EXPECT_EQ(plot_top_views(dir.string()), 1);
  const cv::Mat picture = cv::imread((dir / "sequence001_frame002_top.png").string());
  ASSERT_FALSE(picture.empty());
  EXPECT_EQ(picture.cols, 1100);
  EXPECT_EQ(picture.rows, 700);
  EXPECT_FALSE(fs::exists(dir / "notes_top.png"));
  fs::remove_all(dir);
  fs::create_directories(dir);
  EXPECT_EQ(plot_top_views(dir.string()), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace agv::tools
