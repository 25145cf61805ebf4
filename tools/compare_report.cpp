#include "tools/compare_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "common/angles.h"
#include "common/input_error.h"
#include "common/statistics.h"
#include "tools/build_info.h"
#include "tools/gnuplot.h"
#include "tools/report_table.h"

namespace agv::tools {
namespace {

namespace fs = std::filesystem;
using pipeline::ComparePlan;
using pipeline::CompareRun;

std::string fixed(double value, int decimals) {
  if (std::isinf(value)) return "never";
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

std::string fixed(const std::optional<double>& value, double scale, int decimals) {
  return value ? fixed(*value * scale, decimals) : std::string();
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw InputError(file.string() + ": cannot write");
}

// The suite table: one row per run, scenario by scenario.
ReportTable metrics_table(bool with_scenario) {
  std::vector<ReportTable::Column> columns;
  if (with_scenario) columns.push_back({"scenario", "scenario"});
  columns.insert(columns.end(),
                 {{"controller", "controller"},
                  {"settle_time_s", "settle (s)"},
                  {"max_abs_e_d_mm", "max abs e_d (mm)"},
                  {"max_abs_e_theta_deg", "max abs e_θ (deg)"},
                  {"max_abs_e_d_acting_mm", "max abs e_d after the 1st measurement (mm)"},
                  {"rms_e_d_mm", "RMS e_d after settling (mm)"},
                  {"rms_e_theta_deg", "RMS e_θ after settling (deg)"},
                  {"overshoot_e_d_mm", "overshoot e_d (mm)"},
                  {"max_abs_v_lateral_m_s", "max abs lateral speed (m/s)"},
                  {"max_abs_accel_m_s2", "max abs accel (m/s²)"},
                  {"limit_violations", "limit violations"},
                  {"coverage_area_m2", "coverage area (m²)"},
                  {"frames_lost", "frames lost"},
                  {"max_measurement_age_ms", "max measurement age (ms)"},
                  {"control_us_per_period", "compute per period (µs)"}});
  return ReportTable(columns);
}

std::vector<std::string> metrics_cells(const CompareRun& r, bool with_scenario) {
  const pipeline::RunMetrics& m = r.metrics;
  std::vector<std::string> cells;
  if (with_scenario) cells.push_back(r.scenario);
  cells.insert(cells.end(),
               {r.controller, fixed(m.settle_time_s, 1.0, 2), fixed(1e3 * m.max_abs_e_d_m, 2),
                fixed(rad_to_deg(m.max_abs_e_theta_rad), 2),
                fixed(1e3 * m.max_abs_e_d_after_first_measurement_m, 2), fixed(m.rms_e_d_m, 1e3, 3),
                fixed(m.rms_e_theta_rad, 180.0 / M_PI, 3), fixed(1e3 * m.overshoot_e_d_m, 2),
                fixed(m.max_abs_v_lateral_m_s, 3), fixed(m.max_abs_accel_m_s2, 3),
                std::to_string(m.limit_violations), fixed(m.coverage_area_m2, 4),
                std::to_string(m.frames_lost), fixed(1e3 * r.max_measurement_age_s, 0),
                fixed(r.control_us_per_period, 1)});
  return cells;
}

std::vector<const CompareRun*> runs_of_scenario(const std::vector<CompareRun>& runs,
                                                const std::string& scenario) {
  std::vector<const CompareRun*> out;
  for (const CompareRun& r : runs)
    if (r.scenario == scenario) out.push_back(&r);
  return out;
}

// series/<scenario>.csv: the true errors of every controller against time (the plots' data).
void write_series(const fs::path& file, const std::vector<const CompareRun*>& runs) {
  std::ofstream out(file);
  out << "t_s";
  size_t rows = 0;
  for (const CompareRun* r : runs) {
    out << ',' << r->controller << "_e_d_mm," << r->controller << "_e_theta_deg";
    rows = std::max(rows, r->t_s.size());
  }
  out << '\n';
  for (size_t i = 0; i < rows; ++i) {
    const CompareRun* with_time = nullptr;
    for (const CompareRun* r : runs)
      if (i < r->t_s.size()) with_time = r;
    out << fixed(with_time->t_s[i], 3);
    for (const CompareRun* r : runs) {
      if (i < r->t_s.size())
        out << ',' << fixed(1e3 * r->e_d_m[i], 4) << ',' << fixed(rad_to_deg(r->e_theta_rad[i]), 4);
      else
        out << ",,";
    }
    out << '\n';
  }
  if (!out) throw InputError(file.string() + ": cannot write");
}

// Distinct line colours (matplotlib's tab10), one per controller in the plan's order.
const std::vector<std::string> kColours{"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                        "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

// plots/<scenario>.png: e_d and e_theta of every controller, with the settle bands, and |e_d| on
// a log axis, where convergence reads the same whatever the largest error in the plot.
std::string plot_scenario(const fs::path& series, const fs::path& png,
                          const pipeline::PlannedScenario& scenario,
                          const std::vector<const CompareRun*>& runs) {
  const double band_mm = 1e3 * runs.front()->settle_band_e_d_m;
  const double band_deg = rad_to_deg(runs.front()->settle_band_e_theta_rad);
  const std::string data = gnuplot_quote(series.string());
  std::ostringstream script;
  script << "set terminal pngcairo size 1100,1100 font 'DejaVu Sans,11'\n"
         << "set output " << gnuplot_quote(png.string()) << "\n"
         << "set datafile separator ','\nset datafile missing ''\n"
         << "set multiplot layout 3,1 title "
         << gnuplot_quote(scenario.entry.name + ": " + scenario.entry.about) << " noenhanced\n"
         << "set grid\nset key outside right top noenhanced\nset xlabel 'time (s)'\n"
         << "set lmargin 10\n";
  auto panel = [&](const std::string& ylabel, int offset, double band, const std::string& unit) {
    script << "set ylabel " << gnuplot_quote(ylabel) << "\nplot ";
    for (size_t i = 0; i < runs.size(); ++i) {
      script << data << " using 1:" << 2 + 2 * i + offset << " every ::1 with lines lw 2 lc rgb '"
             << kColours[i % kColours.size()] << "' title " << gnuplot_quote(runs[i]->controller)
             << ", ";
    }
    script << band << " with lines dt 2 lc rgb '#555555' title "
           << gnuplot_quote("±" + fixed(band, 1) + " " + unit) << ", " << -band
           << " with lines dt 2 lc rgb '#555555' notitle\n";
  };
  panel("lateral error e_d (mm)", 0, band_mm, "mm");
  panel("heading error e_θ (deg)", 1, band_deg, "deg");
  // |e_d| is clipped at 1 um, below the few micrometres of perception noise, so that the axis
  // stays readable.
  script << "set logscale y\nset yrange [0.001:*]\nset format y '10^{%L}'\n"
         << "set ylabel 'abs lateral error |e_d| (mm), log'\nplot ";
  for (size_t i = 0; i < runs.size(); ++i) {
    script << data << " using 1:(abs($" << 2 + 2 * i << ") < 0.001 ? 0.001 : abs($" << 2 + 2 * i
           << ")) every ::1 with lines lw 2 lc rgb '" << kColours[i % kColours.size()] << "' title "
           << gnuplot_quote(runs[i]->controller) << ", ";
  }
  script << band_mm << " with lines dt 2 lc rgb '#555555' title "
         << gnuplot_quote(fixed(band_mm, 1) + " mm") << "\nunset logscale y\nunset multiplot\n";
  return run_gnuplot(script.str());
}

// The latency study as a controller x latency grid of "compensation on / off" cells.
std::string latency_tables(const ComparePlan& plan, const std::vector<CompareRun>& runs,
                           bool html) {
  std::vector<std::string> labels;
  for (const auto& s : plan.scenarios) {
    if (!s.latency_label.empty() &&
        std::find(labels.begin(), labels.end(), s.latency_label) == labels.end())
      labels.push_back(s.latency_label);
  }
  if (labels.empty()) return "";
  std::map<std::tuple<std::string, std::string, bool>, const CompareRun*> cell;
  for (const CompareRun& r : runs) {
    for (const auto& s : plan.scenarios) {
      if (s.entry.name == r.scenario && !s.latency_label.empty())
        cell[{r.controller, s.latency_label, s.compensation}] = &r;
    }
  }
  std::vector<ReportTable::Column> columns{{"controller", "controller"}};
  for (const std::string& l : labels)
    columns.push_back({l, l == "threaded" ? "threaded (age varies)" : l + " frame(s)"});
  struct Measure {
    std::string title;
    std::function<std::string(const CompareRun&)> value;
  };
  const std::vector<Measure> measures{
      {"max abs e_d after the 1st measurement (mm), compensation on / off",
       [](const CompareRun& r) {
         return fixed(1e3 * r.metrics.max_abs_e_d_after_first_measurement_m, 2);
       }},
      {"settle time (s), compensation on / off",
       [](const CompareRun& r) {
         return r.metrics.settle_time_s ? fixed(*r.metrics.settle_time_s, 2) : "never";
       }},
      {"RMS e_d after settling (mm), compensation on / off", [](const CompareRun& r) {
         return r.metrics.rms_e_d_m ? fixed(1e3 * *r.metrics.rms_e_d_m, 3) : "-";
       }}};
  std::string out;
  for (const Measure& measure : measures) {
    ReportTable table(columns);
    for (const auto& controller : plan.controllers) {
      std::vector<std::string> cells{controller.name};
      bool any = false;
      for (const std::string& l : labels) {
        const auto on = cell.find({controller.name, l, true});
        const auto off = cell.find({controller.name, l, false});
        std::string text = on != cell.end() ? measure.value(*on->second) : "-";
        text += " / ";
        text += off != cell.end() ? measure.value(*off->second) : "-";
        any = any || on != cell.end() || off != cell.end();
        cells.push_back(text);
      }
      if (any) table.add_row(cells);
    }
    if (html)
      out += "<h3>" + html_escape(measure.title) + "</h3>\n" + table.html();
    else
      out += "### " + measure.title + "\n\n" + table.markdown() + "\n";
  }
  return out;
}

// Page style: tables in a small font with wrapping headers, so that the 15 columns fit a
// laptop screen; every table sorts by a click on a column's header (numbers as numbers,
// "never" and "n/a" last).
const char* kStyle =
    "<style>body{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}"
    "table{border-collapse:collapse;margin:0.5em 0 1.5em;font-size:13px}td,th{border:1px solid "
    "#ccc;padding:2px 6px}td.num{text-align:right}th{background:#eee;max-width:9em;"
    "font-weight:normal;cursor:pointer}th:hover{background:#ddd}img{max-width:100%}"
    "td.score{text-align:center;min-width:4em}td.about{font-size:12px;color:#444}</style>\n"
    "<script>document.addEventListener('DOMContentLoaded',()=>{"
    "document.querySelectorAll('table.sortable th').forEach((th,i)=>{th.title='sort';"
    "th.addEventListener('click',()=>{const body=th.closest('table').tBodies[0];"
    "const rows=[...body.rows].filter(r=>r.cells[0].tagName==='TD');"
    "const up=th.dataset.up!=='1';th.dataset.up=up?'1':'0';"
    "const key=r=>{const t=r.cells[i].textContent.trim();const v=parseFloat(t);"
    "return isNaN(v)?(t==='never'||t==='n/a'||t===''?[1,Infinity]:[0,t]):[0,v];};"
    "rows.sort((a,b)=>{const x=key(a),y=key(b);const c=x[0]-y[0]||(x[1]<y[1]?-1:x[1]>y[1]?1:0);"
    "return up?c:-c;});rows.forEach(r=>body.appendChild(r));});});});</script>\n";

// Background of a settle-time cell: green at 0 s through yellow to red at 3 s and beyond.
std::string settle_colour(double settle_s) {
  const double hue = 120.0 * (1.0 - std::clamp(settle_s / 3.0, 0.0, 1.0));
  char text[48];
  std::snprintf(text, sizeof(text), "hsl(%.0f,70%%,75%%)", hue);
  return text;
}

// The score matrix: a row per controller (with its line from the suite), a column per scenario
// of the suite (not the latency study), each cell the settle time (coloured on the page).
struct ScoreMatrix {
  std::vector<const pipeline::SuiteEntry*> scenarios;
  std::map<std::pair<std::string, std::string>, const CompareRun*> runs;  // (controller, scenario)

  ScoreMatrix(const ComparePlan& plan, const std::vector<CompareRun>& all) {
    for (const pipeline::PlannedScenario& s : plan.scenarios)
      if (s.latency_label.empty()) scenarios.push_back(&s.entry);
    for (const CompareRun& r : all) runs[{r.controller, r.scenario}] = &r;
  }
  const CompareRun* run(const std::string& controller, const std::string& scenario) const {
    const auto found = runs.find({controller, scenario});
    return found == runs.end() ? nullptr : found->second;
  }
};

std::string settle_words(const pipeline::RunMetrics& m) {
  return m.settle_time_s ? fixed(*m.settle_time_s, 2) + " s" : "never";
}

std::string score_matrix_markdown(const ComparePlan& plan, const std::vector<CompareRun>& runs) {
  const ScoreMatrix matrix(plan, runs);
  std::vector<ReportTable::Column> columns{{"controller", "controller"}};
  for (const auto* s : matrix.scenarios) columns.push_back({s->name, s->name});
  columns.push_back({"about", "about"});
  ReportTable table(columns);
  for (const pipeline::SuiteEntry& c : plan.controllers) {
    std::vector<std::string> cells{c.name};
    for (const auto* s : matrix.scenarios) {
      const CompareRun* r = matrix.run(c.name, s->name);
      cells.push_back(r ? settle_words(r->metrics) : "n/a");
    }
    cells.push_back(c.about);
    table.add_row(cells);
  }
  return table.markdown();
}

std::string score_matrix_html(const ComparePlan& plan, const std::vector<CompareRun>& runs) {
  const ScoreMatrix matrix(plan, runs);
  std::string out = "<table class=\"sortable\">\n<tr><th>controller</th>";
  for (const auto* s : matrix.scenarios)
    out += "<th title=\"" + html_escape(s->about) + "\">" + html_escape(s->name) + "</th>";
  out += "<th>about</th></tr>\n";
  for (const pipeline::SuiteEntry& c : plan.controllers) {
    out += "<tr><td>" + html_escape(c.name) + "</td>";
    for (const auto* s : matrix.scenarios) {
      const CompareRun* r = matrix.run(c.name, s->name);
      if (!r) {
        out += "<td class=\"score\" style=\"background:#f4f4f4\">n/a</td>";
        continue;
      }
      const pipeline::RunMetrics& m = r->metrics;
      const std::string style = m.settle_time_s ? "background:" + settle_colour(*m.settle_time_s)
                                                : "background:#a00;color:#fff";
      out += "<td class=\"score\" style=\"" + style + "\" title=\"max abs e_d after the 1st " +
             "measurement " + fixed(1e3 * m.max_abs_e_d_after_first_measurement_m, 2) +
             " mm, limit violations " + std::to_string(m.limit_violations) + "\">" +
             settle_words(m) + "</td>";
    }
    out += "<td class=\"about\">" + html_escape(c.about) + "</td></tr>\n";
  }
  return out + "</table>\n";
}

std::string plan_heading(const ComparePlan& plan, size_t runs) {
  return "suite '" + plan.suite_name + "', seed " + std::to_string(plan.seed) + ", " +
         std::to_string(runs) + " runs, base scenario: " + plan.base.name;
}

std::vector<std::string> write_suite_report(const fs::path& dir, const ComparePlan& plan,
                                            const std::vector<CompareRun>& runs) {
  std::vector<std::string> warnings;
  fs::create_directories(dir / "plots");
  fs::create_directories(dir / "series");
  const CompareRun& first = runs.front();
  const std::string bands = fixed(1e3 * first.settle_band_e_d_m, 1) + " mm / " +
                            fixed(rad_to_deg(first.settle_band_e_theta_rad), 1) + " deg";
  const std::string legend =
      "Settle: the first time after which |e_d| and |e_θ| stay within " + bands +
      " to the end of the run; never: they did not stay within the bands before the run ended (the "
      "vehicle may still be converging, or oscillate about the tape). RMS errors are over the "
      "samples after settling. "
      "Errors are the true ones (ground truth), once per control period. Compute per period is "
      "the controller's mean time, measured, so it varies from run to run.";

  ReportTable all = metrics_table(true);
  for (const CompareRun& r : runs) all.add_row(metrics_cells(r, true));
  write_text(dir / "table.csv", all.csv());

  std::string md = "# agv compare: " + plan_heading(plan, runs.size()) + "\n\n" +
                   "## Settle time by controller and scenario\n\n" +
                   score_matrix_markdown(plan, runs) + "\n" + legend + "\n\n";
  std::string html = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>agv compare: " +
                     html_escape(plan.suite_name) + "</title>\n" + kStyle + "</head><body>\n" +
                     "<h1>agv compare</h1>\n<p>" + html_escape(build_words()) + "</p>\n<p>" +
                     html_escape(plan_heading(plan, runs.size())) +
                     ". Tables: <a href=\"table.md\">table.md</a>, <a href=\"table.csv\">" +
                     "table.csv</a>; traces: series/*.csv.</p>\n" +
                     "<h2>Settle time by controller and scenario</h2>\n" +
                     score_matrix_html(plan, runs) + "<p>" + html_escape(legend) +
                     " Green: settled at once; red: 3 s or more; dark red: never. A cell's tooltip "
                     "gives the largest lateral error once the first measurement arrived; a "
                     "scenario's, what it is. Click a column's header to sort.</p>\n";
  html += "<p>Scenarios:";
  for (const pipeline::PlannedScenario& scenario : plan.scenarios) {
    const std::string name = html_escape(scenario.entry.name);
    html += " <a href=\"#" + name + "\">" + name + "</a>";
  }
  html += "</p>\n";
  const std::string latency_md = latency_tables(plan, runs, false);
  if (!latency_md.empty()) {
    md +=
        "## Latency study\n\nEach cell: compensation on / off (the error predicted over the "
        "measurement's age with the commands already sent).\n\n" +
        latency_md;
    html += "<h2>Latency study</h2>\n<p>Each cell: compensation on / off.</p>\n" +
            latency_tables(plan, runs, true);
  }
  for (const pipeline::PlannedScenario& scenario : plan.scenarios) {
    const std::vector<const CompareRun*> of = runs_of_scenario(runs, scenario.entry.name);
    if (of.empty()) continue;
    ReportTable table = metrics_table(false);
    for (const CompareRun* r : of) table.add_row(metrics_cells(*r, false));
    const std::string name = scenario.entry.name;
    md += "## " + name + "\n\n" + scenario.entry.about + "\n\n" + table.markdown() + "\n![" + name +
          "](plots/" + name + ".png)\n\n";
    const fs::path series = dir / "series" / (name + ".csv");
    write_series(series, of);
    const std::string failure =
        plot_scenario(series, dir / "plots" / (name + ".png"), scenario, of);
    if (!failure.empty()) warnings.push_back("plots/" + name + ".png: " + failure);
    html += "<h2 id=\"" + html_escape(name) + "\">" + html_escape(name) + "</h2>\n<p>" +
            html_escape(scenario.entry.about) + "</p>\n" + table.html() +
            (failure.empty() ? "<img src=\"plots/" + html_escape(name) + ".png\" alt=\"" +
                                   html_escape(name) + "\">\n"
                             : "<p>(no plot: " + html_escape(failure) + ")</p>\n");
  }
  html += "</body></html>\n";
  write_text(dir / "table.md", md);
  write_text(dir / "index.html", html);
  return warnings;
}

double quantile_or_inf(std::vector<double> values, double p) {
  return values.empty() ? std::numeric_limits<double>::infinity()
                        : percentile(std::move(values), p);
}

std::vector<std::string> write_monte_carlo_report(const fs::path& dir, const ComparePlan& plan,
                                                  const std::vector<CompareRun>& runs) {
  std::vector<std::string> warnings;
  ReportTable per_run({{"run", "run"},
                       {"controller", "controller"},
                       {"initial_e_theta_deg", "initial e_θ (deg)"},
                       {"initial_e_d_mm", "initial e_d (mm)"},
                       {"settle_time_s", "settle (s)"},
                       {"max_abs_e_d_mm", "max abs e_d (mm)"},
                       {"max_abs_e_d_acting_mm", "max abs e_d after the 1st measurement (mm)"},
                       {"max_abs_e_theta_deg", "max abs e_θ (deg)"},
                       {"rms_e_d_mm", "RMS e_d after settling (mm)"},
                       {"limit_violations", "limit violations"},
                       {"control_us_per_period", "compute per period (µs)"}});
  for (const CompareRun& r : runs) {
    per_run.add_row({r.scenario, r.controller, fixed(rad_to_deg(r.initial_e_theta_rad), 3),
                     fixed(1e3 * r.initial_e_d_m, 3), fixed(r.metrics.settle_time_s, 1.0, 2),
                     fixed(1e3 * r.metrics.max_abs_e_d_m, 3),
                     fixed(1e3 * r.metrics.max_abs_e_d_after_first_measurement_m, 3),
                     fixed(rad_to_deg(r.metrics.max_abs_e_theta_rad), 3),
                     fixed(r.metrics.rms_e_d_m, 1e3, 4), std::to_string(r.metrics.limit_violations),
                     fixed(r.control_us_per_period, 1)});
  }
  write_text(dir / "monte_carlo.csv", per_run.csv());

  ReportTable table({{"controller", "controller"},
                     {"runs", "runs"},
                     {"settled", "settled"},
                     {"settle_median_s", "settle median (s)"},
                     {"settle_p95_s", "settle p95 (s)"},
                     {"settle_worst_s", "settle worst (s)"},
                     {"max_e_d_median_mm", "max abs e_d after the 1st measurement: median (mm)"},
                     {"max_e_d_p95_mm", "p95 (mm)"},
                     {"max_e_d_worst_mm", "worst (mm)"},
                     {"max_e_theta_median_deg", "max abs e_θ median (deg)"},
                     {"max_e_theta_p95_deg", "max abs e_θ p95 (deg)"},
                     {"max_e_theta_worst_deg", "max abs e_θ worst (deg)"},
                     {"limit_violations", "limit violations"}});
  for (const MonteCarloSummary& s : summarise_monte_carlo(plan, runs)) {
    table.add_row(
        {s.controller, std::to_string(s.runs), std::to_string(s.settled),
         fixed(s.settle_median_s, 2), fixed(s.settle_p95_s, 2), fixed(s.settle_worst_s, 2),
         fixed(1e3 * s.max_e_d_median_m, 2), fixed(1e3 * s.max_e_d_p95_m, 2),
         fixed(1e3 * s.max_e_d_worst_m, 2), fixed(rad_to_deg(s.max_e_theta_median_rad), 2),
         fixed(rad_to_deg(s.max_e_theta_p95_rad), 2), fixed(rad_to_deg(s.max_e_theta_worst_rad), 2),
         std::to_string(s.limit_violations)});
  }
  write_text(dir / "summary.csv", table.csv());
  const std::string heading = "Monte Carlo, " + std::to_string(plan.monte_carlo_runs) +
                              " runs per controller, " + plan_heading(plan, runs.size());
  const std::string legend =
      "Initial errors drawn uniformly within the suite's monte_carlo bounds, a fresh noise seed "
      "per run, the same draws for every controller. Settle time: to " +
      fixed(1e3 * runs.front().settle_band_e_d_m, 1) + " mm / " +
      fixed(rad_to_deg(runs.front().settle_band_e_theta_rad), 1) +
      " deg; 'never': a run (or, for p95 and worst, enough runs) that did not settle.";

  // Cumulative distributions of settle time and max |e_d| after the first measurement, one
  // step curve per controller (the fraction of its runs at or below each value; runs that never
  // settle keep the settle curve below 1), written to distributions.csv and drawn.
  const size_t controllers = plan.controllers.size();
  std::vector<std::vector<double>> settle_s(controllers), e_d_mm(controllers);
  std::vector<int> run_count(controllers, 0);
  for (const CompareRun& r : runs) {
    const size_t c = static_cast<size_t>(
        std::find_if(plan.controllers.begin(), plan.controllers.end(),
                     [&](const pipeline::SuiteEntry& e) { return e.name == r.controller; }) -
        plan.controllers.begin());
    if (c == controllers) continue;
    ++run_count[c];
    if (r.metrics.settle_time_s) settle_s[c].push_back(*r.metrics.settle_time_s);
    e_d_mm[c].push_back(1e3 * r.metrics.max_abs_e_d_after_first_measurement_m);
  }
  std::ostringstream distributions, blocks;
  distributions << "controller,quantity,value,fraction_of_runs\n";
  for (size_t c = 0; c < controllers; ++c) {
    for (int q = 0; q < 2; ++q) {
      std::vector<double>& values = q == 0 ? settle_s[c] : e_d_mm[c];
      std::sort(values.begin(), values.end());
      const char* quantity = q == 0 ? "settle_time_s" : "max_abs_e_d_after_first_measurement_mm";
      blocks << "$q" << q << "c" << c << " << EOD\n";
      for (size_t i = 0; i < values.size(); ++i) {
        const double fraction = static_cast<double>(i + 1) / std::max(1, run_count[c]);
        distributions << plan.controllers[c].name << ',' << quantity << ',' << fixed(values[i], 5)
                      << ',' << fixed(fraction, 5) << "\n";
        blocks << fixed(values[i], 5) << ' ' << fixed(fraction, 5) << "\n";
      }
      if (values.empty()) blocks << "NaN NaN\n";
      blocks << "EOD\n";
    }
  }
  write_text(dir / "distributions.csv", distributions.str());

  std::ostringstream script;
  script << "set terminal pngcairo size 1100,800 font 'DejaVu Sans,11'\n"
         << "set output " << gnuplot_quote((dir / "distributions.png").string()) << "\n"
         << blocks.str() << "set multiplot layout 2,1 title " << gnuplot_quote(heading)
         << " noenhanced\n"
         << "set grid\nset key outside right top noenhanced\n"
         << "set ylabel 'fraction of runs'\nset yrange [0:1.02]\nset ytics 0.2\nset lmargin 10\n";
  auto cumulative = [&](const std::string& xlabel, int q) {
    script << "set xlabel " << gnuplot_quote(xlabel) << "\nplot ";
    for (size_t c = 0; c < controllers; ++c) {
      std::string title = plan.controllers[c].name;
      const int never = run_count[c] - static_cast<int>(settle_s[c].size());
      if (q == 0 && never > 0) title += " (" + std::to_string(never) + " never settle)";
      script << (c ? ", " : "") << "$q" << q << "c" << c << " using 1:2 with steps lw 2 lc rgb '"
             << kColours[c % kColours.size()] << "' title " << gnuplot_quote(title);
    }
    script << "\n";
  };
  cumulative("settle time (s): fraction of runs settled by then", 0);
  cumulative("max abs lateral error e_d after the first measurement (mm)", 1);
  script << "unset multiplot\n";
  const std::string failure = run_gnuplot(script.str());
  if (!failure.empty()) warnings.push_back("distributions.png: " + failure);

  write_text(dir / "table.md", "# agv compare: " + heading + "\n\n" + legend + "\n\n" +
                                   table.markdown("never") +
                                   "\n![distributions](distributions.png)\n");
  write_text(dir / "index.html",
             "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>agv compare: Monte "
             "Carlo</title>\n" +
                 std::string(kStyle) + "</head><body>\n<h1>agv compare: Monte Carlo</h1>\n<p>" +
                 html_escape(build_words()) + "</p>\n<p>" + html_escape(heading) +
                 ". Tables: <a href=\"summary.csv\">summary.csv</a>, " +
                 "<a href=\"monte_carlo.csv\">monte_carlo.csv</a> (every run).</p>\n<p>" +
                 html_escape(legend) + "</p>\n" + table.html("never") +
                 (failure.empty() ? "<img src=\"distributions.png\" alt=\"distributions\">\n"
                                  : "<p>(no plot: " + html_escape(failure) + ")</p>\n") +
                 "</body></html>\n");
  return warnings;
}

}  // namespace

std::vector<MonteCarloSummary> summarise_monte_carlo(const ComparePlan& plan,
                                                     const std::vector<CompareRun>& runs) {
  std::vector<MonteCarloSummary> out;
  const double inf = std::numeric_limits<double>::infinity();
  for (const pipeline::SuiteEntry& controller : plan.controllers) {
    MonteCarloSummary s;
    s.controller = controller.name;
    std::vector<double> settle, e_d, e_theta;
    for (const CompareRun& r : runs) {
      if (r.controller != controller.name) continue;
      ++s.runs;
      s.settled += r.metrics.settle_time_s ? 1 : 0;
      s.limit_violations += r.metrics.limit_violations;
      settle.push_back(r.metrics.settle_time_s.value_or(inf));
      e_d.push_back(r.metrics.max_abs_e_d_after_first_measurement_m);
      e_theta.push_back(r.metrics.max_abs_e_theta_rad);
    }
    if (s.runs == 0) continue;
    s.settle_median_s = quantile_or_inf(settle, 0.5);
    s.settle_p95_s = quantile_or_inf(settle, 0.95);
    s.settle_worst_s = *std::max_element(settle.begin(), settle.end());
    s.max_e_d_median_m = quantile_or_inf(e_d, 0.5);
    s.max_e_d_p95_m = quantile_or_inf(e_d, 0.95);
    s.max_e_d_worst_m = *std::max_element(e_d.begin(), e_d.end());
    s.max_e_theta_median_rad = quantile_or_inf(e_theta, 0.5);
    s.max_e_theta_p95_rad = quantile_or_inf(e_theta, 0.95);
    s.max_e_theta_worst_rad = *std::max_element(e_theta.begin(), e_theta.end());
    out.push_back(s);
  }
  return out;
}

std::vector<std::string> write_compare_report(const fs::path& dir, const ComparePlan& plan,
                                              const std::vector<CompareRun>& runs) {
  if (runs.empty()) return {"no runs to report"};
  return plan.mode == "monte_carlo" ? write_monte_carlo_report(dir, plan, runs)
                                    : write_suite_report(dir, plan, runs);
}

}  // namespace agv::tools
