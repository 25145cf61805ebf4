#include "tools/top_view_plots.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "tools/gnuplot.h"

namespace agv::tools {

int plot_top_views(const std::string& folder) {
  namespace fs = std::filesystem;
  const std::string suffix = "_top.csv";
  std::vector<fs::path> tables;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > suffix.size() && name.ends_with(suffix)) tables.push_back(entry.path());
  }
  std::sort(tables.begin(), tables.end());
  for (const fs::path& table : tables) {
    const std::string stem = table.filename().string();
    const std::string base = stem.substr(0, stem.size() - suffix.size());
    fs::path picture = table;
    picture.replace_filename(base + "_top.png");
    const std::string data = gnuplot_quote(table.string());
    // Rows of one kind: the others are NaN (not drawn).
    auto of_kind = [&](const std::string& kind) {
      return data + " using (strcol(1) eq '" + kind + "' ? $2 : NaN):3";
    };
    std::ostringstream script;
    script << "set terminal pngcairo size 1100,700 font 'DejaVu Sans,11'\n"
           << "set output " << gnuplot_quote(picture.string()) << "\n"
           << "set datafile separator ','\n"
           << "set title " << gnuplot_quote(base + ": the path memory in the vehicle frame")
           << " noenhanced\n"
           << "set size ratio -1\nset grid\nset key below horizontal\n"
           << "set xlabel 'x, forward (m)'\nset ylabel 'y, left (m)'\n"
           << "plot " << of_kind("tape_laid")
           << " with points pt 7 ps 0.4 lc rgb '#c8c8c8' title 'tapes laid (centre lines)', "
           << of_kind("remembered")
           << " with points pt 7 ps 0.5 lc rgb '#1f77b4' title 'remembered centre points', "
           << of_kind("followed")
           << " with points pt 7 ps 0.5 lc rgb '#2ca02c' title 'followed line (chord centres)', "
           << of_kind("other_line")
           << " with points pt 7 ps 0.5 lc rgb '#ff7f0e' title 'other lines in view', "
           << "'-' using 1:2 with points pt 2 ps 2 lw 2 lc rgb '#d62728' title 'vehicle origin'\n"
           << "0,0\ne\n";
    if (const std::string failure = run_gnuplot(script.str()); !failure.empty())
      throw std::runtime_error(picture.string() + ": " + failure);
  }
  return static_cast<int>(tables.size());
}

}  // namespace agv::tools
