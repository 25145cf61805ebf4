#!/usr/bin/env bash
# Prints the figures that README.md and datasets/*/README.md quote, as the program prints them
# today (the test AgvCli.ReadmesQuoteWhatTheProgramPrintsToday fails when a README differs):
# paste each line where its README quotes it.
#   tools/readme_figures.sh [AGV]   (default: build/bin/agv)
set -euo pipefail
cd "$(dirname "$0")/.."
agv="${1:-build/bin/agv}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "README.md (default run):"
"$agv" simulate --quiet --no-plots --out "$out/default" | head -1
for dataset in datasets/*/; do
  [[ -f "$dataset/manifest.csv" ]] || continue
  echo "${dataset}README.md:"
  "$agv" replay --quiet --no-video "$dataset" --out "$out/$(basename "$dataset")" | head -1 |
    sed 's/ | [0-9.]* ms per frame (median)//'
done
for folder in datasets/lines/*/; do
  echo "${folder}README.md:"
  "$agv" replay --quiet --no-video --fps 1 --no-tracking "$folder" --out "$out/$(basename "$folder")" |
    head -1 | sed 's/ | [0-9.]* ms per frame (median)//'
done
