#include "tools/gnuplot.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace agv::tools {

std::string gnuplot_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'')
      quoted += "''";
    else
      quoted += c;
  }
  return quoted + "'";
}

std::string run_gnuplot(const std::string& script) {
  namespace fs = std::filesystem;
  std::random_device random;
  const fs::path dir = fs::temp_directory_path();
  const fs::path script_path = dir / ("agv-plot-" + std::to_string(random()) + ".gp");
  const fs::path log_path = dir / ("agv-plot-" + std::to_string(random()) + ".log");
  {
    std::ofstream out(script_path);
    out << script;
  }
  const std::string command =
      "gnuplot " + script_path.string() + " > " + log_path.string() + " 2>&1";
  const int status = std::system(command.c_str());
  std::stringstream log;
  {
    std::ifstream in(log_path);
    log << in.rdbuf();
  }
  std::error_code error;
  fs::remove(script_path, error);
  fs::remove(log_path, error);
  if (status == 0) return "";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    return "gnuplot not found (install the Debian package gnuplot-nox)";
  }
  std::string message = log.str();
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return "gnuplot failed: " + message;
}

}  // namespace agv::tools
