#!/usr/bin/env bash
# Set-up, build and run, idempotent, on Debian 12 (root, or a user with sudo).
#   tools/setup.sh simulate [agv simulate options]   build (Release) and run the default scenario
#   tools/setup.sh test                              build (Release) and run every test with ctest
#   tools/setup.sh build                             build only
# Environment: BUILD_DIR (default build), JOBS (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-simulate}"
[[ $# -gt 0 ]] && shift

packages=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libeigen3-dev libapriltag-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  googletest libgtest-dev libbenchmark-dev
  gnuplot-nox fonts-dejavu-core
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing Debian packages: ${missing[*]}"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_dir="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build_dir" --parallel "$jobs"

case "$mode" in
  simulate) exec "$build_dir/bin/agv" simulate "$@" ;;
  test) cd "$build_dir" && exec ctest --output-on-failure --parallel "$jobs" "$@" ;;
  build) ;;
  *) echo "setup: unknown mode '$mode' (simulate | test | build)" >&2; exit 2 ;;
esac
