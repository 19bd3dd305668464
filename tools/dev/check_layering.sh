#!/usr/bin/env bash
# Fails if a pure algorithm module includes LCM, threads, yaml-cpp, spdlog, or reads the clock.
# Pure modules: see docs/ARCHITECTURE.md. Usage: check_layering.sh [repo-root]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
pure="core json geometry tracking2d association triangulation body analytics linking tracker stitch sim eval"
pattern='#[[:space:]]*include[[:space:]]*[<"](lcm/|lcm\.h|yaml-cpp/|spdlog/|thread>|mutex>|atomic>|condition_variable>|future>|shared_mutex>|semaphore>|stop_token>|opencv2/|fstream>|iostream>|cstdio>)'
clock='std::chrono::(system|steady|high_resolution)_clock::now|[^a-z_]time\(nullptr\)|gettimeofday|clock_gettime|std::random_device|getenv'
status=0
for m in $pure; do
  d="$root/lib/$m"
  [ -d "$d" ] || continue
  if hits=$(grep -rnE "$pattern" "$d" --include='*.h' --include='*.cc' | grep -v 'core/check.h:.*cstdio'); then
    echo "layering: forbidden include in pure module '$m':"; echo "$hits"; status=1
  fi
  if hits=$(grep -rnE "$clock" "$d" --include='*.h' --include='*.cc'); then
    echo "layering: wall clock / nondeterminism in pure module '$m':"; echo "$hits"; status=1
  fi
done
[ $status -eq 0 ] && echo "layering: pure modules are clean ($pure)"
exit $status
