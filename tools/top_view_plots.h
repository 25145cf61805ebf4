#pragma once

#include <string>

namespace agv::tools {

// For each `NAME_top.csv` in `folder` (written by agv evaluate's sequences for a failed frame:
// kind,x_m,y_m in the vehicle frame), NAME_top.png: a top view of the tapes laid, what the path
// memory holds and the lines in view, to equal scale, the vehicle origin marked. Returns the
// number of pictures written, or throws std::runtime_error with what gnuplot said.
int plot_top_views(const std::string& folder);

}  // namespace agv::tools
