#pragma once

namespace agv::tools {

// The process's peak resident set size so far (getrusage's ru_maxrss), megabytes (2^20 bytes).
double peak_rss_mb();

}  // namespace agv::tools
