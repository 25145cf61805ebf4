#!/usr/bin/env bash
# Seed 002's own scene (scenarios/dual_steer_improved_dwa_pose.yaml: line-arc-line path, R 3 m,
# 0.5 m/s, v_max 0.8 m/s, a_max 1.2 m/s^2, w_max 10 deg/s, angular acceleration 10 deg/s^2, the
# pose known) for each of the three drive forms, plain DWA against improved DWA: prints a
# Markdown table (max |e_d|, coverage area of the front and rear wheel tracks, settle time,
# limit violations) and writes docs/seed002_scene.csv, docs/seed002_scene.png (the same as bars)
# and docs/drive_forms.png (the improved DWA's wheel tracks on the arc, docs/drive_forms.gp).
#   docs/seed002_scene.sh [AGV]   (default: build/bin/agv)
set -euo pipefail
cd "$(dirname "$0")/.."
agv="${1:-build/bin/agv}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
scene=scenarios/dual_steer_improved_dwa_pose.yaml
csv=docs/seed002_scene.csv
echo "drive_form,controller,max_abs_e_d_mm,coverage_area_m2,settle_time_s,limit_violations" > "$csv"
for form in both_steer rear_drive front_drive; do
  for controller in dwa improved_dwa; do
    "$agv" simulate --quiet --no-plots --scenario "$scene" --set vehicle.dual_steer.drive_form=$form \
      --set controller.kind=$controller --out "$out/${controller}_${form}" > /dev/null
    python3 - "$out/${controller}_${form}/summary.json" "$form" "$controller" >> "$csv" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
settle = "" if s["settle_time_s"] is None else "%.2f" % s["settle_time_s"]
print("%s,%s,%.2f,%.3f,%s,%d" % (sys.argv[2], sys.argv[3], 1e3 * s["max_abs_e_d_m"],
                                   s["coverage_area_m2"], settle, s["limit_violations"]))
PY
  done
done
echo "| drive form | controller | max abs e_d (mm) | coverage area (m²) | settle (s) | limit violations |"
echo "|---|---|---:|---:|---:|---:|"
tail -n +2 "$csv" | awk -F, '{printf "| %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, ($5 == "" ? "never" : $5), $6}'
"$agv" simulate --quiet --no-plots --scenario "$scene" --set duration_s=0.2 --out "$out/path" > /dev/null
gnuplot -e "csv='$csv'" docs/seed002_scene.gp
gnuplot -e "dir='$out'" docs/drive_forms.gp
echo "wrote $csv, docs/seed002_scene.png, docs/drive_forms.png"
