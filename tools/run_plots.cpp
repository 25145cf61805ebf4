#include "tools/run_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/angles.h"
#include "tools/gnuplot.h"

namespace agv::tools {

void write_path_csv(const std::string& file, const control::Path& path) {
  std::ofstream out(file);
  out << "s_m,x_m,y_m\n" << std::setprecision(9);
  const int samples = std::max(2, static_cast<int>(std::ceil(path.length_m() / 0.01)) + 1);
  for (int i = 0; i < samples; ++i) {
    const double s = path.length_m() * i / (samples - 1);
    const Eigen::Vector2d p = path.point_at(s);
    out << s << ',' << p.x() << ',' << p.y() << '\n';
  }
}

std::string plot_run(const pipeline::OutputFolder& folder, const pipeline::Scenario& s,
                     const std::string& title) {
  const std::string trace = gnuplot_quote(folder.file("trace.csv").string());
  const std::string frames = gnuplot_quote(folder.file("frames.csv").string());
  const double band_d_mm = 1e3 * s.metrics.settle_band_e_d_m;
  const double band_theta_deg = rad_to_deg(s.metrics.settle_band_e_theta_rad);
  std::ostringstream errors;
  errors << "set terminal pngcairo size 1100,800 font 'DejaVu Sans,11'\n"
         << "set output " << gnuplot_quote(folder.file("errors.png").string()) << "\n"
         << "set datafile separator ','\n"
         << "set multiplot layout 2,1 title " << gnuplot_quote(title) << " noenhanced\n"
         << "set grid\nset key top right\n"
         << "set xlabel 'time (s)'\n"
         << "set ylabel 'lateral error e_{d} (mm)'\n"
         << "plot " << trace
         << " using 1:($6*1000) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true',"
         << " " << frames
         << " using 2:($5>0 ? $7*1000 : NaN) every ::1 with points pt 7 ps 0.6 lc rgb '#ff7f0e' "
            "title 'measured (at frame time)',"
         << " " << band_d_mm << " with lines dt 2 lc rgb '#555555' title 'settle band ±"
         << band_d_mm << " mm',"
         << " " << -band_d_mm << " with lines dt 2 lc rgb '#555555' notitle\n"
         << "set ylabel 'heading error e_{θ} (deg)'\n"
         << "plot " << trace
         << " using 1:($5*180/pi) every ::1 with lines lw 2 lc rgb '#1f77b4' title 'true',"
         << " " << frames
         << " using 2:($5>0 ? $6*180/pi : NaN) every ::1 with points pt 7 ps 0.6 lc rgb '#ff7f0e' "
            "title 'measured (at frame time)',"
         << " " << band_theta_deg << " with lines dt 2 lc rgb '#555555' title 'settle band ±"
         << std::setprecision(3) << band_theta_deg << " deg',"
         << " " << -band_theta_deg << " with lines dt 2 lc rgb '#555555' notitle\n"
         << "unset multiplot\n";
  std::string failure = run_gnuplot(errors.str());
  if (!failure.empty()) return failure;

  // A straight run's deviations are millimetres over metres: then the lateral axis is in mm.
  std::ifstream in(folder.file("trace.csv"));
  std::string line;
  std::getline(in, line);
  double x_lo = 1e9, x_hi = -1e9, y_lo = 1e9, y_hi = -1e9;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string t, x, y;
    std::getline(fields, t, ',');
    std::getline(fields, x, ',');
    std::getline(fields, y, ',');
    x_lo = std::min(x_lo, std::stod(x));
    x_hi = std::max(x_hi, std::stod(x));
    y_lo = std::min(y_lo, std::stod(y));
    y_hi = std::max(y_hi, std::stod(y));
  }
  const bool straight_along_x = (y_hi - y_lo) < 0.05 * std::max(1e-6, x_hi - x_lo) &&
                                std::abs(s.path.heading_at(0.0)) < 1e-9 &&
                                s.path.segments().size() == 1 &&
                                s.path.segments().front().curvature_1_m == 0.0;
  const double margin = 0.1 * std::max(x_hi - x_lo, 0.05);
  std::ostringstream path;
  path << "set terminal pngcairo size 1100,600 font 'DejaVu Sans,11'\n"
       << "set output " << gnuplot_quote(folder.file("path.png").string()) << "\n"
       << "set datafile separator ','\n"
       << "set grid\nset key top right\n"
       << "set title " << gnuplot_quote(title + " - top view") << " noenhanced\n"
       << "set xlabel 'x (m)'\n"
       << "set xrange [" << x_lo - margin << ":" << x_hi + margin << "]\n";
  if (straight_along_x) {
    path << "set ylabel 'y (mm, exaggerated)'\n"
         << "plot " << gnuplot_quote(folder.file("path.csv").string())
         << " using 2:($3*1000) every ::1 with lines lw 6 lc rgb '#9ecae1' title 'path (tape "
            "centre line)',"
         << " " << trace
         << " using 2:($3*1000) every ::1 with lines lw 2 lc rgb '#d62728' title 'vehicle "
            "reference point',"
         << " " << trace
         << " using 2:($3*1000) every ::1::1 with points pt 7 ps 1.5 lc rgb '#2ca02c' title "
            "'start'\n";
  } else {
    path << "set ylabel 'y (m)'\nset size ratio -1\n"
         << "plot " << gnuplot_quote(folder.file("path.csv").string())
         << " using 2:3 every ::1 with lines lw 6 lc rgb '#9ecae1' title 'path (tape centre line)',"
         << " " << trace
         << " using 2:3 every ::1 with lines lw 2 lc rgb '#d62728' title 'vehicle reference point',"
         << " " << trace
         << " using 2:3 every ::1::1 with points pt 7 ps 1.5 lc rgb '#2ca02c' title 'start'\n";
  }
  return run_gnuplot(path.str());
}

}  // namespace agv::tools
