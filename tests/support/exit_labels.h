#pragma once

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace agv::perception {

// A real frame's hand label: its kind (straight, corner, crossing, curve_left, ...) and where the
// tape leaves the image (border -> pixel along it; "end" -> the row where the tape ends).
struct ExitLabel {
  std::string file, kind;
  std::map<std::string, double> exits;
};

// labels.csv as ../shared/data/real/rcj_black_tape_topdown and datasets/lines/* give it:
// file,kind,exits with exits as side:pixel pairs separated by ';'. Empty where the file is missing.
inline std::vector<ExitLabel> read_exit_labels(const std::string& csv_path) {
  std::vector<ExitLabel> labels;
  std::ifstream in(csv_path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    ExitLabel label;
    std::string exits;
    std::getline(fields, label.file, ',');
    std::getline(fields, label.kind, ',');
    std::getline(fields, exits, ',');
    std::stringstream parts(exits);
    std::string part;
    while (std::getline(parts, part, ';')) {
      const size_t colon = part.find(':');
      label.exits[part.substr(0, colon)] = std::stod(part.substr(colon + 1));
    }
    labels.push_back(label);
  }
  return labels;
}

}  // namespace agv::perception
