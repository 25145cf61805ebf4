#pragma once

#include <string>
#include <vector>

namespace agv::tools {

// A table of text cells written three ways: Markdown for people, CSV for scripts (one header
// row of unit-named keys), HTML for the report page. Cells are already formatted; an empty
// cell means "not defined" (e.g. the settle time of a run that never settles).
class ReportTable {
 public:
  struct Column {
    std::string key;      // CSV header: settle_time_s
    std::string heading;  // Markdown / HTML header: settle (s)
  };

  explicit ReportTable(std::vector<Column> columns) : columns_(std::move(columns)) {}
  void add_row(std::vector<std::string> cells);  // one cell per column

  std::string markdown(const std::string& empty_cell = "n/a") const;
  std::string csv() const;
  std::string html(const std::string& empty_cell = "n/a") const;

 private:
  std::vector<Column> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// Escapes &, <, > and quotes for HTML text.
std::string html_escape(const std::string& text);

}  // namespace agv::tools
