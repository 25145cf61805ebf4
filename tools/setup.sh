#!/usr/bin/env bash
# Set-up, build and run, idempotent, on Debian 12 (root, or a user with sudo).
#   tools/setup.sh simulate [agv simulate options]   build (Release) and run the default scenario
#   tools/setup.sh test        build with AddressSanitizer + UndefinedBehaviorSanitizer and run every
#                              test (the threaded loop's timing against lockstep alone, last);
#                              build with ThreadSanitizer and run the threaded tests (CI)
#   tools/setup.sh test-plain  build (Release) and run every test (quicker, no sanitizers)
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
  gstreamer1.0-plugins-base   # videotestsrc, videoconvert, appsink: live-source tests, agv track
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

# A test build: optimised (-O1) but with assertions on, no debug info (faster to link);
# sanitizers as given, less the checks left out.
test_build() {  # dir sanitizers checks-left-out [target]
  cmake -S . -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 \
    -DAGV_SANITIZE="$2" -DAGV_NO_SANITIZE="$3" > /dev/null
  cmake --build "$1" --parallel "$jobs" ${4:+--target "$4"}
}

case "$mode" in
  simulate | build | test-plain)
    cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
    cmake --build "$build_dir" --parallel "$jobs"
    ;;
esac

case "$mode" in
  simulate) exec "$build_dir/bin/agv" simulate "$@" ;;
  test-plain) cd "$build_dir" && exec ctest --output-on-failure --parallel "$jobs" "$@" ;;
  test)
    # UBSan's alignment and null checks double the build (they instrument every reference in
    # Eigen's and the standard library's inlined code); AddressSanitizer still reports a null
    # dereference, with its stack.
    echo "setup: AddressSanitizer + UndefinedBehaviorSanitizer build, all tests"
    test_build build-asan address,undefined alignment,null
    timing_test="^ClosedLoop\\.ThreadedModeMatchesLockstep$"
    export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
    export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
    (cd build-asan && ctest --output-on-failure --parallel "$jobs" -E "$timing_test" "$@")
    # The threaded loop's timing against lockstep's: alone, so that nothing else competes for
    # the cores (this build keeps up with real time; ThreadSanitizer's does not).
    echo "setup: the threaded loop against lockstep, alone"
    (cd build-asan && ctest --output-on-failure -R "$timing_test" "$@")
    echo "setup: ThreadSanitizer build, threaded tests (queue, loop, closed loop, watchdog)"
    test_build build-tsan thread "" pipeline_loop_tests
    cd build-tsan
    export TSAN_OPTIONS="suppressions=$PWD/../tests/tsan.supp halt_on_error=1"
    # The threaded closed-loop tests run on real time: the comparison runs (several closed loops
    # at once) come after them, not beside them, so that they cannot starve their threads.
    ctest --output-on-failure --parallel "$jobs" -R "^(BoundedQueue|ClosedLoop|Loop|Watchdog)\\." "$@"
    echo "setup: ThreadSanitizer, parallel comparison runs"
    exec ctest --output-on-failure --parallel "$jobs" -R "^CompareRunner\\." "$@"
    ;;
  build) ;;
  *) echo "setup: unknown mode '$mode' (simulate | test | test-plain | build)" >&2; exit 2 ;;
esac
