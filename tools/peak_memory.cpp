#include "tools/peak_memory.h"

#include <sys/resource.h>

namespace agv::tools {

double peak_rss_mb() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

}  // namespace agv::tools
