#!/usr/bin/env bash
# Starts the real lcm-spy through the launcher with no display: lcm-spy scans its class path for
# LCM types and prints "Found N LCM types" before it opens its window, which then fails with a
# HeadlessException. Requires exactly the expected number of types (all of ours, nothing else)
# and that the failure is the missing display, not a class path or start-up error.
# Usage: spy_headless_test.sh <launcher> <number of mvtrack types>
set -uo pipefail
launcher=${1:?usage: spy_headless_test.sh LAUNCHER NUM_TYPES}
num_types=${2:?usage: spy_headless_test.sh LAUNCHER NUM_TYPES}
out=$(env -u DISPLAY -u WAYLAND_DISPLAY JAVA_TOOL_OPTIONS=-XX:TieredStopAtLevel=1 \
      timeout 60 "$launcher" -l 'memq://' 2>&1)
rc=$?
status=0
if grep -qx "Found $num_types LCM types" <<<"$out"; then
  echo "ok: lcm-spy found $num_types LCM types on the launcher's class path"
else
  echo "FAIL: lcm-spy did not report 'Found $num_types LCM types'"; status=1
fi
if [ "$rc" -ne 124 ] && grep -q "java.awt.HeadlessException" <<<"$out"; then
  echo "ok: lcm-spy got as far as opening its window (exit $rc without a display)"
else
  echo "FAIL: expected a HeadlessException exit, got exit $rc"; status=1
fi
[ "$status" -eq 0 ] || printf '%s\n' "--- lcm-spy output ---" "$out"
exit "$status"
