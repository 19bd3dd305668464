#!/usr/bin/env bash
# Starts lcm-spy through the launcher on a virtual X display and requires it to stay up for
# 3 s without a Java exception. Exits 77 (CTest: skipped) when xvfb-run is not installed
# (Debian package: xvfb).
# Usage: spy_gui_smoke.sh <launcher>
set -uo pipefail
launcher=${1:?usage: spy_gui_smoke.sh LAUNCHER}
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIP: xvfb-run not found; install the Debian package 'xvfb' to run this test"
  exit 77
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# Own process group, so the spy, xvfb-run and Xvfb can be stopped together by its id.
setsid xvfb-run -a "$launcher" -l 'memq://' >"$log" 2>&1 &
pid=$!
sleep 3
if kill -0 "$pid" 2>/dev/null; then
  kill -TERM -- "-$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  if grep -q "Exception" "$log"; then
    echo "FAIL: lcm-spy printed an exception:"; cat "$log"; exit 1
  fi
  echo "ok: lcm-spy ran for 3 s on a virtual display"
  exit 0
fi
wait "$pid"
echo "FAIL: lcm-spy exited within 3 s (status $?):"; cat "$log"
exit 1
