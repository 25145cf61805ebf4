#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace agv::tools {

// The program's version and the git commit it was built from ("unknown" outside a clone).
std::string agv_version();
std::string agv_commit();

// {"version", "commit", "date"}: what every result file carries (date: now, local ISO 8601), so
// that a result can be traced to the program that made it.
nlohmann::json build_json();

// "agv 0.1.0, commit abc123, 2026-12-02 10:00": the same in words.
std::string build_words();

}  // namespace agv::tools
