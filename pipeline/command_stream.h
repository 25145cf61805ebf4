#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "pipeline/run_result.h"

namespace agv::pipeline {

// One line of the command stream of live tracking (shared/DESIGN.md): {"t_s", "v_x_m_s",
// "v_y_m_s", "w_z_rad_s", "line_found", "e_theta_rad", "e_d_m", "age_s"}, the errors and age
// of the newest measurement (null before the first one, the errors null when it found no line).
std::string command_json_line(const TraceRow& row);

// Sends each control period's command as one JSON line: into a file (commands.jsonl) and, if
// given an address, as one UDP datagram to a vehicle computer.
class CommandStream {
 public:
  // `udp`: "HOST:PORT" or empty. Throws InputError naming --udp when it cannot be used, or the
  // file when it cannot be written.
  CommandStream(const std::filesystem::path& file, const std::string& udp);
  ~CommandStream();
  CommandStream(const CommandStream&) = delete;
  CommandStream& operator=(const CommandStream&) = delete;

  void send(const TraceRow& row);
  // Flushes the file; false when a write failed.
  bool finish();
  std::uint64_t lines() const { return lines_; }
  std::uint64_t udp_failures() const { return udp_failures_; }

 private:
  std::ofstream file_;
  std::filesystem::path path_;
  int socket_ = -1;
  std::string address_;  // sockaddr bytes
  std::uint64_t lines_ = 0, udp_failures_ = 0;
};

}  // namespace agv::pipeline
