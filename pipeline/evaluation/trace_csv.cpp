#include "pipeline/evaluation/trace_csv.h"

#include <cmath>
#include <iomanip>
#include <variant>

#include "common/angles.h"

namespace agv::pipeline {

namespace {

std::string without_commas(std::string text) {
  for (char& c : text)
    if (c == ',' || c == '\n') c = ';';
  return text;
}

}  // namespace

namespace {

// The wheel columns of the vehicle the run drove: four Mecanum wheel speeds, or the steer angle
// and ground speed of each of two steering wheels.
const char* wheel_columns(const RunResult& run) {
  const bool dual_steer =
      !run.rows.empty() && std::holds_alternative<control::DualSteerWheels>(run.rows[0].wheels);
  return dual_steer ? "front_steer_rad,front_speed_m_s,rear_steer_rad,rear_speed_m_s"
                    : "wheel_fl_rad_s,wheel_fr_rad_s,wheel_rl_rad_s,wheel_rr_rad_s";
}

void write_wheels(std::ostream& out, const control::WheelCommand& wheels) {
  if (const auto* w = std::get_if<control::DualSteerWheels>(&wheels)) {
    out << w->front_steer_rad << ',' << w->front_speed_m_s << ',' << w->rear_steer_rad << ','
        << w->rear_speed_m_s;
    return;
  }
  const control::MecanumWheelSpeeds& w = std::get<control::MecanumWheelSpeeds>(wheels);
  out << w[0] << ',' << w[1] << ',' << w[2] << ',' << w[3];
}

}  // namespace

void write_trace_csv(std::ostream& out, const RunResult& run) {
  out << "t_s,x_m,y_m,yaw_rad,true_e_theta_rad,true_e_d_m,line_found,meas_e_theta_rad,meas_e_d_m,"
         "meas_confidence,meas_age_s,used_e_theta_rad,used_e_d_m,cmd_vx_m_s,cmd_vy_m_s,"
         "cmd_wz_rad_s,"
      << wheel_columns(run)
      << ",horizon_steps,flags,violations,front_wheel_x_m,front_wheel_y_m,rear_wheel_x_m,"
         "rear_wheel_y_m\n";
  out << std::setprecision(9);
  for (const TraceRow& r : run.rows) {
    out << r.t_s << ',' << r.pose.x_m << ',' << r.pose.y_m << ',' << r.pose.yaw_rad << ','
        << r.truth.e_theta_rad << ',' << r.truth.e_d_m << ',';
    if (r.has_measurement) {
      out << (r.measurement.line_found ? 1 : 0) << ',' << r.measurement.e_theta_rad << ','
          << r.measurement.e_d_m << ',' << r.measurement.confidence << ',' << r.measurement_age_s
          << ',';
    } else {
      out << "0,,,,,";
    }
    if (r.output.has_estimate) {
      out << r.output.estimate.e_theta_rad << ',' << r.output.estimate.e_d_m << ',';
    } else {
      out << ",,";
    }
    const BodyTwist& c = r.output.command;
    out << c.vx_m_s << ',' << c.vy_m_s << ',' << c.wz_rad_s << ',';
    write_wheels(out, r.wheels);
    out << ',' << r.output.horizon_steps << ',' << r.output.flags << ',' << r.violations << ','
        << r.front_wheel.x() << ',' << r.front_wheel.y() << ',' << r.rear_wheel.x() << ','
        << r.rear_wheel.y() << '\n';
  }
}

namespace {

// Degrees to a tenth, without "-0".
double tenths_deg(double angle_rad) {
  return std::round(10.0 * rad_to_deg(angle_rad)) / 10.0 + 0.0;
}

// ",legs_deg,chosen_leg_deg": the junction's ways out, ';'-separated, in degrees (left positive).
void write_legs(std::ostream& out, const FrameRecord& f) {
  out << ',';
  for (size_t k = 0; k < f.legs_rad.size(); ++k)
    out << (k > 0 ? ";" : "") << tenths_deg(f.legs_rad[k]);
  out << ',';
  if (f.chosen_leg_rad) out << tenths_deg(*f.chosen_leg_rad);
}

}  // namespace

void write_frames_csv(std::ostream& out, const RunResult& run) {
  out << "index,t_s,true_e_theta_rad,true_e_d_m,line_found,e_theta_rad,e_d_m,confidence,points_"
         "used,tape_width_m,curvature_1_m,extrapolated,curvature_change_m,curvature_ahead_1_m,"
         "no_line_reason,remembered_only,legs_deg,chosen_leg_deg\n";
  out << std::setprecision(9);
  for (const FrameRecord& f : run.frames) {
    const LineMeasurement& m = f.measurement;
    out << f.index << ',' << f.stamp_s << ',';
    if (f.truth) {
      out << f.truth->e_theta_rad << ',' << f.truth->e_d_m << ',';
    } else {
      out << ",,";
    }
    out << (m.line_found ? 1 : 0) << ',';
    if (m.line_found) {
      out << m.e_theta_rad << ',' << m.e_d_m << ',' << m.confidence << ',' << m.points_used << ','
          << m.tape_width_m << ',' << m.curvature_1_m << ',' << (m.extrapolated ? 1 : 0) << ',';
      if (std::isfinite(m.curvature_change_m)) {
        out << m.curvature_change_m << ',' << m.curvature_ahead_1_m << ",,";
      } else {
        out << ",,,";
      }
      out << (m.remembered_only ? 1 : 0);
    } else {
      out << ",,0,0,,,0,,," << without_commas(f.bad ? f.problem : f.no_line_reason) << ",0";
    }
    write_legs(out, f);
    out << '\n';
  }
}

void write_measurements_csv(std::ostream& out, const std::vector<FrameRecord>& frames,
                            bool with_truth) {
  out << "index,t_s,line_found,e_theta_rad,e_d_m,curvature_1_m,confidence,tape_width_m,"
         "no_line_reason,points_used,lines_seen,junction_ahead,bad,source,perceive_ms,extrapolated,"
         "curvature_change_m,curvature_ahead_1_m,remembered_only,legs_deg,chosen_leg_deg";
  if (with_truth) out << ",true_e_theta_rad,true_e_d_m";
  out << '\n' << std::setprecision(9);
  for (const FrameRecord& f : frames) {
    const LineMeasurement& m = f.measurement;
    out << f.index << ',' << f.stamp_s << ',' << (m.line_found ? 1 : 0) << ',';
    if (m.line_found) {
      out << m.e_theta_rad << ',' << m.e_d_m << ',' << m.curvature_1_m << ',' << m.confidence << ','
          << m.tape_width_m << ',';
    } else {
      out << ",,,0,,";
    }
    out << without_commas(f.bad ? f.problem : f.no_line_reason) << ',' << m.points_used << ','
        << m.lines_seen << ',' << (m.junction_ahead ? 1 : 0) << ',' << (f.bad ? 1 : 0) << ','
        << without_commas(f.label) << ',' << 1e3 * f.perceive_s << ','
        << (m.line_found && m.extrapolated ? 1 : 0) << ',';
    if (m.line_found && std::isfinite(m.curvature_change_m)) {
      out << m.curvature_change_m << ',' << m.curvature_ahead_1_m;
    } else {
      out << ',';
    }
    out << ',' << (m.line_found && m.remembered_only ? 1 : 0);
    write_legs(out, f);
    if (with_truth) {
      if (f.truth) {
        out << ',' << f.truth->e_theta_rad << ',' << f.truth->e_d_m;
      } else {
        out << ",,";
      }
    }
    out << '\n';
  }
}

}  // namespace agv::pipeline
