#pragma once

#include <string>

#include "pipeline/config/scenario.h"
#include "pipeline/evaluation/output_folder.h"

namespace agv::tools {

// errors.png: e_d (mm) and e_theta (deg) against time, true and measured, with the settle bands;
// path.png: top view of the path and the vehicle track. Reads trace.csv and path.csv of the
// folder. Returns "" or what went wrong.
std::string plot_run(const pipeline::OutputFolder& folder, const pipeline::Scenario& scenario,
                     const std::string& title);

// path.csv: the path sampled every centimetre (s_m, x_m, y_m), for plots and users.
void write_path_csv(const std::string& file, const control::Path& path);

}  // namespace agv::tools
