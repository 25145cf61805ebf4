#include "tools/progress_bar.h"

#include <gtest/gtest.h>

namespace agv::tools {
namespace {

// At the same pace: a quarter done in 10 s leaves 30 s; half done in 100 s leaves 100 s; a
// tenth in 400 s leaves 3600 s. Nothing while there is too little to go by, or when done.
TEST(ProgressBar, TimeLeftAtThePaceSoFar) {
  EXPECT_EQ(time_left_words(10.0, 0.25), "about 30 s left");
  EXPECT_EQ(time_left_words(100.0, 0.5), "about 1 min 40 s left");
  EXPECT_EQ(time_left_words(400.0, 0.1), "about 1 h 0 min left");
  EXPECT_EQ(time_left_words(5.0, 0.005), "");
  EXPECT_EQ(time_left_words(0.1, 0.5), "");
  EXPECT_EQ(time_left_words(10.0, 1.0), "");
}

}  // namespace
}  // namespace agv::tools
