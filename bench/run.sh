#!/usr/bin/env bash
# Reproduces docs/BENCHMARKS.md on a fresh clone: configures an optimized build
# (RelWithDebInfo = -O2 -g, the build the published figures come from) in build/bench, builds
# the `mvtrack` program only, and runs `mvtrack bench`, which writes bench/results/results.json,
# results.md (the tables) and fps.png (the plot).
#
#   bench/run.sh                      the full run (paper grid, store scale, latency, one-hour soak)
#   SUITE=smoke bench/run.sh          a few seconds, what CI runs
#   bench/run.sh --frames 900         extra arguments go to `mvtrack bench` (see --help)
#
# Environment: BUILD_DIR (default build/bench), OUT (default bench/results), SUITE (default full).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build/bench}
out=${OUT:-$root/bench/results}
suite=${SUITE:-full}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMVTRACK_BUILD_TESTS=OFF \
  -DMVTRACK_BUILD_PICTURES=ON
cmake --build "$build" --target mvtrack
echo "bench/run.sh: load before: $(cat /proc/loadavg) (measure on a quiet machine)"
if [ "$suite" = "full" ] && [ $# -eq 0 ]; then
  # The published run: 600 frames per grid point, 30 s of paced latency per mode.
  set -- --frames 600 --latency-seconds 30
fi
"$build/tools/mvtrack" bench --suite "$suite" --out "$out" "$@"
