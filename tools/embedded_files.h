#pragma once

#include <map>
#include <string>

namespace agv::tools {

// The files of tools/config, built into the program: name -> text.
const std::map<std::string, std::string>& embedded_files();

}  // namespace agv::tools
