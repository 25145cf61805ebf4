#pragma once

#include <string>

namespace agv::tools {

// Runs gnuplot (Debian package gnuplot-nox) on a script. Returns an empty string on success,
// otherwise what went wrong (gnuplot missing, or its error output).
std::string run_gnuplot(const std::string& script);

// Quotes a file name for a gnuplot script.
std::string gnuplot_quote(const std::string& text);

}  // namespace agv::tools
