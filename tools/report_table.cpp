#include "tools/report_table.h"

#include <cassert>

namespace agv::tools {

void ReportTable::add_row(std::vector<std::string> cells) {
  assert(cells.size() == columns_.size());
  rows_.push_back(std::move(cells));
}

std::string ReportTable::markdown(const std::string& empty_cell) const {
  std::string out = "|";
  for (const Column& c : columns_) out += " " + c.heading + " |";
  out += "\n|";
  for (size_t i = 0; i < columns_.size(); ++i) out += i == 0 ? "---|" : "---:|";
  out += "\n";
  for (const auto& row : rows_) {
    out += "|";
    for (const std::string& cell : row) out += " " + (cell.empty() ? empty_cell : cell) + " |";
    out += "\n";
  }
  return out;
}

std::string ReportTable::csv() const {
  // Keys and cells are words and numbers: nothing here needs CSV quoting except commas.
  auto field = [](const std::string& text) {
    return text.find_first_of(",\"") == std::string::npos ? text : "\"" + text + "\"";
  };
  std::string out;
  for (size_t i = 0; i < columns_.size(); ++i) out += (i ? "," : "") + field(columns_[i].key);
  out += "\n";
  for (const auto& row : rows_) {
    for (size_t i = 0; i < row.size(); ++i) out += (i ? "," : "") + field(row[i]);
    out += "\n";
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string ReportTable::html(const std::string& empty_cell) const {
  std::string out = "<table class=\"sortable\">\n<tr>";
  for (const Column& c : columns_) out += "<th>" + html_escape(c.heading) + "</th>";
  out += "</tr>\n";
  for (const auto& row : rows_) {
    out += "<tr>";
    for (size_t i = 0; i < row.size(); ++i) {
      out += i == 0 ? "<td>" : "<td class=\"num\">";
      out += html_escape(row[i].empty() ? empty_cell : row[i]) + "</td>";
    }
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

}  // namespace agv::tools
