#!/usr/bin/env python3
"""Mutation testing: applies small mutations (sign flips, off-by-one, removed checks) to named
lines of the core code one at a time, rebuilds, runs the test binaries that guard that code and
prints KILLED (a test failed) or SURVIVED (every test passed: a bug the suite lets through).

    tools/mutate.py [--build-dir build] [--only NAME ...] [--list]

Run it in a clean checkout (it edits the sources and restores each file afterwards, also when
interrupted). Not run in CI: a full pass takes some tens of minutes on 2 cores.
"""
import argparse
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent

# name, file, exact original text (must occur once), mutated text, test binaries (build/bin).
MUTATIONS = [
    ("limits: acceleration ignores lateral", "control/vehicle_limits.cpp",
     "std::hypot(command.vx_m_s - previous.vx_m_s, command.vy_m_s - previous.vy_m_s) / ts_s",
     "std::abs(command.vx_m_s - previous.vx_m_s) / ts_s", ["control_tests"]),
    ("limits: yaw acceleration unchecked", "control/vehicle_limits.cpp",
     "if (exceeds(yaw_accel_rad_s2, limits.alpha_max_rad_s2))",
     "if (exceeds(yaw_accel_rad_s2, 1e9))", ["control_tests"]),
    ("pid: integral sign", "control/pid_controller.cpp",
     "o.ki_d_1_s2 * integral_e_d_m_s_", "-o.ki_d_1_s2 * integral_e_d_m_s_", ["control_tests"]),
    ("pid: derivative sign", "control/pid_controller.cpp",
     "o.kd_theta * d_e_theta", "-o.kd_theta * d_e_theta", ["control_tests"]),
    ("finite-step: curvature feed-forward sign", "control/finite_step_controller.cpp",
     "-plan.turn_rate_rad_s + estimate.curvature_1_m * context.path_speed_m_s",
     "-plan.turn_rate_rad_s - estimate.curvature_1_m * context.path_speed_m_s",
     ["control_tests", "pipeline_tests"]),
    ("mecanum: one wheel's yaw term", "control/mecanum_kinematics.cpp",
     "(twist.vx_m_s - twist.vy_m_s + k * twist.wz_rad_s) / r",
     "(twist.vx_m_s - twist.vy_m_s - k * twist.wz_rad_s) / r", ["control_tests"]),
    ("tracker: curve braking distance 5 cm short", "control/line_tracker.cpp",
     "2.0 * decel * braking_m", "2.0 * decel * (braking_m + 0.05)", ["control_tests"]),
    ("tracker: hold time doubled", "control/line_tracker.cpp",
     "now_s - *last_arrival_s_ <= options_.line_lost_hold_s + kTimeSlack_s",
     "now_s - *last_arrival_s_ <= 2 * options_.line_lost_hold_s + kTimeSlack_s",
     ["control_tests"]),
    ("camera: ground 1 mm high", "perception/camera_model.cpp",
     "const double scale = -t.z() / ray.z();", "const double scale = -(t.z() + 0.001) / ray.z();",
     ["perception_tests"]),
    ("camera: undistortion with 5 iterations", "perception/camera_model.cpp",
     "cv::TermCriteria::EPS, 100, 1e-12);", "cv::TermCriteria::EPS, 5, 1e-12);",
     ["perception_tests"]),
    ("apriltag: no half-pixel shift", "perception/apriltag_detector.cpp",
     "return {p[0] - 0.5, p[1] - 0.5};", "return {p[0], p[1]};", ["perception_tests"]),
    ("path memory: registration the wrong way", "perception/path_memory.cpp",
     "const Eigen::Vector3d delta = jtj.ldlt().solve(-jtd);",
     "const Eigen::Vector3d delta = jtj.ldlt().solve(jtd);", ["perception_tests"]),
    ("camera file: folding distortion accepted", "perception/camera_file.cpp",
     "  if (!problem.empty())\n    fail(source,", "  if (false)\n    fail(source,",
     ["perception_tests"]),
    ("calibration: no refit when the fit folds", "perception/intrinsics_calibration.cpp",
     "  for (size_t i = 0; i < steps.size(); ++i) {", "  for (size_t i = 0; i < 1; ++i) {",
     ["perception_tests"]),
    ("yaml: unknown keys in list items unchecked", "pipeline/config/yaml_reader.cpp",
     'check_unused(entry.second[i], key + "." + std::to_string(i));', "(void)entry.second[i];",
     ["pipeline_tests"]),
    ("queue: drops not counted", "pipeline/bounded_queue.h",
     "        ++stats_.dropped;", "", ["pipeline_loop_tests"]),
    ("metrics: settle ignores e_theta", "pipeline/evaluation/metrics.cpp",
     "return std::abs(e_d[i]) > band_d || std::abs(e_theta[i]) > band_theta;",
     "return std::abs(e_d[i]) > band_d;", ["pipeline_tests"]),
    ("latency: one frame short", "pipeline/config/scenario_run.cpp",
     "camera_options.latency_s = s.latency_frames * frame_period_s;",
     "camera_options.latency_s = (s.latency_frames - 1) * frame_period_s;",
     ["pipeline_tests", "pipeline_loop_tests"]),
    ("tape regions: one edge counts as a bar", "perception/tape_regions.cpp",
     "out[x] = c[x] - std::max(before[x], after[x]);",
     "out[x] = c[x] - std::min(before[x], after[x]);", ["perception_tests"]),
    ("hough baseline: centre from one edge", "perception/hough_baseline.cpp",
     "const double centre_offset_m = 0.5 * (lo + hi);",
     "const double centre_offset_m = lo;", ["perception_tests"]),
    ("watchdog: finished threads still watched", "pipeline/stall_tracker.cpp",
     "    if (w.finished) continue;\n", "", ["pipeline_tests"]),
    ("output folder: a failed run's folder kept", "pipeline/evaluation/output_folder.cpp",
     "  fs::remove_all(temporary_, error);\n}", "}", ["pipeline_tests"]),
    ("plant: sideways motion ignored while turning", "common/twist_motion.h",
     "dx = (twist.vx_m_s * s + twist.vy_m_s * (c - 1.0)) / twist.wz_rad_s;",
     "dx = (twist.vx_m_s * s) / twist.wz_rad_s;", ["pipeline_tests", "control_tests"]),
    ("plant: actuator lag skipped within a period", "control/drive_response.h",
     "const double mean = target + (state - target) * (1.0 - mean_gain);",
     "const double mean = target + 0.0 * mean_gain * (state - target);",
     ["control_tests", "pipeline_tests"]),
]


def run(command, cwd=ROOT, timeout=1800):
    return subprocess.run(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--only", nargs="*", help="run only mutations whose name contains these")
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    chosen = [m for m in MUTATIONS
              if not args.only or any(word in m[0] for word in args.only)]
    if args.list:
        for m in chosen:
            print(f"{m[0]}: {m[1]}")
        return 0
    build = ROOT / args.build_dir
    killed, survived = [], []
    for number, (name, file, original, mutated, binaries) in enumerate(chosen, 1):
        path = ROOT / file
        text = path.read_text()
        if text.count(original) != 1:
            print(f"[{number}/{len(chosen)}] {name}: the original text is not in {file} once",
                  file=sys.stderr)
            return 2
        start = time.time()
        try:
            path.write_text(text.replace(original, mutated))
            built = run(["cmake", "--build", str(build)] +
                        sum((["--target", b] for b in binaries), []))
            if built.returncode != 0:
                outcome = "KILLED (does not compile)"
                killed.append(name)
            else:
                failed = [b for b in binaries
                          if run([str(build / "bin" / b), "--gtest_brief=1"]).returncode != 0]
                if failed:
                    outcome = "KILLED by " + ", ".join(failed)
                    killed.append(name)
                else:
                    outcome = "SURVIVED"
                    survived.append(name)
        finally:
            path.write_text(text)
        print(f"[{number}/{len(chosen)}] {name}: {outcome} ({time.time() - start:.0f} s)",
              flush=True)
    run(["cmake", "--build", str(build)])  # back to the unmutated build
    print(f"score: {len(killed)} killed, {len(survived)} survived of {len(chosen)}")
    for name in survived:
        print(f"  survived: {name}")
    return 0 if not survived else 1


if __name__ == "__main__":
    sys.exit(main())
