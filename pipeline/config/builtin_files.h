#pragma once

#include <map>
#include <string>

namespace agv::pipeline {

// The built-in configuration files (pipeline/config/default_*.yaml), built into the library so
// that the program needs no data folder: name -> text.
const std::map<std::string, std::string>& builtin_files();

}  // namespace agv::pipeline
