#include "pipeline/command_stream.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "common/input_error.h"

namespace agv::pipeline {
namespace {

// The address of "HOST:PORT" for UDP, as sockaddr bytes.
std::string resolve_udp(const std::string& udp) {
  const size_t colon = udp.rfind(':');
  const std::string option = "--udp " + udp;
  if (colon == std::string::npos || colon == 0 || colon + 1 == udp.size())
    throw InputError(option + ": expected HOST:PORT, such as 192.168.1.20:5005");
  const std::string host = udp.substr(0, colon), port = udp.substr(colon + 1);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const int error = getaddrinfo(host.c_str(), port.c_str(), &hints, &found);
  if (error != 0 || !found)
    throw InputError(option + ": cannot resolve the address (" + gai_strerror(error) + ")");
  std::string address(reinterpret_cast<const char*>(found->ai_addr), found->ai_addrlen);
  freeaddrinfo(found);
  return address;
}

}  // namespace

std::string command_json_line(const TraceRow& row) {
  const BodyTwist& c = row.output.command;
  nlohmann::ordered_json j = {{"t_s", row.t_s},
                              {"v_x_m_s", c.vx_m_s},
                              {"v_y_m_s", c.vy_m_s},
                              {"w_z_rad_s", c.wz_rad_s},
                              {"line_found", row.has_measurement && row.measurement.line_found},
                              {"e_theta_rad", nullptr},
                              {"e_d_m", nullptr},
                              {"age_s", nullptr}};
  if (row.has_measurement) {
    j["age_s"] = row.measurement_age_s;
    if (row.measurement.line_found) {
      j["e_theta_rad"] = row.measurement.e_theta_rad;
      j["e_d_m"] = row.measurement.e_d_m;
    }
  }
  return j.dump();
}

CommandStream::CommandStream(const std::filesystem::path& file, const std::string& udp)
    : file_(file), path_(file) {
  if (!file_) throw InputError(file.string() + ": cannot write the command stream");
  if (udp.empty()) return;
  address_ = resolve_udp(udp);
  const auto* address = reinterpret_cast<const sockaddr*>(address_.data());
  socket_ = ::socket(address->sa_family, SOCK_DGRAM, 0);
  if (socket_ < 0)
    throw InputError("--udp " + udp + ": cannot open a UDP socket (" + std::strerror(errno) + ")");
}

CommandStream::~CommandStream() {
  if (socket_ >= 0) ::close(socket_);
}

void CommandStream::send(const TraceRow& row) {
  const std::string line = command_json_line(row);
  file_ << line << '\n';
  ++lines_;
  if (socket_ < 0) return;
  const ssize_t sent = ::sendto(socket_, line.data(), line.size(), 0,
                                reinterpret_cast<const sockaddr*>(address_.data()),
                                static_cast<socklen_t>(address_.size()));
  if (sent != static_cast<ssize_t>(line.size())) ++udp_failures_;
}

bool CommandStream::finish() {
  file_.flush();
  return static_cast<bool>(file_);
}

}  // namespace agv::pipeline
