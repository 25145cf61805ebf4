#pragma once

#include <stdexcept>
#include <string>

namespace agv {

// Bad input from outside the program (file, YAML, CSV, frame, command line). The message
// names the file and the field or row. Tools catch it at the top and exit with code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace agv
